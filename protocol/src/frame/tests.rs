//! Checks of the frame encoder against the byte-at-a-time encoder it replaced (kept here as the
//! reference) and of the accumulator's chunk entry point against its per-byte one.

use crc::{CRC_32_ISO_HDLC, Crc};
use serde::Serialize;
use serde::ser::SerializeTuple;

use super::{FrameAccumulator, FrameError, encode_frame};
use crate::MAX_MESSAGE_LEN;

/// The encoder `encode_frame` replaced, kept as the reference: a postcard flavor that COBS-encodes
/// one byte at a time and keeps a bytewise running CRC of the raw bytes.
struct CobsCrcWriter<'b> {
    out: &'b mut [u8],
    /// Index of the code byte of the block being written.
    code_at: usize,
    /// Next free index.
    pos: usize,
    raw_len: usize,
    crc: crc::Digest<'static, u32>,
}

static BYTEWISE: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

impl<'b> CobsCrcWriter<'b> {
    fn new(out: &'b mut [u8]) -> Result<Self, FrameError> {
        if out.is_empty() {
            return Err(FrameError::BufferTooSmall);
        }
        Ok(Self {
            out,
            code_at: 0,
            pos: 1,
            raw_len: 0,
            crc: BYTEWISE.digest(),
        })
    }

    fn close_block(&mut self) -> Result<(), FrameError> {
        let code = self.pos - self.code_at;
        self.out[self.code_at] = code as u8;
        self.code_at = self.pos;
        *self
            .out
            .get_mut(self.pos)
            .ok_or(FrameError::BufferTooSmall)? = 0;
        self.pos += 1;
        Ok(())
    }

    fn push_cobs(&mut self, byte: u8) -> Result<(), FrameError> {
        if byte == 0 {
            return self.close_block();
        }
        *self
            .out
            .get_mut(self.pos)
            .ok_or(FrameError::BufferTooSmall)? = byte;
        self.pos += 1;
        if self.pos - self.code_at == 0xFF {
            self.close_block()?;
        }
        Ok(())
    }

    /// Appends the CRC, closes the last block and the frame; returns the frame length.
    fn finish(mut self) -> Result<usize, FrameError> {
        let crc = self.crc.clone().finalize();
        for b in crc.to_le_bytes() {
            self.push_cobs(b)?;
        }
        let code = self.pos - self.code_at;
        self.out[self.code_at] = code as u8;
        *self
            .out
            .get_mut(self.pos)
            .ok_or(FrameError::BufferTooSmall)? = 0;
        Ok(self.pos + 1)
    }
}

impl postcard::ser_flavors::Flavor for CobsCrcWriter<'_> {
    type Output = usize;

    fn try_push(&mut self, data: u8) -> postcard::Result<()> {
        self.raw_len += 1;
        if self.raw_len > MAX_MESSAGE_LEN {
            return Err(postcard::Error::SerializeBufferFull);
        }
        self.crc.update(&[data]);
        self.push_cobs(data)
            .map_err(|_| postcard::Error::SerializeBufferFull)
    }

    fn finalize(self) -> postcard::Result<usize> {
        self.finish()
            .map_err(|_| postcard::Error::SerializeBufferFull)
    }
}

/// Encodes `message` with the reference encoder.
fn reference_frame<'b, T: Serialize + ?Sized>(
    message: &T,
    buf: &'b mut [u8],
) -> Result<&'b [u8], FrameError> {
    let writer = CobsCrcWriter::new(&mut *buf)?;
    let len =
        postcard::serialize_with_flavor(message, writer).map_err(|_| FrameError::BufferTooSmall)?;
    Ok(&buf[..len])
}

/// Raw bytes as a message: postcard writes a tuple of `u8` as the bytes themselves (no length).
struct Raw<'a>(&'a [u8]);

impl Serialize for Raw<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple(self.0.len())?;
        for b in self.0 {
            t.serialize_element(b)?;
        }
        t.end()
    }
}

/// Deterministic bytes (a linear congruential generator's high bits).
struct Lcg(u64);

impl Lcg {
    fn byte(&mut self) -> u8 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 56) as u8
    }

    /// A byte that is zero about once in `one_in` (never with 0).
    fn byte_with_zeros(&mut self, one_in: u8) -> u8 {
        let b = self.byte();
        if one_in != 0 && self.byte().is_multiple_of(one_in) {
            0
        } else {
            b.max(1)
        }
    }
}

const BUF: usize = MAX_MESSAGE_LEN + 64;

