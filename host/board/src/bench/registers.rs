//! Reading and writing one register of one servo, by e-manual field name (spaces or underscores,
//! `dynamixel::control_table` owns the fields) or by address and length.

use super::{Bench, BenchError};
use crate::bus::serial::block_on;
use dynamixel::control_table::{self as ct, Field};

/// Which register: a control table field by name, or raw bytes at an address.
#[derive(Debug, Clone, Copy)]
pub enum Target<'a> {
    Field(&'a str),
    Addr { addr: u16, len: u16 },
}

impl Target<'_> {
    /// The field `name` names, or a raw register of `len` (1..=147) bytes at `addr`.
    pub fn resolve(self) -> Result<Field, BenchError> {
        match self {
            Target::Field(name) => ct::field_by_name(name).ok_or_else(|| {
                let names: Vec<&str> = ct::FIELDS.iter().map(|f| f.name).collect();
                BenchError::UnknownField {
                    name: name.to_owned(),
                    known: names.join(", "),
                }
            }),
            Target::Addr { addr, len } if (1..=147).contains(&len) => Ok(Field {
                name: "register",
                addr,
                size: len as u8,
                eeprom: addr < 64,
                writable: true,
            }),
            Target::Addr { len, .. } => Err(BenchError::BadLength { len }),
        }
    }
}

/// The bytes read from one register.
#[derive(Debug, Clone, PartialEq)]
pub struct Reading {
    pub id: u8,
    pub field: Field,
    /// Little endian, `field.size` bytes.
    pub bytes: Vec<u8>,
    /// The servo's alert bit: a hardware error is latched (read Hardware Error Status).
    pub alert: bool,
}

impl Reading {
    /// The value as unsigned (1, 2 or 4 bytes; none for other lengths).
    pub fn unsigned(&self) -> Option<u64> {
        let b = &self.bytes;
        match b.len() {
            1 => Some(b[0].into()),
            2 => Some(u16::from_le_bytes([b[0], b[1]]).into()),
            4 => Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]).into()),
            _ => None,
        }
    }

    /// The value as two's complement signed (1, 2 or 4 bytes; none for other lengths).
    pub fn signed(&self) -> Option<i64> {
        let b = &self.bytes;
        match b.len() {
            1 => Some((b[0] as i8).into()),
            2 => Some(i16::from_le_bytes([b[0], b[1]]).into()),
            4 => Some(i32::from_le_bytes([b[0], b[1], b[2], b[3]]).into()),
            _ => None,
        }
    }
}

/// One register written.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    pub id: u8,
    pub field: Field,
    pub value: i64,
    pub alert: bool,
}

/// `v` as `size` little endian bytes (signed values as two's complement).
pub fn encode_value(v: i64, field: &Field) -> Result<Vec<u8>, BenchError> {
    let size = field.size;
    let (min, max) = match size {
        1 => (i8::MIN as i64, u8::MAX as i64),
        2 => (i16::MIN as i64, u16::MAX as i64),
        4 => (i32::MIN as i64, u32::MAX as i64),
        _ => {
            return Err(BenchError::WriteSize {
                field: field.name.to_owned(),
                size,
            });
        }
    };
    if v < min || v > max {
        return Err(BenchError::ValueRange {
            field: field.name.to_owned(),
            value: v,
            size,
            min,
            max,
        });
    }
    Ok(v.to_le_bytes()[..size as usize].to_vec())
}

impl Bench {
    /// Reads `target` of servo `id`.
    pub fn read(&mut self, id: u8, target: Target<'_>) -> Result<Reading, BenchError> {
        let field = target.resolve()?;
        let mut bytes = vec![0u8; field.size as usize];
        let port = self.port.clone();
        let st = block_on(self.master(id)?.read(id, field.addr, &mut bytes)).map_err(|source| {
            BenchError::Bus {
                port,
                id,
                what: format!("reading {}", field.name),
                source,
            }
        })?;
        Ok(Reading {
            id,
            field,
            bytes,
            alert: st.alert(),
        })
    }

    /// Writes `value` (1, 2 or 4 bytes) to `target` of servo `id` (254 = broadcast).
    pub fn write(&mut self, id: u8, target: Target<'_>, value: i64) -> Result<Written, BenchError> {
        let field = target.resolve()?;
        let bytes = encode_value(value, &field)?;
        let port = self.port.clone();
        let st = block_on(self.master(id)?.write(id, field.addr, &bytes)).map_err(|source| {
            BenchError::Bus {
                port,
                id,
                what: format!("writing {}", field.name),
                source,
            }
        })?;
        Ok(Written {
            id,
            field,
            value,
            alert: st.alert(),
        })
    }
}
