//! The servo checks of the bring-up check: every servo of the model file answering at the bus's
//! rate with the right model number, its firmware, Return Delay Time, Operating Mode, position
//! limits and Hardware Error Status; servos that are silent looked for at the other MX rates;
//! two servos whose models are each other's called swapped; the supply voltage from the servos'
//! Present Input Voltage.

use dynamixel::ServoModel;
use dynamixel::control_table::{self as ct, Field};
use dynamixel::master::{BusError, ReplyFault};
use planner::model::Model;

use super::Item;
use super::servo_bus::ServoBus;

/// The Return Delay Time the board's bus needs: its reply slack (300 us, `firmware/src/rp.rs`)
/// assumes servos answer at once (the factory's 250 = 500 us does not fit).
pub const RETURN_DELAY: u32 = 0;
/// Operating Mode 3, Position Control: the board writes Goal Position.
pub const POSITION_MODE: u32 = 3;
/// MX(2.0) servos speak Protocol 2.0 from firmware version 39 (e-manual).
pub const MIN_FIRMWARE: u8 = 39;
/// The MX(2.0) operating voltage range, V (e-manual: 10 to 14.8 V, 12 V recommended).
pub const SUPPLY_RANGE_V: (f64, f64) = (10.0, 14.8);

/// A servo the model file names.
#[derive(Debug, Clone, PartialEq)]
pub struct Expected {
    pub id: u8,
    pub model: ServoModel,
    /// The joint it drives (`LF_CTr`).
    pub joint: String,
    /// The joint's range as servo positions, lowest first (ticks).
    pub ticks: (i64, i64),
}

/// The servos of `model`, in the model file's joint order.
pub fn expected_servos(model: &Model) -> Vec<Expected> {
    model
        .joints
        .iter()
        .filter_map(|j| {
            let s = j.servo?;
            let c = s.centre_calibration();
            let t = |a: f64| c.goal_of_urad(((a - s.zero_offset) * 1e6).round() as i64);
            let (a, b) = (t(j.limits.0), t(j.limits.1));
            Some(Expected {
                id: s.id,
                model: s.model,
                joint: j.name.clone(),
                ticks: (a.min(b), a.max(b)),
            })
        })
        .collect()
}

/// What one servo answered.
#[derive(Debug, Clone, PartialEq)]
struct Answer {
    model_number: u16,
    firmware: u8,
    /// Its settings and state, or the read that failed.
    registers: Result<Registers, String>,
}

#[derive(Debug, Clone, PartialEq)]
struct Registers {
    return_delay: u32,
    operating_mode: u32,
    min_position: i64,
    max_position: i64,
    hardware_error: u32,
    /// Present Input Voltage, V.
    voltage: f64,
}

fn read_field(bus: &mut dyn ServoBus, id: u8, f: Field) -> Result<u32, String> {
    let mut b = [0u8; 4];
    bus.read(id, f.addr, &mut b[..f.size as usize])
        .map_err(|e| format!("reading {} of ID {id}: {e}", f.name))?;
    Ok(u32::from_le_bytes(b))
}

fn read_registers(bus: &mut dyn ServoBus, id: u8) -> Result<Registers, String> {
    Ok(Registers {
        return_delay: read_field(bus, id, ct::RETURN_DELAY_TIME)?,
        operating_mode: read_field(bus, id, ct::OPERATING_MODE)?,
        min_position: read_field(bus, id, ct::MIN_POSITION_LIMIT)? as i32 as i64,
        max_position: read_field(bus, id, ct::MAX_POSITION_LIMIT)? as i32 as i64,
        hardware_error: read_field(bus, id, ct::HARDWARE_ERROR_STATUS)?,
        voltage: read_field(bus, id, ct::PRESENT_INPUT_VOLTAGE)? as f64 * 0.1,
    })
}

/// What pinging one ID at the bus's rate gave.
#[derive(Debug, Clone, PartialEq)]
enum Heard {
    Answer(Answer),
    Silent,
    Garbled(String),
}

fn listen(bus: &mut dyn ServoBus, id: u8) -> Heard {
    match bus.ping(id) {
        Ok(p) => Heard::Answer(Answer {
            model_number: p.model_number,
            firmware: p.firmware,
            registers: read_registers(bus, id),
        }),
        Err(BusError::Reply {
            fault: ReplyFault::Timeout,
            ..
        }) => Heard::Silent,
        Err(e) => Heard::Garbled(e.to_string()),
    }
}

fn model_words(number: u16) -> String {
    match ServoModel::from_number(number) {
        Some(m) => format!("{} (model number {number})", m.name()),
        None => format!("model number {number}, not an MX this stack knows"),
    }
}