/// `encode_frame` and the reference give the same frame, or the same error, for `payload` in a
/// buffer of `buf_len` bytes.
fn same_frame(payload: &[u8], buf_len: usize) {
    let mut fast = [0xAAu8; BUF];
    let mut slow = [0x55u8; BUF];
    let a = encode_frame(&Raw(payload), &mut fast[..buf_len]);
    let b = reference_frame(&Raw(payload), &mut slow[..buf_len]);
    assert_eq!(
        a,
        b,
        "payload of {} bytes in a buffer of {buf_len}",
        payload.len()
    );
}

fn same_frame_in_a_large_buffer(payload: &[u8]) {
    same_frame(payload, BUF);
}

#[test]
fn encoder_equals_the_reference_at_every_length() {
    let mut rng = Lcg(1);
    let mut p = [0u8; MAX_MESSAGE_LEN + 20];
    for one_in in [0, 2, 8, 64, 255] {
        for len in 0..p.len() {
            for b in &mut p[..len] {
                *b = rng.byte_with_zeros(one_in);
            }
            same_frame_in_a_large_buffer(&p[..len]);
        }
    }
    for fill in [0u8, 1, 0xFF] {
        for len in 0..p.len() {
            same_frame_in_a_large_buffer(&[fill; MAX_MESSAGE_LEN + 20][..len]);
        }
    }
}

#[test]
fn encoder_equals_the_reference_with_a_zero_at_every_position() {
    let mut rng = Lcg(2);
    let mut p = [0u8; 600];
    for b in &mut p {
        *b = rng.byte_with_zeros(0);
    }
    for len in [1, 2, 253, 254, 255, 256, 300, 508, 509, 510, 600] {
        for at in 0..len {
            let mut q = p;
            q[at] = 0;
            same_frame_in_a_large_buffer(&q[..len]);
            // ... and a second zero further on.
            for gap in [1, 2, 253, 254, 255] {
                if at + gap < len {
                    let mut r = q;
                    r[at + gap] = 0;
                    same_frame_in_a_large_buffer(&r[..len]);
                }
            }
        }
    }
}

#[test]
fn encoder_equals_the_reference_around_the_block_boundary() {
    // Non-zero runs of 250..=260 and 505..=512 bytes (a full COBS block is 254 data bytes), after
    // `lead` other bytes, followed by a zero or not, then `tail` more bytes.
    let mut rng = Lcg(3);
    let mut p = [0u8; MAX_MESSAGE_LEN];
    for run in (250..=260).chain(505..=512) {
        for lead in [0, 1, 2, 5, 100] {
            for zero_after in [false, true] {
                for tail in [0, 1, 3, 4, 5, 60] {
                    let mut n = 0;
                    for _ in 0..lead {
                        p[n] = rng.byte_with_zeros(4);
                        n += 1;
                    }
                    for _ in 0..run {
                        p[n] = rng.byte_with_zeros(0);
                        n += 1;
                    }
                    if zero_after {
                        p[n] = 0;
                        n += 1;
                    }
                    for _ in 0..tail {
                        if n < p.len() {
                            p[n] = rng.byte_with_zeros(0);
                            n += 1;
                        }
                    }
                    same_frame_in_a_large_buffer(&p[..n]);
                }
            }
        }
    }
}

#[test]
fn encoder_equals_the_reference_in_every_buffer_size() {
    // Every buffer size from empty to past the frame: the same frame or the same error.
    let mut rng = Lcg(4);
    let mut p = [0u8; MAX_MESSAGE_LEN + 2];
    for (len, one_in) in [
        (0, 0),
        (1, 0),
        (10, 3),
        (249, 0),
        (250, 0),
        (251, 0),
        (254, 0),
        (300, 0),
        (300, 9),
        (508, 0),
        (600, 0),
        (MAX_MESSAGE_LEN, 0),
        (MAX_MESSAGE_LEN, 5),
        (MAX_MESSAGE_LEN + 1, 0),
    ] {
        for b in &mut p[..len] {
            *b = rng.byte_with_zeros(one_in);
        }
        for buf_len in 0..BUF {
            same_frame(&p[..len], buf_len);
        }
    }
}

