//! Implementation checks: which of Fabian & Hellgren's problems a supervisor set can still hit once it
//! runs on a controller.
//!
//! Each check reads a deterministic automaton (a closed loop, built as the synchronous product of plants
//! and supervisors) and reports [`Finding`]s with the state, the events and a shortest trace from the
//! initial state:
//!
//! * [`Problem::Avalanche`] — σ with p –σ→ q –σ→ r, p ≠ q, q ≠ r (self-loops never count).
//! * [`Problem::Choice`] — two enabled controllable events whose two orders do not reach one state.
//! * [`Problem::InexactSynchronisation`] — the same for a controllable and an uncontrollable event.
//! * [`Problem::Simultaneity`] — the same for two uncontrollable events.
//!
//! Only reachable states are examined. Cost: O(s + t) for avalanche, O(Σ k²) for the diamonds, k the
//! transitions out of a state.

mod avalanche;
mod diamond;
mod finding;
mod paths;
#[cfg(test)]
mod testing;

pub use finding::{Finding, Problem};

use crate::model::Automaton;

/// Runs the checks in `problems` on `a`; findings grouped by problem in [`Problem::ALL`] order, each group
/// nearest state first.
pub fn run(a: &Automaton, problems: &[Problem]) -> Vec<Finding> {
    let paths = paths::Paths::new(a);
    let mut found = if problems.contains(&Problem::Avalanche) { avalanche::find(&paths) } else { Vec::new() };
    let mut diamonds = diamond::find(&paths, problems);
    diamonds.sort_by_key(|f| f.problem);
    found.extend(diamonds);
    found
}