/// `dbot dxl ... -p PORT` or, without a port of its own, a word on how to reach the bus.
fn dxl(bus: &dyn ServoBus, rest: &str) -> String {
    match bus.dxl_port() {
        Some(p) => format!("dbot dxl {rest} -p {p}"),
        None => format!("dbot dxl {rest} -p PORT (a U2D2 on the servo bus)"),
    }
}

/// Checks every servo of `expected` on `bus` (at its rate now), then the supply voltage; the
/// items come in this order: one per servo, then `supply voltage`.
pub fn check_servos(bus: &mut dyn ServoBus, expected: &[Expected]) -> Vec<Item> {
    let baud = bus.baud();
    let heard: Vec<Heard> = expected.iter().map(|e| listen(bus, e.id)).collect();
    // Servos silent at the bus's rate: at which other MX rate do they answer?
    let silent: Vec<u8> = expected
        .iter()
        .zip(&heard)
        .filter(|(_, h)| matches!(h, Heard::Silent))
        .map(|(e, _)| e.id)
        .collect();
    let (elsewhere, elsewhere_searched) = find_elsewhere(bus, &silent, baud);
    let mut items = Vec::new();
    for (i, (e, h)) in expected.iter().zip(&heard).enumerate() {
        let name = format!("servo ID {} ({}, {})", e.id, e.joint, e.model.name());
        let item = match h {
            Heard::Answer(a) => check_answer(bus, e, a, expected, &heard, i),
            Heard::Silent => match elsewhere.iter().find(|(id, _)| *id == e.id) {
                Some(&(_, at)) => Item::fail(
                    &name,
                    format!(
                        "answers at {at} bit/s, not at the bus's {baud} bit/s (wrong baud rate)"
                    ),
                    format!(
                        "set its rate: {}",
                        dxl(
                            bus,
                            &format!("setup --baud {at} --id {} --new-baud {baud}", e.id)
                        )
                    ),
                ),
                None => Item::fail(
                    &name,
                    match &elsewhere_searched {
                        Ok(()) => {
                            format!("missing: no answer at {baud} bit/s nor at any other MX rate")
                        }
                        Err(why) => format!("missing: no answer at {baud} bit/s ({why})"),
                    },
                    format!(
                        "check its cable and power, and that no other servo took its ID; \
                         find what answers: {}",
                        dxl(bus, "scan --baud auto")
                    ),
                ),
            },
            Heard::Garbled(why) => Item::fail(
                &name,
                format!("a garbled answer ({why})"),
                "two servos with this ID answer at once, or the line is noisy: connect the \
                 servos one by one and give each its own ID (dbot dxl setup --new-id)"
                    .to_owned(),
            ),
        };
        items.push(item.named(name));
    }
    items.push(supply(expected, &heard));
    items
}

/// The silent `ids` that answer at another MX rate, and that rate; the bus is back at `baud`.
/// With it, why other rates were not searched (a bus that cannot change its rate).
fn find_elsewhere(
    bus: &mut dyn ServoBus,
    ids: &[u8],
    baud: u32,
) -> (Vec<(u8, u32)>, Result<(), String>) {
    let mut found = Vec::new();
    let mut searched = Ok(());
    if ids.is_empty() {
        return (found, searched);
    }
    for &(_, rate) in ct::BAUD_RATES.iter().filter(|(_, r)| *r != baud) {
        if let Err(why) = bus.set_baud(rate) {
            searched = Err(why);
            continue;
        }
        for &id in ids {
            if !found.iter().any(|(f, _)| *f == id) && bus.ping(id).is_ok() {
                found.push((id, rate));
            }
        }
    }
    // A bus that cannot go back is reported by the next read that fails.
    let _ = bus.set_baud(baud);
    (found, searched)
}

