//! Symbolic synthesis: supC and the nonblocking check on binary decision diagrams (the
//! `biodivine-lib-bdd` library), for systems whose product outgrows explicit states.
//!
//! # Overview
//!
//! Structured plants — lines, cells, philosophers — have BDDs that grow with the number of components,
//! not with the product of their sizes, so the fixed points of synthesis run on sets of 10²⁷ states in
//! seconds. The pieces:
//!
//! - [`Order`]: which component's bits come first in the variable order (by default, components that
//!   share events sit together);
//! - `encoding`: each component's state as binary variables (current and next bits interleaved), the
//!   transition relation partitioned per event over the components holding it;
//! - `fixpoint`: reachability, co-reachability and supC as the greatest fixed point, with progress and
//!   the memory limit;
//! - `extract`: the explicit automaton of a result small enough to list ([`Options::explicit_limit`]).
//!
//! [`monolithic`] gives the exact state and transition counts of the monolithic supervisor (numbers
//! beyond 2⁶⁴ included) and, when it is small enough, the supervisor itself — the same automaton as
//! [`synth::monolithic`](crate::synth::monolithic) up to state numbering. [`Check`] plugs the symbolic
//! nonblocking check into the conflict check of the modular architectures
//! ([`Config::nonblocking`](crate::synth::Config::nonblocking)). [`AUTO_EXPLICIT_STATES`] and
//! [`AUTO_PRODUCT_BITS`] are the `auto` engine's thresholds.

mod encoding;
mod extract;
mod fixpoint;
mod order;
#[cfg(test)]
mod tests;

use std::sync::atomic::{AtomicBool, Ordering};

use num_bigint::BigUint;

pub use order::Order;

use crate::model::{Automaton, Dfa};
use crate::synth::{Config, Inputs, NonblockingCheck, Supervisor, SynthError};
use encoding::Space;
use fixpoint::Walk;

/// Largest supervisor (states) [`monolithic`] lists as an explicit automaton by default.
pub const EXPLICIT_LIMIT: u64 = 1_000_000;

/// Product size (states of the product of all components, an upper bound of the reachable part) from
/// which the `auto` engine runs the conflict check symbolically: 2²⁴, about 1.7·10⁷.
pub const AUTO_PRODUCT_BITS: f64 = 24.0;

/// States the `auto` engine lets an explicit monolithic product reach before it stops it and runs the
/// symbolic engine instead: below it the explicit engine is faster (listing a symbolic supervisor of
/// this size as an automaton costs about as much as the explicit synthesis).
pub const AUTO_EXPLICIT_STATES: usize = 1_000_000;

/// Settings of the symbolic engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    /// The variable order of the components.
    pub order: Order,
    /// Largest supervisor (states) listed as an explicit automaton; beyond it only the counts are given.
    pub explicit_limit: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options { order: Order::default(), explicit_limit: EXPLICIT_LIMIT }
    }
}

/// A supervisor computed symbolically.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SymbolicSupervisor {
    /// Its name (`S_monolithic`).
    pub name: String,
    /// Names of the specifications it enforces.
    pub specs: Vec<String>,
    /// Names of the plant subsystems.
    pub plants: Vec<String>,
    /// Exact number of states.
    pub states: BigUint,
    /// Exact number of transitions.
    pub transitions: BigUint,
    /// The supervisor as an explicit automaton, when it has at most [`Options::explicit_limit`] states.
    pub automaton: Option<Automaton>,
    /// BDD nodes of its state set.
    pub nodes: usize,
    /// The largest BDD (nodes) a fixed point held after any round.
    pub peak_nodes: usize,
}

impl SymbolicSupervisor {
    /// The explicit supervisor in the explicit engine's form, when it was listed.
    pub fn to_supervisor(&self) -> Option<Supervisor> {
        let automaton = self.automaton.clone()?;
        Some(Supervisor { automaton, specs: self.specs.clone(), plants: self.plants.clone() })
    }
}

/// Monolithic synthesis on BDDs: supC of the product of all plants and all specifications.
pub fn monolithic(
    plants: &[Automaton],
    specs: &[Automaton],
    cfg: &Config,
    options: &Options,
) -> Result<SymbolicSupervisor, SynthError> {
    let name = "S_monolithic";
    let inputs = Inputs::new(plants.iter().chain(specs))?;
    let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
    cfg.stage(&format!("{name}: encoding {} automata", dfas.len()));
    let space = Space::new(&dfas, &inputs.controllable, options.order, name)?;
    let mut walk = Walk::new(&space, cfg, name);
    let sup = walk.supc(plants.len())?;
    let states = space.count(&sup);
    let transitions = walk.transitions(&sup);
    let automaton = (states <= BigUint::from(options.explicit_limit)).then(|| {
        cfg.stage(&format!("{name}: listing {states} states"));
        let sources: Vec<&Automaton> = plants.iter().chain(specs).collect();
        extract::to_automaton(&space, &sup, &dfas, &sources, &inputs.table, name)
    });
    Ok(SymbolicSupervisor {
        name: name.to_owned(),
        specs: specs.iter().map(|a| a.name.clone()).collect(),
        plants: plants.iter().map(|a| a.name.clone()).collect(),
        states,
        transitions,
        automaton,
        nodes: sup.size(),
        peak_nodes: walk.peak_nodes,
    })
}

/// Whether the product of `automata` is nonblocking, decided on BDDs.
pub fn nonblocking(automata: &[Automaton], cfg: &Config, options: &Options) -> Result<bool, SynthError> {
    let inputs = Inputs::new(automata.iter())?;
    let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
    nonblocking_dfas(&dfas, &inputs.controllable, cfg, options, "product")
}

fn nonblocking_dfas(
    dfas: &[&Dfa],
    controllable: &[bool],
    cfg: &Config,
    options: &Options,
    what: &str,
) -> Result<bool, SynthError> {
    let space = Space::new(dfas, controllable, options.order, what)?;
    Walk::new(&space, cfg, what).nonblocking()
}

/// The symbolic nonblocking check as the conflict check of modular and local modular synthesis.
#[derive(Debug, Default)]
pub struct Check {
    /// Settings of the symbolic engine.
    pub options: Options,
    /// Whether to decline products below 2^[`AUTO_PRODUCT_BITS`] states (the `auto` engine), leaving
    /// them to the explicit check.
    pub auto: bool,
    /// Whether a check ran symbolically (for the CLI to say which engine ran).
    pub ran: AtomicBool,
}

impl NonblockingCheck for Check {
    fn nonblocking(&self, dfas: &[&Dfa], cfg: &Config, what: &str) -> Result<Option<bool>, SynthError> {
        if self.auto && product_bits(dfas.iter().map(|d| d.state_count())) < AUTO_PRODUCT_BITS {
            return Ok(None);
        }
        self.ran.store(true, Ordering::Relaxed);
        // Nonblocking does not depend on controllability: every event counts as controllable.
        nonblocking_dfas(dfas, &[], cfg, &self.options, what).map(Some)
    }
}

/// log2 of the product of `sizes` (state counts).
fn product_bits(sizes: impl Iterator<Item = usize>) -> f64 {
    sizes.map(|n| (n.max(1) as f64).log2()).sum()
}
