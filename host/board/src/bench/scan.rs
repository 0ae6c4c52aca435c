//! Finding servos: ping IDs 0..=max_id at the bench's rate, or with `auto` at each MX(2.0) rate
//! until servos answer.

use super::{BaudChoice, Bench, BenchError, rates};
use crate::bus::serial::{SerialMaster, block_on};
use dynamixel::ServoModel;
use dynamixel::master::{BusError, ReplyFault};

/// A servo that answered a ping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Found {
    pub id: u8,
    pub model_number: u16,
    /// The model the number is (none for servos this stack does not know).
    pub model: Option<ServoModel>,
    pub firmware: u8,
    /// The servo's alert bit: a hardware error is latched.
    pub alert: bool,
}

/// What one ping of a scan gave, reported as the scan goes.
#[derive(Debug)]
pub enum Pinged<'a> {
    /// The scan starts pinging at this rate.
    Rate {
        baud: u32,
        ids: u16,
    },
    Found(&'a Found),
    /// Something answered `id`, but not with a good reply.
    Bad {
        id: u8,
        error: &'a BusError,
    },
    /// Nothing answered `id` in time.
    Silent {
        id: u8,
    },
}

/// The servos a scan found, and the rate they answer at.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Scan {
    pub baud: u32,
    pub found: Vec<Found>,
}

impl Bench {
    /// Pings IDs 0..=max_id at the bench's rate, or with `auto` at each MX rate until servos
    /// answer (the bench then stays at that rate). Nothing answering is an error that says which
    /// rates to try next. `on` hears of each ping as it is answered.
    pub fn scan(&mut self, max_id: u8, mut on: impl FnMut(Pinged<'_>)) -> Result<Scan, BenchError> {
        let tried = match (&self.open, self.choice) {
            (Some((b, _)), _) => vec![*b],
            (None, c) => c.candidates(),
        };
        for &baud in &tried {
            // The port is opened exclusively: the one at another rate closes first.
            let mut m = match self.open.take() {
                Some((b, m)) if b == baud => m,
                other => {
                    drop(other);
                    self.open_at(baud)?
                }
            };
            let found = scan_at(&mut m, max_id, baud, &mut on);
            self.open = Some((baud, m));
            if !found.is_empty() {
                return Ok(Scan { baud, found });
            }
        }
        let others: Vec<u32> = BaudChoice::Auto
            .candidates()
            .into_iter()
            .filter(|b| !tried.contains(b))
            .collect();
        let port = self.port.clone();
        Err(match others.first() {
            None => BenchError::NoneAtAnyRate {
                port,
                rates: rates::list(&tried),
            },
            Some(&next) => BenchError::NoneAtRate {
                port,
                rates: rates::list(&tried),
                next,
            },
        })
    }
}

/// Pings IDs 0..=max_id at one rate; returns the servos that answered.
fn scan_at(
    m: &mut SerialMaster,
    max_id: u8,
    baud: u32,
    on: &mut impl FnMut(Pinged<'_>),
) -> Vec<Found> {
    on(Pinged::Rate {
        baud,
        ids: u16::from(max_id) + 1,
    });
    let mut found = Vec::new();
    for id in 0..=max_id {
        match block_on(m.ping(id)) {
            Ok(p) => {
                let f = Found {
                    id,
                    model_number: p.model_number,
                    model: ServoModel::from_number(p.model_number),
                    firmware: p.firmware,
                    alert: p.error.alert(),
                };
                on(Pinged::Found(&f));
                found.push(f);
            }
            Err(BusError::Reply {
                fault: ReplyFault::Timeout,
                ..
            }) => on(Pinged::Silent { id }),
            Err(e) => on(Pinged::Bad { id, error: &e }),
        }
    }
    found
}
