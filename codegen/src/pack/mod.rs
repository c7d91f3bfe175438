//! Packing a supervisor set into byte tables for the microcontroller, and the size report.
//!
//! # Overview
//!
//! Every layout takes a [`PackSet`] (plants then supervisors over one [`EventTable`](crate::model::EventTable))
//! and writes each automaton as one block of bytes; each has a decoder back to automata, which the tests
//! use as the oracle. In the costs below, per automaton `s` states, `t` transitions, `k` transitions out
//! of the current state, and for the set `e` events.
//!
//! * [`offset`] — what the firmware runs (`firmware/src/table.rs`). Per state a count byte, per
//!   transition `[event u8][target byte offset u16 BE]`: 1 byte per state, 3 per transition,
//!   Σs + 3Σt in all. A step scans the k records of the current state and jumps: O(k), never O(s).
//!   Limits: 256 events, 255 transitions per state, 64 KiB per block.
//!
//! Side tables (initial states, alphabets, controllability, names) are counted separately in the report,
//! never hidden in a total.
//!
//! The worst case for every layout is the synchronous product a monolithic supervisor comes from: for
//! the manufacturing cell 3420 states and 11 808 transitions, 38 844 bytes in `offset` against 2 324 for
//! the six local modular supervisors.

mod bits;
mod bitset;
pub mod compact;
mod decoded;
mod error;
pub mod floor;
mod layout;
pub mod memory_safe;
pub mod offset;
pub mod paper;
pub mod report;
mod set;
mod size;
#[cfg(test)]
pub(crate) mod testing;

pub use error::{DecodeError, PackError};
pub use layout::Layout;
pub use set::{Member, PackSet, Role};
pub use size::Size;