#[test]
fn encoder_equals_the_reference_when_the_crc_has_zero_bytes() {
    // Payloads whose CRC has a zero byte in each of its four places (and one with two).
    let mut found = [false; 4];
    let mut p = [0u8; 12];
    let mut rng = Lcg(5);
    let mut tries = 0u32;
    while found.iter().any(|f| !f) {
        tries += 1;
        assert!(tries < 1_000_000, "no CRC with a zero byte found");
        for b in &mut p {
            *b = rng.byte_with_zeros(6);
        }
        let crc = BYTEWISE.checksum(&p).to_le_bytes();
        let mut any = false;
        for (i, &c) in crc.iter().enumerate() {
            if c == 0 {
                found[i] = true;
                any = true;
            }
        }
        if any {
            for buf_len in 0..40 {
                same_frame(&p, buf_len);
            }
        }
    }
}

#[test]
fn encoder_equals_the_reference_for_messages() {
    use crate::{
        BusStats, DeviceMessage, HostMessage, JointFeedback, JointSetpoint, Proprioception,
        Setpoint,
    };
    let mut rng = Lcg(6);
    for _ in 0..200 {
        let mut i16_ = || i16::from_le_bytes([rng.byte(), rng.byte()]);
        let mut joints = heapless::Vec::new();
        let mut setpoints = heapless::Vec::new();
        for _ in 0..22 {
            let _ = joints.push(JointFeedback {
                commanded: i16_(),
                present: i16_(),
                velocity: i16_(),
                load: i16_(),
                error: 0,
                flags: 4,
            });
            let _ = setpoints.push(JointSetpoint {
                angle: i16_(),
                torque: Some(i16_()),
            });
        }
        let p = DeviceMessage::Proprioception(Proprioception {
            time_us: u64::from(i16_() as u16) << 20,
            cycle: 7,
            setpoint_seq: 0,
            setpoint_age: 1,
            joints,
            bus: BusStats::default(),
        });
        let s = HostMessage::Setpoint(Setpoint {
            seq: 3,
            joints: setpoints,
        });
        let (mut a, mut b) = ([0u8; BUF], [0u8; BUF]);
        assert_eq!(encode_frame(&p, &mut a), reference_frame(&p, &mut b));
        assert_eq!(encode_frame(&s, &mut a), reference_frame(&s, &mut b));
    }
}

/// What an accumulator made of a frame, in a form that can be compared without allocating.
#[derive(Debug, PartialEq)]
enum Outcome {
    /// The frame's length and an FNV-1a hash of its bytes (not a CRC: every good frame has the
    /// same CRC residue).
    Frame {
        len: usize,
        hash: u64,
    },
    Error(FrameError),
}

impl Outcome {
    fn of(frame: Result<&[u8], FrameError>) -> Self {
        match frame {
            Ok(f) => Self::Frame {
                len: f.len(),
                hash: f.iter().fold(0xCBF2_9CE4_8422_2325, |h, &b| {
                    (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3)
                }),
            },
            Err(e) => Self::Error(e),
        }
    }
}

type Outcomes = heapless::Vec<Outcome, 64>;

fn bytewise(stream: &[u8]) -> (Outcomes, FrameAccumulator) {
    let mut acc = FrameAccumulator::new();
    let mut out = Outcomes::new();
    for &b in stream {
        if let Some(f) = acc.push(b) {
            out.push(Outcome::of(f)).unwrap();
        }
    }
    (out, acc)
}

/// Feeds `stream` to `push_slice` in the pieces that `cuts` (ascending) make.
fn chunked(stream: &[u8], cuts: &[usize]) -> (Outcomes, FrameAccumulator) {
    let mut acc = FrameAccumulator::new();
    let mut out = Outcomes::new();
    let mut from = 0;
    for &to in cuts.iter().chain(core::iter::once(&stream.len())) {
        let mut input = &stream[from..to];
        while let Some(f) = acc.push_slice(&mut input) {
            out.push(Outcome::of(f)).unwrap();
        }
        assert!(input.is_empty());
        from = to;
    }
    (out, acc)
}

/// Same outcomes, and the same state after the stream (checked by what a further frame makes).
fn same_outcomes(stream: &[u8], cuts: &[usize]) {
    let (want, mut acc_a) = bytewise(stream);
    let (got, mut acc_b) = chunked(stream, cuts);
    assert_eq!(
        got,
        want,
        "stream of {} bytes cut at {cuts:?}",
        stream.len()
    );
    let mut buf = [0u8; BUF];
    let after = encode_frame(&Raw(&[1, 0, 2]), &mut buf).unwrap();
    let a = after.iter().find_map(|&b| acc_a.push(b).map(Outcome::of));
    let mut input = after;
    let b = acc_b.push_slice(&mut input).map(Outcome::of);
    assert_eq!(b, a, "frame after the stream cut at {cuts:?}");
}

