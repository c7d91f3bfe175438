//! Packing a supervisor set into byte tables for the microcontroller, and the size report.
//!
//! # Overview
//!
//! Every layout takes a [`PackSet`] (plants then supervisors over one [`EventTable`](crate::model::EventTable))
//! and is encoded by the one encoder the firmware ships (`firmware::build`, [`tables`]): what the report
//! measures is the image the firmware compiles, section by section ([`Size`]). Each layout has a decoder
//! back to automata, the encoder's test oracle ([`decode`]). In the costs below, per automaton `s` states,
//! `t` transitions, `k` transitions out of the current state, and for the set `e` events.
//!
//! | layout | per state | per transition | a step costs | limits |
//! |---|---|---|---|---|
//! | `memory-safe` | 1 byte | 3 bytes | walk to state k: O(Σ records before k) | 256 events, 255 out-transitions, 65 535 states |
//! | `offset` | 1 byte | 3 bytes (5 when an automaton spans more than 64 KiB) | O(k): scan the current state's record, jump | 256 events, 255 out-transitions |
//! | `ranked` | 1 byte mask id (2 in every automaton when some needs more than 256 masks or handles), padding to the scale | 1 byte handle (2 likewise) | O(1): mask test, rank, one load | 256 events, 65 536 masks, 65 536 handles |
//! | `indexed` | as `ranked` | a handle per event of the alphabet | O(1): one load at the event's place | as `ranked` |
//! | `compact` | a bits | ⌈log₂ s⌉ bits | ≤ 15 state skips (popcounts) from a directory entry | 65 535 states |
//!
//! Every layout holds a state's position in 16 bits while the tables' positions stay below 65 536 (the
//! first 64 KiB of blocks, 8 KiB of `compact` bits), in 32 bits beyond: the encoder chooses
//! (`firmware::table::Position`).
//!
//! * `memory-safe` is the reference tool's vector, byte for byte ([`memory_safe::vector`]): Σs + 3Σt + e.
//!   For the six published supervisors of the manufacturing cell, 233 + 3·697 + 23 = 2347 bytes
//!   (committed as `tests/gen/cell.memory-safe.bin`).
//! * `offset` is the offset-addressed variant the design notes ask for: the same records with targets
//!   stored as byte offsets, so the O(s) walk is gone at no cost in size.
//! * `ranked` is what the Cortex-M3 runs by default, laid out as `firmware::table` describes: each state
//!   names its out-mask in a pool shared by all automata and lists only its targets; `indexed`, the
//!   Cortex-M0+'s default, a target per event of the alphabet and masks of whole words.
//! * `compact` numbers events within each automaton's alphabet and writes a mask of the events leaving
//!   each state, then only the targets, in as many bits as the state count needs. For the cell's
//!   supervisors: 1121 bytes with every side table, 1.33× the floor, under half of 2347.
//!
//! [`report`] measures every layout on the bytes actually produced, next to the information-theoretic
//! [`floor`] and the [`paper`]'s three formulas, and marks the layouts the cores run ([`fit`]: which
//! layout each core runs and whether its tables fit the board's flash; a refusal names what would fit).
//! Side tables (descriptors, mask pool, holders, initial states, choice sites) are listed by name, never
//! hidden in a total; event names are not counted.
//!
//! The worst case for every layout is the synchronous product a monolithic supervisor comes from: for
//! the manufacturing cell 3420 states and 11 808 transitions, 38 867 bytes in `memory-safe` (the paper's
//! figure) and 28 039 in `compact` (1.20× its floor of 23 326), against 1 121 bytes of `compact` for the six
//! local modular supervisors.

mod bits;
pub mod compact;
mod decoded;
mod error;
pub mod fit;
pub mod floor;
mod layout;
pub mod memory_safe;
pub mod paper;
pub mod ranked;
pub mod records;
pub mod report;
mod set;
mod size;
pub mod tables;
#[cfg(test)]
pub(crate) mod testing;

pub use error::{DecodeError, PackError};
pub use layout::Layout;
pub use set::{Member, PackSet, Role};
pub use size::Size;

use crate::model::Automaton;

/// Reads the firmware's tables `packed` back into automata (plants first), in whichever layout they are,
/// checking every field: the oracle the encoder is tested against. States are named by index and
/// unmarked: layouts keep no marking, the runtime needs none.
pub fn decode(packed: &tables::Packed) -> Result<Vec<Automaton>, DecodeError> {
    match packed.layout {
        firmware::build::Layout::Ranked | firmware::build::Layout::Indexed => ranked::decode(packed),
        firmware::build::Layout::MemorySafe | firmware::build::Layout::Offset => records::decode(packed),
        firmware::build::Layout::Compact => compact::decode(packed),
    }
}
