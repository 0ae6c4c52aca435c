//! On-target: the QSPI flash behaves as NOR flash through embassy-rp's driver, as the gait store and
//! the emulator's stand-in boot ROM assume: erase sets a 4 KB sector to 0xFF and only that sector,
//! programming can only clear bits (0xF0 then 0x0F reads 0x00). Erases and rewrites the last two
//! sectors of the gait store (SCRATCH_SECTOR and the one below): a stored gait there is lost.
#![no_std]
#![no_main]

use hil_on_target as _;

#[cfg(test)]
#[embedded_test::tests]
mod tests {
    use embassy_rp::flash::{Blocking, Flash};
    use embassy_rp::peripherals::FLASH;
    use hil_on_target::{FLASH_SIZE, SCRATCH_SECTOR};

    type Nor = Flash<'static, FLASH, Blocking, FLASH_SIZE>;

    #[init]
    fn init() -> Nor {
        let p = embassy_rp::init(Default::default());
        Flash::new_blocking(p.FLASH)
    }

    fn read_page(flash: &mut Nor, offset: u32) -> [u8; 256] {
        let mut buf = [0u8; 256];
        flash.blocking_read(offset, &mut buf).unwrap();
        buf
    }

    #[test]
    fn program_only_clears_bits(mut flash: Nor) {
        flash.blocking_erase(SCRATCH_SECTOR, SCRATCH_SECTOR + 4096).unwrap();
        assert!(read_page(&mut flash, SCRATCH_SECTOR).iter().all(|&b| b == 0xFF));
        flash.blocking_write(SCRATCH_SECTOR, &[0xF0; 256]).unwrap();
        assert!(read_page(&mut flash, SCRATCH_SECTOR).iter().all(|&b| b == 0xF0));
        flash.blocking_write(SCRATCH_SECTOR, &[0x0F; 256]).unwrap();
        assert!(read_page(&mut flash, SCRATCH_SECTOR).iter().all(|&b| b == 0x00));
    }

    #[test]
    fn erase_stops_at_the_sector_boundary(mut flash: Nor) {
        let below = SCRATCH_SECTOR - 4096;
        flash.blocking_erase(below, SCRATCH_SECTOR).unwrap();
        let pattern: [u8; 256] = core::array::from_fn(|i| i as u8);
        flash.blocking_write(below + 3840, &pattern).unwrap();
        flash.blocking_erase(SCRATCH_SECTOR, SCRATCH_SECTOR + 4096).unwrap();
        assert_eq!(read_page(&mut flash, below + 3840), pattern);
    }
}
