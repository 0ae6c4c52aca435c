//! An in-memory NOR flash for host tests and the host's in-process virtual robot: behaves like the
//! board's QSPI flash (erase sets a 4 KB sector to 0xFF, programming can only clear bits, writes come in
//! units of `W` bytes) and can lose power after any number of programmed bytes or erased sectors.

use std::vec;
use std::vec::Vec;

use embedded_storage::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

use super::FlashWindow;

/// Erase unit of the double, the same as the RP2040's W25Q16 sector.
pub const SECTOR: usize = 4096;

/// Why the double refused an operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NorDoubleError {
    /// The range runs past the end of the flash.
    OutOfBounds { offset: u32, len: usize },
    /// Offset or length is not a multiple of the write or erase unit.
    NotAligned { offset: u32, len: usize },
    /// Programming would have to set a bit that is 0: real NOR needs an erase first.
    SetsBits { offset: u32, have: u8, want: u8 },
    /// The simulated power loss happened; nothing works until [`NorDouble::power_cycle`].
    PowerLost,
}

impl NorFlashError for NorDoubleError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            Self::OutOfBounds { .. } => NorFlashErrorKind::OutOfBounds,
            Self::NotAligned { .. } => NorFlashErrorKind::NotAligned,
            Self::SetsBits { .. } | Self::PowerLost => NorFlashErrorKind::Other,
        }
    }
}

/// NOR flash in RAM with write unit `W` bytes. Every programmed byte and every erased sector is one
/// "tick" of wear; [`NorDouble::lose_power_after`] cuts the power after a given number of ticks, leaving
/// the byte or sector in flight half done, as a brown-out would.
#[derive(Debug, Clone)]
pub struct NorDouble<const W: usize = 4> {
    mem: Vec<u8>,
    /// Ticks left before the power fails (`None`: never).
    budget: Option<u64>,
    dead: bool,
    /// Programmed bytes plus erased sectors since creation (the power-loss test iterates over these).
    pub ticks: u64,
}

impl<const W: usize> NorDouble<W> {
    /// A fresh, fully erased flash of `sectors` 4 KB sectors.
    pub fn new(sectors: usize) -> Self {
        Self {
            mem: vec![0xFF; sectors * SECTOR],
            budget: None,
            dead: false,
            ticks: 0,
        }
    }

    /// The power fails after `ticks` more programmed bytes or erased sectors.
    pub fn lose_power_after(&mut self, ticks: u64) {
        self.budget = Some(ticks);
    }

    /// Power comes back: the contents stay as they were when it failed.
    pub fn power_cycle(&mut self) {
        self.budget = None;
        self.dead = false;
    }

    /// Whether the simulated power loss has happened.
    pub fn is_dead(&self) -> bool {
        self.dead
    }

    /// Takes one tick of the budget; false when the power fails on this tick.
    fn spend(&mut self) -> bool {
        if let Some(b) = self.budget.as_mut() {
            if *b == 0 {
                self.dead = true;
                return false;
            }
            *b -= 1;
        }
        self.ticks += 1;
        true
    }

    fn check(&self, offset: u32, len: usize, unit: usize) -> Result<(), NorDoubleError> {
        if self.dead {
            return Err(NorDoubleError::PowerLost);
        }
        let end = offset as usize + len;
        if end > self.mem.len() {
            return Err(NorDoubleError::OutOfBounds { offset, len });
        }
        if !(offset as usize).is_multiple_of(unit) || !len.is_multiple_of(unit) {
            return Err(NorDoubleError::NotAligned { offset, len });
        }
        Ok(())
    }
}

impl<const W: usize> ErrorType for NorDouble<W> {
    type Error = NorDoubleError;
}

impl<const W: usize> ReadNorFlash for NorDouble<W> {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        self.check(offset, bytes.len(), 1)?;
        let at = offset as usize;
        bytes.copy_from_slice(&self.mem[at..at + bytes.len()]);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.mem.len()
    }
}

