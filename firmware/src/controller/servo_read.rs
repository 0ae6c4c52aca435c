//! Servo reads for the host (`ReadServo` / `GetServoRead`, protocol version 9): the bring-up check
//! reads each servo's registers through the board. One read waits at a time; the bus loop does it
//! after a cycle's action when the cycle leaves the time ([`crate::bus_loop`]), so the cycle's rate
//! never pays for it, and hands back its result, which the host collects.

use embedded_storage::nor_flash::NorFlash;
use protocol::{MAX_SERVO_READ, ServoRead, ServoReadResult};

use super::Controller;
use crate::store::FlashWindow;

/// Why a servo read is refused: the ID is not one servo's (0..=252) or the length is more than a
/// reply carries here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ServoReadError {
    Id(u8),
    Len(u8),
}

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// Asks for `read` (a read still waiting is replaced; the last result is dropped).
    pub fn read_servo(&mut self, read: ServoRead) -> Result<(), ServoReadError> {
        if read.id > dynamixel::instruction::MAX_ID {
            return Err(ServoReadError::Id(read.id));
        }
        if usize::from(read.len) > MAX_SERVO_READ {
            return Err(ServoReadError::Len(read.len));
        }
        self.servo_read = Some(read);
        self.servo_read_result = None;
        Ok(())
    }

    /// The bus loop finished `result` (of the read asked last, unless another replaced it since).
    pub fn servo_read_done(&mut self, result: ServoReadResult) {
        if self.servo_read == Some(result.request) {
            self.servo_read = None;
            self.servo_read_result = Some(result);
        }
    }

    /// The last finished read (`None`: pending, or none asked).
    pub fn servo_read_result(&self) -> Option<ServoReadResult> {
        self.servo_read_result.clone()
    }
}
