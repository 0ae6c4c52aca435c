//! Hardware-in-the-loop support: reading the firmware image and, with the emulator runner, driving
//! the real firmware binary end to end.

pub mod image;
