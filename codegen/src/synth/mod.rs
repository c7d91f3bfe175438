//! Supervisor synthesis: products, trimming, supC, checks, minimisation, language comparison, and the
//! monolithic, modular and local modular syntheses built from them.
//!
//! # Overview
//!
//! Every algorithm runs on [`Dfa`] (the model layer's automaton over the global event ids of one
//! [`EventTable`]): dense `u32` state ids and transitions in flat arrays sorted by source then event
//! (about `9 s + 8 t` bytes for `s` states and `t` transitions). The public functions take and return
//! [`Automaton`]s and convert at the edges.
//!
//! - [`product`]: reachable synchronous product of n automata, built on the fly.
//! - [`trim`]: accessible, coaccessible and trim parts.
//! - [`supc()`]: the supremal controllable nonblocking sublanguage of `K = G ‖ E` with respect to `G`;
//!   [`verify`] holds the controllability and nonblocking checks with counterexample traces.
//! - [`minimize()`]: the smallest automaton with the same generated and marked languages.
//! - [`language`]: equality and inclusion of generated and marked languages, with a counterexample.
//! - [`local_modular()`], [`modular()`] and [`monolithic()`]: the three architectures of the paper,
//!   with the conflict check and the merge of conflicting specifications.
//! - [`reduce()`]: supervisor reduction (Su–Wonham control congruence, as TCT `supreduce`).
//! - [`deploy::deploy`]: the supervisors a project runs (full, reduced, monolithic, monolithic reduced),
//!   proven to give the full set's closed loop.
//! - [`as_written`]: which specifications are controllable as written, against their local plants.
//! - [`condat()`]: the control data (TCT `condat`): per supervisor state, the controllable events it disables.
//!
//! The worst case is the product: `n` components of `k` states can reach `k^n` states. [`Config::state_limit`]
//! bounds it and the walk stops with [`SynthError::StateLimit`] naming the limit.

mod architecture;
pub mod as_written;
mod condat;
mod config;
pub mod deploy;
mod error;
pub mod families;
pub mod language;
pub mod memory;
mod minimize;
mod product;
mod reduce;
mod reverse;
mod supc;
pub mod trim;
pub mod verify;

pub use architecture::{local_modular, modular, monolithic, LocalModularResult, Supervisor};
pub use condat::condat;
pub use config::{Config, NonblockingCheck, Observer};
pub use error::SynthError;
pub use minimize::minimize;
pub(crate) use product::name_of_tuple;
pub use product::{product, Reachable};
pub use reduce::{reduce, reduction, Reduction};
pub use supc::supc;

use crate::model::{Automaton, Dfa, EventTable};

/// A set of automata converted to [`Dfa`]s over one event table.
pub(crate) struct Inputs {
    /// Global events of the set.
    pub table: EventTable,
    /// Whether each global event is controllable.
    pub controllable: Vec<bool>,
    /// The automata, in the order given.
    pub dfas: Vec<Dfa>,
}

impl Inputs {
    /// Builds the event table of `automata` and converts each one.
    pub(crate) fn new<'a>(automata: impl Iterator<Item = &'a Automaton> + Clone) -> Result<Self, SynthError> {
        let table = EventTable::build(automata.clone())?;
        let controllable = table.ids().map(|e| table.is_controllable(e)).collect();
        let dfas = automata
            .map(|a| {
                Dfa::from_automaton(a, &table)
                    .map_err(|source| SynthError::Model { automaton: a.name.clone(), source })
            })
            .collect::<Result<_, _>>()?;
        Ok(Inputs { table, controllable, dfas })
    }
}

#[cfg(test)]
mod tests;
