//! Instruction codes, the status error byte and broadcast ID of Protocol 2.0.

/// The broadcast ID: every servo executes, none replies (except to Ping, Sync Read, Bulk Read).
pub const BROADCAST_ID: u8 = 0xFE;
/// Highest ID a servo may have.
pub const MAX_ID: u8 = 252;
/// Instruction byte of every status packet.
pub const STATUS: u8 = 0x55;

/// Instruction codes (e-manual, Protocol 2.0 "Instruction").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
#[non_exhaustive]
pub enum Instruction {
    Ping = 0x01,
    Read = 0x02,
    Write = 0x03,
    RegWrite = 0x04,
    Action = 0x05,
    FactoryReset = 0x06,
    Reboot = 0x08,
    Clear = 0x10,
    Backup = 0x20,
    SyncRead = 0x82,
    SyncWrite = 0x83,
    FastSyncRead = 0x8A,
    BulkRead = 0x92,
    BulkWrite = 0x93,
    FastBulkRead = 0x9A,
}

impl Instruction {
    /// The instruction for a code byte, `None` for codes Protocol 2.0 does not define.
    pub fn from_code(code: u8) -> Option<Self> {
        use Instruction::*;
        Some(match code {
            0x01 => Ping,
            0x02 => Read,
            0x03 => Write,
            0x04 => RegWrite,
            0x05 => Action,
            0x06 => FactoryReset,
            0x08 => Reboot,
            0x10 => Clear,
            0x20 => Backup,
            0x82 => SyncRead,
            0x83 => SyncWrite,
            0x8A => FastSyncRead,
            0x92 => BulkRead,
            0x93 => BulkWrite,
            0x9A => FastBulkRead,
            _ => return None,
        })
    }

    /// The instruction's name as the e-manual writes it ("Sync Write").
    pub const fn name(self) -> &'static str {
        match self {
            Instruction::Ping => "Ping",
            Instruction::Read => "Read",
            Instruction::Write => "Write",
            Instruction::RegWrite => "Reg Write",
            Instruction::Action => "Action",
            Instruction::FactoryReset => "Factory Reset",
            Instruction::Reboot => "Reboot",
            Instruction::Clear => "Clear",
            Instruction::Backup => "Control Table Backup",
            Instruction::SyncRead => "Sync Read",
            Instruction::SyncWrite => "Sync Write",
            Instruction::FastSyncRead => "Fast Sync Read",
            Instruction::BulkRead => "Bulk Read",
            Instruction::BulkWrite => "Bulk Write",
            Instruction::FastBulkRead => "Fast Bulk Read",
        }
    }
}

/// The error byte of a status packet: bit 7 is Alert (read Hardware Error Status), bits 0..6 an
/// error number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StatusError(pub u8);

/// The error numbers of bits 0..6 of the status error byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ErrorNumber {
    ResultFail,
    Instruction,
    Crc,
    DataRange,
    DataLength,
    DataLimit,
    Access,
    /// A number the e-manual does not define.
    Other(u8),
}

impl ErrorNumber {
    /// The error's name as the e-manual's status-packet table writes it.
    pub fn name(self) -> &'static str {
        match self {
            ErrorNumber::ResultFail => "Result Fail",
            ErrorNumber::Instruction => "Instruction Error",
            ErrorNumber::Crc => "CRC Error",
            ErrorNumber::DataRange => "Data Range Error",
            ErrorNumber::DataLength => "Data Length Error",
            ErrorNumber::DataLimit => "Data Limit Error",
            ErrorNumber::Access => "Access Error",
            ErrorNumber::Other(_) => "an error number the e-manual does not define",
        }
    }
}

impl StatusError {
    pub const ALERT: u8 = 0x80;
    pub const RESULT_FAIL: u8 = 0x01;
    pub const INSTRUCTION: u8 = 0x02;
    pub const CRC: u8 = 0x03;
    pub const DATA_RANGE: u8 = 0x04;
    pub const DATA_LENGTH: u8 = 0x05;
    pub const DATA_LIMIT: u8 = 0x06;
    pub const ACCESS: u8 = 0x07;

    /// Alert: the servo has a hardware error (overload, overheat, ...); data is still valid.
    pub fn alert(self) -> bool {
        self.0 & Self::ALERT != 0
    }

    /// The error number of bits 0..6, `None` when the instruction succeeded.
    pub fn number(self) -> Option<ErrorNumber> {
        Some(match self.0 & 0x7F {
            0 => return None,
            1 => ErrorNumber::ResultFail,
            2 => ErrorNumber::Instruction,
            3 => ErrorNumber::Crc,
            4 => ErrorNumber::DataRange,
            5 => ErrorNumber::DataLength,
            6 => ErrorNumber::DataLimit,
            7 => ErrorNumber::Access,
            n => ErrorNumber::Other(n),
        })
    }
}