fn check_answer(
    bus: &dyn ServoBus,
    e: &Expected,
    a: &Answer,
    expected: &[Expected],
    heard: &[Heard],
    index: usize,
) -> Item {
    let mut problems = Vec::new();
    let mut fixes = Vec::new();
    if a.model_number != e.model.number() {
        problems.push(format!(
            "answers as {}, the model file has {} (model number {}) here (wrong model)",
            model_words(a.model_number),
            e.model.name(),
            e.model.number()
        ));
        match swapped_with(e, a, expected, heard, index) {
            Some(other) => fixes.push(format!(
                "IDs {} and {other} look swapped (each answers with the other's model): swap \
                 their IDs ({}) or their cables",
                e.id,
                dxl(bus, &format!("setup --id {} --new-id FREE_ID", e.id))
            )),
            None => fixes.push(format!(
                "put an {} on joint {} or correct the model file's servo there",
                e.model.name(),
                e.joint
            )),
        }
    }
    if a.firmware < MIN_FIRMWARE {
        problems.push(format!(
            "firmware {} (Protocol 2.0 on MX needs {MIN_FIRMWARE} or later)",
            a.firmware
        ));
        fixes.push(
            "update its firmware with ROBOTIS's Dynamixel Wizard (one servo alone on the bus)"
                .to_owned(),
        );
    }
    let r = match &a.registers {
        Ok(r) => r,
        Err(why) => {
            problems.push(why.clone());
            fixes.push("check the cable: it answers pings but not reads".to_owned());
            return Item::failed_with(problems, fixes);
        }
    };
    if r.return_delay != RETURN_DELAY {
        problems.push(format!(
            "Return Delay Time {} ({} us; the board's bus needs 0)",
            r.return_delay,
            r.return_delay * ct::RETURN_DELAY_UNIT_US
        ));
        fixes.push(dxl(
            bus,
            &format!(
                "setup --baud {} --id {} --return-delay-us 0",
                bus.baud(),
                e.id
            ),
        ));
    }
    if r.operating_mode != POSITION_MODE {
        problems.push(format!(
            "Operating Mode {} (the board needs 3, Position Control)",
            r.operating_mode
        ));
        fixes.push(dxl(
            bus,
            &format!(
                "write --baud {} --id {} --field \"Operating Mode\" --value 3",
                bus.baud(),
                e.id
            ),
        ));
    }
    if r.min_position > e.ticks.0 || r.max_position < e.ticks.1 {
        problems.push(format!(
            "position limits {}..{} ticks do not hold the joint's range {}..{} ticks",
            r.min_position, r.max_position, e.ticks.0, e.ticks.1
        ));
        fixes.push(format!(
            "widen Min/Max Position Limit ({})",
            dxl(
                bus,
                &format!("write --id {} --field \"Min Position Limit\"", e.id)
            )
        ));
    }
    if r.hardware_error != 0 {
        problems.push(format!(
            "Hardware Error Status {:#04x} (latched: overload, overheating or voltage)",
            r.hardware_error
        ));
        fixes.push(
            "find the cause (a blocked joint, heat, the supply), let it cool, then power-cycle the servos"
                .to_owned(),
        );
    }
    if problems.is_empty() {
        Item::pass(
            "",
            format!(
                "{}, firmware {}, Return Delay 0, Position Control, limits {}..{} ticks hold \
                 the joint's {}..{}, no hardware error, {:.1} V",
                model_words(a.model_number),
                a.firmware,
                r.min_position,
                r.max_position,
                e.ticks.0,
                e.ticks.1,
                r.voltage
            ),
        )
    } else {
        Item::failed_with(problems, fixes)
    }
}

/// The ID whose expected model this servo has while it has this one's (a swap), if any.
fn swapped_with(
    e: &Expected,
    a: &Answer,
    expected: &[Expected],
    heard: &[Heard],
    index: usize,
) -> Option<u8> {
    expected
        .iter()
        .zip(heard)
        .enumerate()
        .find(|(j, (o, h))| {
            *j != index
                && o.model.number() == a.model_number
                && matches!(h, Heard::Answer(b) if b.model_number == e.model.number())
        })
        .map(|(_, (o, _))| o.id)
}

fn supply(expected: &[Expected], heard: &[Heard]) -> Item {
    let volts: Vec<(u8, f64)> = expected
        .iter()
        .zip(heard)
        .filter_map(|(e, h)| match h {
            Heard::Answer(Answer {
                registers: Ok(r), ..
            }) => Some((e.id, r.voltage)),
            _ => None,
        })
        .collect();
    let name = "supply voltage";
    let Some(&(lo_id, lo)) = volts.iter().min_by(|a, b| a.1.total_cmp(&b.1)) else {
        return Item::not_checked(
            name,
            "no servo answered to read its Present Input Voltage".to_owned(),
        );
    };
    let &(hi_id, hi) = volts
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("not empty");
    let (min, max) = SUPPLY_RANGE_V;
    let detail = format!(
        "Present Input Voltage of {} servos: {lo:.1} V (ID {lo_id}) to {hi:.1} V (ID {hi_id})",
        volts.len()
    );
    if lo < min {
        Item::fail(
            name,
            format!("{detail}: below the MX's {min} V"),
            "use a 12 V supply that holds its voltage under load, and check the supply \
             cables and connectors for drop (docs/hardware.md, Supply)"
                .to_owned(),
        )
    } else if hi > max {
        Item::fail(
            name,
            format!("{detail}: above the MX's {max} V"),
            "lower the supply to 12 V".to_owned(),
        )
    } else {
        Item::pass(name, format!("{detail}, within {min}..{max} V"))
    }
}
