//! The servo chain side of the emulator's bus link (runner/src/bus.js): the dynamixel crate's
//! [`VirtualChain`] (the one servo model of the project) driven in lock step with simulated time.
//!
//! For every burst the emulated board puts on the bus, the runner sends
//! `{"tx":"<hex>","start_ns":..,"end_ns":..,"baud":..}`; [`ServoBus::burst`] advances the motors to
//! the burst's end, parses the bytes (a packet may span bursts; garbage is skipped as a servo would),
//! lets the chain execute each complete instruction packet and answers with the status packets as
//! timed segments. `{"control":{..}}` lines inject faults ([`ServoBus::control`]): overload, load,
//! silent, corrupt, stuck servos and bus noise.

use anyhow::{Context, Result, bail};
use dynamixel::parser::Parser;
use dynamixel::sim::{Faults, VirtualChain};
use serde_json::{Value, json};

/// One reply on the wire: `delay_ns` after the end of the previous segment (or of the request).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Segment {
    /// Idle time before the first byte, nanoseconds.
    pub delay_ns: u64,
    /// The bytes.
    pub rx: Vec<u8>,
}

/// A virtual servo chain on simulated time.
#[derive(Debug)]
pub struct ServoBus {
    chain: VirtualChain,
    parser: Parser,
    now_ns: Option<u64>,
    /// A servo's own processing time before its Return Delay Time starts, ns.
    turnaround_ns: u64,
    /// Instruction packets executed so far.
    pub packets: u64,
    /// Noise to put on the wire ahead of the next replies (the `noise` control).
    noise: Vec<u8>,
    noise_seed: u32,
}

impl ServoBus {
    /// A bus with this chain; its motors start at the first burst's time. Servos answer at once
    /// when their Return Delay Time is 0; see [`Self::with_turnaround`].
    pub fn new(chain: VirtualChain) -> Self {
        Self {
            chain,
            parser: Parser::default(),
            now_ns: None,
            turnaround_ns: 0,
            packets: 0,
            noise: Vec::new(),
            noise_seed: 0x2545_F491,
        }
    }

    /// Adds a servo's processing time to every reply: a real MX does not answer within one character
    /// time even at Return Delay Time 0 (the firmware's notes cite about 50 us for the MX-64).
    pub fn with_turnaround(mut self, turnaround: std::time::Duration) -> Self {
        self.turnaround_ns = turnaround.as_nanos() as u64;
        self
    }

    /// The chain, for inspection.
    pub fn chain(&self) -> &VirtualChain {
        &self.chain
    }

    /// Handles one burst from the board; returns the replies in wire order.
    pub fn burst(&mut self, tx: &[u8], end_ns: u64, baud: u32) -> Vec<Segment> {
        if let Some(then) = self.now_ns
            && end_ns > then
        {
            self.chain.step((end_ns - then) as f64 * 1e-9);
        }
        self.now_ns = Some(end_ns);
        let mut out = Vec::new();
        let mut rest = tx;
        // Carried-over silence of a servo with the no-reply fault: the next chained reply waits
        // for its slot anyway.
        let mut silent_ns = 0u64;
        while !rest.is_empty() {
            let n = self.parser.feed(rest);
            rest = &rest[n..];
            while let Some(frame) = self.parser.next_frame() {
                let Ok(frame) = frame else { continue };
                if frame.status().is_some() {
                    continue;
                }
                self.packets += 1;
                for reply in self.chain.handle(&frame, baud) {
                    let delay_ns =
                        u64::from(reply.delay_us) * 1000 + self.turnaround_ns + silent_ns;
                    match reply.bytes {
                        Some(rx) => {
                            silent_ns = 0;
                            out.push(Segment { delay_ns, rx });
                        }
                        None => silent_ns = delay_ns,
                    }
                }
            }
            if n == 0 {
                break;
            }
        }
        if !out.is_empty() && !self.noise.is_empty() {
            // The noise collides with the replies: the servos send on time (they do not listen
            // while they talk), and what reaches the board is the noise in place of the first
            // reply bytes of the window. Noise longer than the replies is cut at their end.
            let noise = std::mem::take(&mut self.noise);
            let mut it = noise.into_iter();
            for b in out.iter_mut().flat_map(|s| s.rx.iter_mut()) {
                match it.next() {
                    Some(n) => *b = n,
                    None => break,
                }
            }
        }
        out
    }

    /// Queues noise for the next burst that gets replies: `bytes` pseudo-random bytes, then
    /// `headers` false status headers (`FF FF FD 00`, ID 5, a length of 32 that swallows the
    /// bytes after it). They replace the first reply bytes of that window, timing unchanged (a
    /// collision on the wire). Deterministic: the same controls give the same bytes.
    pub fn queue_noise(&mut self, bytes: usize, headers: usize) {
        for _ in 0..bytes {
            let x = &mut self.noise_seed;
            *x ^= *x << 13;
            *x ^= *x >> 17;
            *x ^= *x << 5;
            self.noise.push(*x as u8);
        }
        for _ in 0..headers {
            self.noise
                .extend_from_slice(&[0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x20, 0x00]);
        }
    }

