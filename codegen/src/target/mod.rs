//! Where a firmware runs: its build for a target board ([`image`]) and the emulators that boot it with a
//! byte link to it: QEMU on the lm3s6965's UART ([`qemu`]), the RP2040 harness on the Pico's pins
//! ([`rp2040`]).
//!
//! An emulator is one module here: it starts the emulator on an ELF, hands back a
//! [`ByteLink`](crate::link::ByteLink) to the firmware's link and makes sure the process never outlives
//! its owner ([`child`]). The closed loop ([`crate::closed_loop`]) then runs over that link.
//!
//! What the firmware and the harness are built from travels inside the binary ([`sources`]), so an
//! installed `codegen` builds and runs them from any directory, and writes a firmware project of the user's
//! own on them ([`crate::project::new_project`]); [`lock`] serialises what processes share; [`flash`]
//! says how much of each board's flash the tables may take.

pub mod child;
pub mod flash;
pub mod image;
pub mod lock;
pub mod qemu;
pub mod rp2040;
pub mod sources;
