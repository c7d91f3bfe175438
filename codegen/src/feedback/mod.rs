//! State feedback control (docs/state-based.md; Côté, St-Denis & Kerjean): a controller that tracks no
//! event reads the plant's state from its signals and, per controllable event σ, evaluates a formula
//! F_σ over them. This module computes F_σ for a supervisor set — what the PLC's state-based program
//! ([`crate::plc::state_based`]) and the state-based firmware's tables ([`crate::emit::state`]) are both
//! written from, so the two run one feedback.
//!
//! | part | module |
//! |---|---|
//! | the manifest's `[state]` section bound to the set's plants and checked against them | [`vector`] |
//! | f from the reachable closed loop; where memory decides, the conflicts or the supervisors kept | [`sfbc`] |
//! | the kept supervisors' states as memory bits among the variables | [`memory`] |
//! | F_σ as a prime, irredundant sum of products | [`minimise`] |
//! | F_σ from guards read off the symbolic engine's BDDs (`--engine symbolic`) | [`guards`] |
//! | the rules as the state-based firmware's tables (cubes over the packed signal word) | [`tables`] |

pub mod guards;
pub mod memory;
pub mod minimise;
pub mod sfbc;
pub mod tables;
pub mod vector;

use crate::config::{Cube, Signals, SignalsError};
use crate::model::EventId;
use crate::pack::PackSet;
use crate::synth::{Reachable, SynthError};

pub use sfbc::Sfbc;
pub use vector::Vector;

/// Why a state feedback cannot be computed or written.
#[derive(Debug, thiserror::Error)]
pub enum FeedbackError {
    /// The manifest has no `[state]` section.
    #[error("--encoding state needs the manifest's [state] section (the plant's state vectors)")]
    Missing,
    /// The section is malformed.
    #[error(transparent)]
    Signals(#[from] SignalsError),
    /// The section does not fit the set's plants, or the tables cannot hold the feedback.
    #[error("{key}: {message}")]
    Vector {
        /// The key it is about.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// The closed loop could not be explored.
    #[error("closed loop: {0}")]
    Synth(#[from] SynthError),
    /// The supervisors' memory decides somewhere and memory is not allowed.
    #[error("{0}")]
    Memory(String),
}

/// One controllable event's feedback: F_σ as a sum of cubes over the variables (the signals, then the
/// memory bits), and the outputs its command writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rule {
    /// The event.
    pub event: EventId,
    /// F_σ: the event is allowed where one of the cubes holds.
    pub cubes: Vec<Cube>,
    /// What its command writes (the outputs it sets and clears).
    pub command: Cube,
}

/// The feedback of `set` under `signals`' state vectors (memory kept where it decides when `memory`
/// or `[state] memory` allows it; the events of `decided` left to guards over a module's variables,
/// [`Sfbc::compute_deciding`]), and the state vectors bound to the set.
pub fn analyse(
    set: &PackSet,
    signals: Signals,
    memory: bool,
    decided: &[EventId],
) -> Result<(Vector, Sfbc), FeedbackError> {
    let vector = Vector::bind(set, signals)?;
    let f = Sfbc::compute_deciding(set, memory || vector.signals.memory, decided)?;
    Ok((vector, f))
}

/// The cube of entry `e`: its plant state's formula and its kept supervisors' memory bits.
pub fn entry_cube(vector: &Vector, f: &Sfbc, memory: &memory::Layout, e: &sfbc::Entry) -> Cube {
    let x = vector.cube(&e.state[..f.plants]);
    let m = memory.cube(&e.state[f.plants..]);
    Cube { mask: x.mask | m.mask, value: x.value | m.value }
}

/// The rules of `f`: per controllable event (in [`Sfbc::controllable`] order), F_σ minimised between
/// its ON set and the valuations no reachable state produces (none with `exact`).
pub fn rules(vector: &Vector, f: &Sfbc, memory: &memory::Layout, exact: bool) -> Vec<Rule> {
    let u = minimise::Universe::new(vector.signals.signals.len() + memory.count());
    let cubes: Vec<Cube> = f.entries.iter().map(|e| entry_cube(vector, f, memory, e)).collect();
    let reachable = u.union(&cubes);
    let dc = if exact { u.union(&[]) } else { reachable.not() };
    f.controllable
        .iter()
        .enumerate()
        .map(|(i, &event)| {
            let on: Vec<Cube> =
                f.entries.iter().zip(&cubes).filter(|(en, _)| en.allowed[i]).map(|(_, &c)| c).collect();
            Rule { event, cubes: u.minimise(&u.union(&on), &dc), command: vector.command(event) }
        })
        .collect()
}

/// States and transitions of the reachable product of `dfas` (the free plant G, or the specification E).
pub fn product_size(dfas: &[&crate::model::Dfa]) -> Result<(usize, usize), SynthError> {
    let r = Reachable::explore(dfas, sfbc::STATE_LIMIT)?;
    Ok((r.dfa().state_count(), r.dfa().transition_count()))
}