    fn faults_of<'v>(&mut self, v: &'v Value, what: &str) -> Result<(&mut Faults, &'v Value)> {
        let id = v[0]
            .as_u64()
            .and_then(|id| u8::try_from(id).ok())
            .with_context(|| format!("{what}[0]: servo id 0..=252, got {}", v[0]))?;
        let servo = self.chain.servo_mut(id)?;
        Ok((&mut servo.faults, &v[1]))
    }

    /// Applies a control message: `{"overload": id}`, `{"external_torque": [id, N m]}`,
    /// `{"return_delay": code}`, and the servo faults of the dynamixel crate's sim
    /// ([`dynamixel::sim::Faults`]): `{"silent": [id, bool]}` (executes, never replies),
    /// `{"corrupt": [id, bool]}` (every reply with a bad CRC) or `{"corrupt": [id, n]}` (the next n
    /// replies), `{"stuck": [id, bool]}` (output jammed: position frozen, goals accepted, no error
    /// bit); `{"noise": {"bytes": n, "headers": k}}` ([`Self::queue_noise`]); and the heat knobs
    /// ([`dynamixel::sim::thermal`], ESTIMATE): `{"thermal": [id, K/W, s]}` (thermal resistance
    /// and time constant of one servo: a high resistance makes it heat fast) and
    /// `{"temperature": [id, degC]}` (its winding's temperature now).
    pub fn control(&mut self, msg: &Value) -> Result<()> {
        let flag = |v: &Value, what: &str| {
            v.as_bool()
                .with_context(|| format!("{what}[1]: true or false, got {v}"))
        };
        if let Some(v) = msg.get("silent") {
            let (f, on) = self.faults_of(v, "silent")?;
            f.no_reply = flag(on, "silent")?;
        } else if let Some(v) = msg.get("stuck") {
            let (f, on) = self.faults_of(v, "stuck")?;
            f.stuck = flag(on, "stuck")?;
        } else if let Some(v) = msg.get("corrupt") {
            let (f, arg) = self.faults_of(v, "corrupt")?;
            match (arg.as_bool(), arg.as_u64()) {
                (Some(on), _) => f.corrupt_crc = on,
                (_, Some(n)) => {
                    f.corrupt_next = u32::try_from(n).context("corrupt[1]: too many replies")?
                }
                _ => bail!("corrupt[1]: true, false or a number of replies, got {arg}"),
            }
        } else if let Some(v) = msg.get("noise") {
            let n = |k: &str| {
                v.get(k).map_or(Ok(0), |x| {
                    x.as_u64()
                        .filter(|&n| n <= 4096)
                        .map(|n| n as usize)
                        .with_context(|| format!("noise.{k}: a count up to 4096, got {x}"))
                })
            };
            let (bytes, headers) = (n("bytes")?, n("headers")?);
            if bytes + headers == 0 {
                bail!("noise: give \"bytes\" and/or \"headers\" (counts), got {v}");
            }
            self.queue_noise(bytes, headers);
        } else if let Some(id) = msg.get("overload") {
            let id = id.as_u64().context("overload: servo id")? as u8;
            self.chain.trigger_overload(id)?;
        } else if let Some(v) = msg.get("external_torque") {
            let id = v[0].as_u64().context("external_torque[0]: servo id")? as u8;
            let nm = v[1].as_f64().context("external_torque[1]: N m")?;
            self.chain.set_external_torque(id, nm)?;
        } else if let Some(v) = msg.get("thermal") {
            let id = v[0].as_u64().context("thermal[0]: servo id")? as u8;
            let r = v[1].as_f64().filter(|x| *x > 0.0);
            let tau = v[2].as_f64().filter(|x| *x > 0.0);
            let (Some(r), Some(tau)) = (r, tau) else {
                bail!("thermal: [id, K/W > 0, time constant s > 0], got {v}");
            };
            self.chain.set_thermal(
                id,
                dynamixel::sim::Thermal {
                    r_th_k_per_w: r,
                    tau_s: tau,
                    ..dynamixel::sim::Thermal::MX
                },
            )?;
        } else if let Some(v) = msg.get("temperature") {
            let id = v[0].as_u64().context("temperature[0]: servo id")? as u8;
            let t = v[1].as_f64().context("temperature[1]: degC")?;
            self.chain.servo_mut(id)?.set_temperature_c(t);
        } else if let Some(code) = msg.get("return_delay") {
            self.chain
                .set_return_delay_all(code.as_u64().context("return_delay: code")? as u8);
        } else {
            bail!("unknown servo chain control message {msg}");
        }
        Ok(())
    }

    /// Handles one line of the runner protocol; returns the answer line for a burst.
    pub fn line(&mut self, line: &str) -> Result<Option<String>> {
        let msg: Value = serde_json::from_str(line).with_context(|| format!("not JSON: {line}"))?;
        if let Some(c) = msg.get("control") {
            self.control(c)?;
            return Ok(None);
        }
        let tx = hex_decode(msg["tx"].as_str().context("burst without tx")?)?;
        let end = msg["end_ns"].as_f64().context("burst without end_ns")? as u64;
        let baud = msg["baud"].as_u64().context("burst without baud")? as u32;
        let segments: Vec<Value> = self
            .burst(&tx, end, baud)
            .into_iter()
            .map(|s| json!({"delay_ns": s.delay_ns, "rx": hex_encode(&s.rx)}))
            .collect();
        Ok(Some(json!({ "segments": segments }).to_string()))
    }
}

fn hex_decode(s: &str) -> Result<Vec<u8>> {
    if !s.len().is_multiple_of(2) {
        bail!("odd-length hex string");
    }
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).with_context(|| format!("bad hex at {i}")))
        .collect()
}

fn hex_encode(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}
