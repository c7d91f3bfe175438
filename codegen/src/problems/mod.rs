//! Implementation problems (`codegen check`): which of Fabian & Hellgren's problems a supervisor set can
//! still hit once it runs on a controller.
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

mod attribute;
mod avalanche;
mod diamond;
mod finding;
mod group;
mod paths;
mod scope;
#[cfg(test)]
mod strings;

pub use attribute::Attributor;
pub use finding::{Finding, Problem, Shape};
pub use group::{group, Concern, Group};
pub use scope::{scopes, Scope};

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

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use proptest::prelude::*;

    use super::*;

    /// Distances from the initial state by relaxation to a fixed point: the reference for BFS.
    fn distances(a: &Automaton) -> Vec<Option<usize>> {
        let mut dist = vec![None; a.states.len()];
        dist[a.initial.unwrap().index()] = Some(0);
        let mut changed = true;
        while changed {
            changed = false;
            for t in &a.transitions {
                if let Some(d) = dist[t.source.index()] {
                    if dist[t.target.index()].is_none_or(|old| old > d + 1) {
                        dist[t.target.index()] = Some(d + 1);
                        changed = true;
                    }
                }
            }
        }
        dist
    }

    fn step(a: &Automaton, s: usize, e: usize) -> Option<usize> {
        a.transitions.iter().find(|t| t.source.index() == s && t.event.index() == e).map(|t| t.target.index())
    }

    proptest! {
        #[test]
        fn findings_match_brute_force(a in crate::model::testing::arb_automaton("A".into(), 4, 6)) {
            let found = run(&a, &Problem::ALL);
            let dist = distances(&a);
            let state_of = |name: &str| a.state_id(name).unwrap().index();
            // Every trace replays from the initial state to the finding's state, and is shortest.
            for f in &found {
                let mut s = a.initial.unwrap().index();
                for e in &f.trace {
                    s = step(&a, s, a.event_id(e).unwrap().index()).unwrap();
                }
                prop_assert_eq!(s, state_of(&f.state));
                prop_assert_eq!(Some(f.trace.len()), dist[s]);
            }
            // Avalanche: the events, each at a nearest witness.
            let mut want = BTreeSet::new();
            let mut nearest = vec![usize::MAX; a.events.len()];
            for p in (0..a.states.len()).filter(|&p| dist[p].is_some()) {
                for (e, near) in nearest.iter_mut().enumerate() {
                    let q = step(&a, p, e).filter(|&q| q != p);
                    if q.and_then(|q| step(&a, q, e).filter(|&r| r != q)).is_some() {
                        want.insert(a.events[e].name.clone());
                        *near = (*near).min(dist[p].unwrap());
                    }
                }
            }
            let avalanche: Vec<_> = found.iter().filter(|f| f.problem == Problem::Avalanche).collect();
            let got: BTreeSet<_> = avalanche.iter().map(|f| f.events[0].clone()).collect();
            prop_assert_eq!(got, want);
            for f in avalanche {
                prop_assert_eq!(f.trace.len(), nearest[a.event_id(&f.events[0]).unwrap().index()]);
            }
            // Diamonds: every reachable state, every pair of enabled events.
            let mut want = BTreeSet::new();
            for s in (0..a.states.len()).filter(|&s| dist[s].is_some()) {
                for x in 0..a.events.len() {
                    for y in x + 1..a.events.len() {
                        let (Some(mx), Some(my)) = (step(&a, s, x), step(&a, s, y)) else { continue };
                        let (xy, yx) = (step(&a, mx, y), step(&a, my, x));
                        if xy.is_none() || xy != yx {
                            let kind = match (a.events[x].controllable, a.events[y].controllable) {
                                (true, true) => Problem::Choice,
                                (false, false) => Problem::Simultaneity,
                                _ => Problem::InexactSynchronisation,
                            };
                            want.insert((kind, s, a.events[x].name.clone(), a.events[y].name.clone()));
                        }
                    }
                }
            }
            let got: BTreeSet<_> = found
                .iter()
                .filter(|f| f.problem != Problem::Avalanche)
                .map(|f| (f.problem, state_of(&f.state), f.events[0].clone(), f.events[1].clone()))
                .collect();
            prop_assert_eq!(got, want);
        }
    }
}
