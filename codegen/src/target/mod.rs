//! Where a firmware runs: its build for a target board ([`image`]) and the emulator that boots it with
//! a byte link to its UART ([`qemu`]).
//!
//! An emulator is one file here: it starts the emulator on an ELF, hands back a
//! [`ByteLink`](crate::link::ByteLink) to the firmware's link and makes sure the process never outlives
//! its owner. The closed loop ([`crate::closed_loop`]) then runs over that link.

pub mod image;
pub mod qemu;
