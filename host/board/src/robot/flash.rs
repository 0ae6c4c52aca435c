//! The virtual board's gait store: the NOR flash double and its size, the board's own (slots and
//! the gait-store region of memory.x). The robot, its servo dynamics and its flash image file all
//! name it; it imports none of them.

use firmware::store::nor_double::NorDouble;

/// The flash double of the virtual board (4-byte write unit, like the firmware tests).
pub type VirtualFlash = NorDouble<4>;

/// Gait slots of the virtual board, as on the real one.
pub const SLOTS: u8 = firmware::store::BOARD_SLOTS;
/// Sectors of the virtual gait store: the board's gait store region.
pub const FLASH_SECTORS: usize =
    firmware::memory_map::GAIT_STORE_SIZE as usize / firmware::store::nor_double::SECTOR;
