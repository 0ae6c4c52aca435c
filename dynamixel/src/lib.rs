//! Dynamixel Protocol 2.0 for the MX-28(2.0) / MX-64(2.0) servos of Drosophibot II: packet codec,
//! async bus master and control tables (`no_std`, no alloc), and with `std` a virtual servo chain.

#![cfg_attr(not(any(feature = "std", test)), no_std)]
