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
//! - `extract`: the explicit automaton of a result small enough to list ([`Options::explicit_limit`]);
//! - [`Guards`]: the state feedback of the monolithic supervisor read off its BDDs, a guard per
//!   controllable event over the plants' state bits, and rewritten over the plants' signals.
//!
//! [`monolithic`] gives the exact state and transition counts of the monolithic supervisor (numbers
//! beyond 2⁶⁴ included) and, when it is small enough, the supervisor itself — the same automaton as
//! [`synth::monolithic`](crate::synth::monolithic) up to state numbering. [`Check`] plugs the symbolic
//! nonblocking check into the conflict check of the modular architectures
//! ([`Config::nonblocking`](crate::synth::Config::nonblocking)). [`AUTO_EXPLICIT_STATES`] is the `auto`
//! engine's threshold: the explicit engine runs first, the symbolic one when its product passes it.

mod encoding;
mod extract;
mod fixpoint;
mod guard;
mod order;
#[cfg(test)]
mod tests;

use std::sync::atomic::{AtomicBool, Ordering};

use num_bigint::BigUint;

pub use guard::{Guard, Guards};
pub use order::Order;

use crate::model::{Automaton, Dfa};
use crate::synth::{Config, Inputs, NonblockingCheck, Supervisor, SynthError};
use encoding::Space;
use fixpoint::Walk;

/// Largest supervisor (states) [`monolithic`] lists as an explicit automaton by default.
pub const EXPLICIT_LIMIT: u64 = 1_000_000;

/// States the `auto` engine lets an explicit product (the monolithic one, or the supervisors' product of
/// a conflict check) reach before it stops it and runs the symbolic engine instead: below it the
/// explicit engine is faster (listing a symbolic supervisor of this size as an automaton costs about as
/// much as the explicit synthesis, and a conflict check's reachable product is often tiny where its
/// BDD relations are not). Measured in `docs/symbolic.md`.
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
    /// States the explicit check may build before this one runs: [`AUTO_EXPLICIT_STATES`] for the
    /// `auto` engine, `0` (symbolic right away) for the symbolic one.
    pub explicit_states: usize,
    /// Whether a check ran symbolically (for the CLI to say which engine ran).
    pub ran: AtomicBool,
}

impl NonblockingCheck for Check {
    fn explicit_states(&self) -> usize {
        self.explicit_states
    }

    fn nonblocking(&self, dfas: &[&Dfa], cfg: &Config, what: &str) -> Result<bool, SynthError> {
        self.ran.store(true, Ordering::Relaxed);
        // Nonblocking does not depend on controllability: every event counts as controllable.
        nonblocking_dfas(dfas, &[], cfg, &self.options, what)
    }
}