impl<const W: usize> NorFlash for NorDouble<W> {
    const WRITE_SIZE: usize = W;
    const ERASE_SIZE: usize = SECTOR;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        let len = to.checked_sub(from).ok_or(NorDoubleError::OutOfBounds {
            offset: from,
            len: 0,
        })? as usize;
        self.check(from, len, SECTOR)?;
        for sector in (from as usize..to as usize).step_by(SECTOR) {
            if !self.spend() {
                // A brown-out mid-erase leaves the sector partly erased: first half 0xFF, the rest
                // as it was.
                self.mem[sector..sector + SECTOR / 2].fill(0xFF);
                return Err(NorDoubleError::PowerLost);
            }
            self.mem[sector..sector + SECTOR].fill(0xFF);
        }
        Ok(())
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        self.check(offset, bytes.len(), W)?;
        let at = offset as usize;
        // Real NOR refuses nothing, but a set bit that stays 0 is always a driver bug: fail loudly
        // before touching anything.
        for (i, (&have, &want)) in self.mem[at..].iter().zip(bytes).enumerate() {
            if want & !have != 0 {
                return Err(NorDoubleError::SetsBits {
                    offset: offset + i as u32,
                    have,
                    want,
                });
            }
        }
        for (i, &want) in bytes.iter().enumerate() {
            if !self.spend() {
                // The byte in flight is half programmed: only its high nibble reached the cells.
                self.mem[at + i] &= want | 0x0F;
                return Err(NorDoubleError::PowerLost);
            }
            self.mem[at + i] &= want;
        }
        Ok(())
    }
}

impl<const W: usize> FlashWindow for NorDouble<W> {
    fn window(&self) -> &[u8] {
        &self.mem
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erase_sets_ff_and_programming_only_clears_bits() {
        let mut f = NorDouble::<4>::new(2);
        f.write(0, &[0x0F, 0xF0, 0x00, 0xAA]).unwrap();
        assert_eq!(&f.window()[..4], &[0x0F, 0xF0, 0x00, 0xAA]);
        // Clearing more bits is fine (0xAA & 0x0A), setting one is refused and changes nothing.
        f.write(0, &[0x0F, 0xF0, 0x00, 0x0A]).unwrap();
        assert_eq!(
            f.write(0, &[0x1F, 0xF0, 0x00, 0x0A]),
            Err(NorDoubleError::SetsBits {
                offset: 0,
                have: 0x0F,
                want: 0x1F
            })
        );
        assert_eq!(&f.window()[..4], &[0x0F, 0xF0, 0x00, 0x0A]);
        f.erase(0, 4096).unwrap();
        assert!(f.window()[..4096].iter().all(|&b| b == 0xFF));
    }

    #[test]
    fn alignment_and_bounds_are_enforced() {
        let mut f = NorDouble::<4>::new(1);
        assert!(matches!(
            f.write(2, &[0; 4]),
            Err(NorDoubleError::NotAligned { .. })
        ));
        assert!(matches!(
            f.write(0, &[0; 3]),
            Err(NorDoubleError::NotAligned { .. })
        ));
        assert!(matches!(
            f.write(4096, &[0; 4]),
            Err(NorDoubleError::OutOfBounds { .. })
        ));
        assert!(matches!(
            f.erase(0, 100),
            Err(NorDoubleError::NotAligned { .. })
        ));
    }

    #[test]
    fn power_loss_tears_the_write_in_flight_and_stops_everything() {
        let mut f = NorDouble::<4>::new(1);
        f.lose_power_after(5);
        assert_eq!(f.write(0, &[0; 8]), Err(NorDoubleError::PowerLost));
        // Five bytes programmed, the sixth half (high nibble cleared), the rest untouched.
        assert_eq!(&f.window()[..8], &[0, 0, 0, 0, 0, 0x0F, 0xFF, 0xFF]);
        assert_eq!(f.erase(0, 4096), Err(NorDoubleError::PowerLost));
        f.power_cycle();
        f.erase(0, 4096).unwrap();
        assert_eq!(f.window()[5], 0xFF);
    }

    #[test]
    fn power_loss_mid_erase_leaves_a_partly_erased_sector() {
        let mut f = NorDouble::<4>::new(2);
        f.write(0, &[0; 4]).unwrap();
        f.write(4092, &[0; 4]).unwrap();
        f.lose_power_after(0);
        assert_eq!(f.erase(0, 8192), Err(NorDoubleError::PowerLost));
        assert_eq!(f.window()[0], 0xFF);
        assert_eq!(f.window()[4095], 0x00);
    }
}
