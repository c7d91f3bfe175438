//! Packing a supervisor set into byte tables for the microcontroller, and the size report.
//!
//! # Overview
//!
//! Every layout takes a [`PackSet`] (plants then supervisors over one [`EventTable`](crate::model::EventTable))
//! and writes each automaton as one block of bytes; each has a decoder back to automata, which the tests
//! use as the oracle, measures itself ([`Measure`]) and keeps the set's [`Names`] apart from its bytes. In the costs below, per automaton `s` states, `t` transitions, `k` transitions out
//! of the current state, and for the set `e` events.
//!
//! | layout | per state | per transition | side tables | a step costs | limits |
//! |---|---|---|---|---|---|
//! | [`memory_safe`] | 1 byte | 3 bytes | e bytes controllability, per automaton offset, initial, alphabet | walk to state k: O(Σ records before k) | 256 events, 255 out-transitions, 65 535 states |
//! | [`offset`] | 1 byte | 3 bytes | ⌈e/32⌉ words controllability, per automaton offset, initial, alphabet | O(k): scan the current state's records, jump | 256 events, 255 out-transitions, 64 KiB block |
//! | [`ranked`] | 1 byte mask id (2 in every automaton when some needs more than 256 masks or handles), padding to the scale | 1 byte handle (2 likewise) | mask pool (⌈e/8⌉ bytes per distinct out-mask), per automaton 4-byte descriptor and alphabet, ⌈e/32⌉ words controllability | O(1): mask test, rank, one load | 256 events, 65 536 masks, 65 536 states |
//! | [`compact`] | a bits | ⌈log₂ s⌉ bits | ⌈e/8⌉ bytes controllability, per automaton counts, alphabet, directory | ≤ 15 state skips (popcounts) from a directory entry | 65 535 states |
//!
//! * `memory-safe` is the reference tool's vector, byte for byte: Σs + 3Σt + e. For the six published
//!   supervisors of the manufacturing cell, 233 + 3·697 + 23 = 2347 bytes (committed as
//!   `tests/gen/cell.memory-safe.bin`).
//! * `offset` is the offset-addressed variant of `memory-safe` the design notes ask for: the same
//!   records with targets stored as byte offsets, so the O(s) walk is gone at no cost in size (the
//!   runtime's table before `ranked`).
//! * `ranked` is what the firmware runs, laid out as `firmware::table` describes and encoded by
//!   `firmware::build`: each state names its out-mask in a pool shared by all automata and lists only
//!   its targets, as handles (record start / scale) of 1 byte where every automaton allows. For the cell
//!   with its plants: 1028 bytes of blocks and 97 masks of 3 bytes, 1404 bytes with every side table,
//!   against 2510 for `offset`.
//! * `compact` numbers events within each automaton's alphabet and writes a mask of the events leaving
//!   each state, then only the targets, in as many bits as the state count needs. For the cell's
//!   supervisors: 1121 bytes with every side table, 1.33× the floor, under half of 2347.
//!
//! [`report`] measures every layout on the bytes actually produced, next to the information-theoretic
//! [`floor`] and the [`paper`]'s three formulas. Side tables (initial states, alphabets, controllability,
//! offsets, directories) are listed by name, never hidden in a total; event names are not counted.
//!
//! The worst case for every layout is the synchronous product a monolithic supervisor comes from: for
//! the manufacturing cell 3420 states and 11 808 transitions, 38 867 bytes in `memory-safe` (the paper's
//! figure) and 28 039 in `compact` (1.20× its floor of 23 326), against 1 121 bytes of `compact` for the six
//! local modular supervisors.

mod bits;
pub mod compact;
mod decoded;
mod error;
pub mod floor;
mod layout;
pub mod memory_safe;
mod names;
pub mod offset;
pub mod paper;
pub mod ranked;
pub mod report;
mod set;
mod size;
#[cfg(test)]
pub(crate) mod testing;

pub use error::{DecodeError, PackError};
pub use layout::Layout;
pub use names::Names;
pub use set::{Member, PackSet, Role};
pub use size::{Measure, Size};