/// A stream of good and bad frames: every kind of error the accumulator reports.
fn stream(out: &mut [u8]) -> usize {
    let mut n = 0;
    let mut put = |bytes: &[u8]| {
        out[n..n + bytes.len()].copy_from_slice(bytes);
        n += bytes.len();
    };
    let mut buf = [0u8; BUF];
    let mut rng = Lcg(7);
    let mut p = [0u8; 300];
    for b in &mut p {
        *b = rng.byte_with_zeros(7);
    }
    // Empty frames and a good frame.
    put(&[0, 0]);
    put(encode_frame(&Raw(&p[..40]), &mut buf).unwrap());
    // A frame with a block of 254 data bytes.
    let mut long = [1u8; 270];
    long[260] = 0;
    put(encode_frame(&Raw(&long), &mut buf).unwrap());
    // Bad CRC: a data byte changed (a non-zero byte to another non-zero byte).
    let f = encode_frame(&Raw(&p[..60]), &mut buf).unwrap();
    let len = f.len();
    let i = (1..len - 1).find(|&i| f[i] > 1).unwrap();
    buf[i] ^= 0x01;
    if buf[i] == 0 {
        buf[i] = 0x03;
    }
    put(&buf[..len]);
    // Bad COBS: the last block's code points past the delimiter.
    let f = encode_frame(&Raw(&p[100..130]), &mut buf).unwrap();
    let len = f.len();
    let last_code = {
        let mut at = 0;
        while at + usize::from(buf[at]) < len - 1 {
            at += usize::from(buf[at]);
        }
        at
    };
    buf[last_code] = buf[last_code].saturating_add(5);
    put(&buf[..len]);
    // Shorter than a CRC (the accumulator passes it on; `decode_message` refuses it).
    put(&[3, 7, 7, 0]);
    // Too long: more data than a frame can hold.
    for _ in 0..3 {
        put(&[0xFF]);
        put(&[0x5A; 254]);
    }
    put(&[0]);
    // Broken COBS: the frame ends in the middle of a block.
    put(&[0xFF]);
    put(&[0x11; 254]);
    put(&[0xFF]);
    put(&[0x22; 254]);
    put(&[0x80]);
    put(&[0x33; 100]);
    put(&[0]);
    // Garbage, then a good frame.
    put(&[0xC3, 0x01, 0x01, 0x09, 0x44]);
    put(encode_frame(&Raw(&p[200..300]), &mut buf).unwrap());
    // A truncated frame left open at the end.
    let f = encode_frame(&Raw(&p[..80]), &mut buf).unwrap();
    let len = f.len();
    put(&buf[..len / 2]);
    n
}

#[test]
fn slice_accumulator_equals_the_per_byte_one_at_every_split() {
    let mut s = [0u8; 4096];
    let n = stream(&mut s);
    let s = &s[..n];
    // The stream holds every outcome.
    let (want, _) = bytewise(s);
    for e in [FrameError::TooLong, FrameError::Cobs] {
        assert!(want.contains(&Outcome::Error(e)), "{e:?} in {want:?}");
    }
    assert!(
        want.iter()
            .any(|o| matches!(o, Outcome::Frame { len, .. } if *len < 4))
    );
    same_outcomes(s, &[]);
    for cut in 0..=n {
        same_outcomes(s, &[cut]);
    }
    for first in (0..=n).step_by(7) {
        for second in (first..=n).step_by(13) {
            same_outcomes(s, &[first, second]);
        }
    }
    for chunk in [1, 2, 3, 4, 5, 16, 63, 64, 255, 256, 1000] {
        let cuts: heapless::Vec<usize, 4096> = (chunk..n).step_by(chunk).collect();
        same_outcomes(s, &cuts);
    }
}

#[test]
fn slice_accumulator_reports_the_crc_of_a_bad_frame_as_the_per_byte_one() {
    // Every single-byte corruption of a frame (each non-delimiter byte set to each of a few
    // values), fed whole and cut in two everywhere.
    let mut buf = [0u8; BUF];
    let mut rng = Lcg(8);
    let mut p = [0u8; 40];
    for b in &mut p {
        *b = rng.byte_with_zeros(5);
    }
    let len = encode_frame(&Raw(&p), &mut buf).unwrap().len();
    for at in 0..len - 1 {
        for value in [0u8, 1, 2, 0x7F, 0xFE, 0xFF] {
            let mut f = [0u8; BUF];
            f[..len].copy_from_slice(&buf[..len]);
            f[at] = value;
            let frame = &f[..len];
            for cut in 0..=len {
                same_outcomes(frame, &[cut]);
            }
        }
    }
}
