//! The automaton model every other part of the tool works on.
//!
//! An [`Automaton`] is a finite automaton with named states and named events, one optional initial
//! state, a set of marked states and a deterministic transition relation. Its events carry their
//! controllability. Automata read from different files are brought together in an [`EventTable`],
//! which gives every event of a set one dense id in one deterministic order and refuses an event whose
//! controllability differs between two files.
//!
//! A [`Dfa`] is an automaton re-indexed by the global ids of an event table, in compressed rows: what
//! synthesis computes on and the layouts pack. A [`Composition`] runs several automata side by side over one event table, one event at a time: the
//! synchronous product tracked rather than built, as the virtual plant runs the plants and the monitor
//! the closed loop.
//!
//! Everything here is ordered deterministically: the same input gives the same ids and so byte-identical
//! output downstream.

mod alphabet;
mod automaton;
mod composition;
mod controllability;
mod dfa;
mod error;
mod event_table;
mod ids;
pub mod suggest;
#[cfg(test)]
pub(crate) mod testing;

pub use alphabet::{plantless_events, PlantlessEvent};
pub use automaton::{Automaton, Event, Kind, State, Transition};
pub use composition::Composition;
pub use controllability::{resolve_controllability, resolve_controllability_or};
pub use dfa::Dfa;
pub(crate) use dfa::{DfaBuilder, NONE};
pub use error::ModelError;
pub use event_table::EventTable;
pub use ids::{EventId, IdError, StateId};
