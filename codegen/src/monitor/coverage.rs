//! Which controllable transitions of each supervisor the closed loop can take, and which it took.

use std::collections::{BTreeSet, HashMap};

use crate::model::EventId;
use crate::plant::Composition;

/// A supervisor transition, as (local source state, global event id).
pub type Edge = (u32, u32);

/// The closed loop has more reachable states than [`reachable_controllable`] was allowed to visit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("closed loop exceeds the exploration limit of {limit} states")]
pub struct TooLarge {
    /// The limit that was hit.
    pub limit: usize,
}

/// For every member in `supervisors` (indices into `closed`), the controllable transitions it takes in
/// some reachable state of `closed` (plants ‖ supervisors). A transition counts once per (supervisor
/// state, event), however many closed-loop states reach it.
///
/// Explores breadth first from the initial state and stops with [`TooLarge`] past `limit` states.
pub fn reachable_controllable(
    closed: &Composition,
    supervisors: std::ops::Range<usize>,
    controllable: &[bool],
    limit: usize,
) -> Result<Vec<BTreeSet<Edge>>, TooLarge> {
    let mut out = vec![BTreeSet::new(); supervisors.len()];
    let initial = closed.initial();
    let mut seen: HashMap<Vec<u32>, ()> = HashMap::from([(initial.clone(), ())]);
    let mut queue = std::collections::VecDeque::from([initial]);
    while let Some(state) = queue.pop_front() {
        for e in closed.enabled(&state) {
            if controllable[e.index()] {
                for (k, i) in supervisors.clone().enumerate() {
                    if closed.has_event(i, e) {
                        out[k].insert((state[i], e.as_u32()));
                    }
                }
            }
            let mut next = state.clone();
            closed.step(&mut next, e);
            if !seen.contains_key(&next) {
                if seen.len() >= limit {
                    return Err(TooLarge { limit });
                }
                seen.insert(next.clone(), ());
                queue.push_back(next);
            }
        }
    }
    Ok(out)
}

/// Controllable supervisor transitions taken during a run.
#[derive(Clone, Debug, Default)]
pub struct Taken {
    edges: Vec<BTreeSet<Edge>>,
}

impl Taken {
    /// Nothing taken yet, for `supervisors` supervisors.
    pub fn new(supervisors: usize) -> Self {
        Taken { edges: vec![BTreeSet::new(); supervisors] }
    }

    /// Records command `event` taken in closed-loop `state`, for every supervisor (members from
    /// `first_supervisor` on) holding it.
    pub fn record(&mut self, closed: &Composition, first_supervisor: usize, state: &[u32], event: EventId) {
        for (k, set) in self.edges.iter_mut().enumerate() {
            let i = first_supervisor + k;
            if closed.has_event(i, event) {
                set.insert((state[i], event.as_u32()));
            }
        }
    }

    /// The transitions taken by supervisor `k`.
    pub fn of(&self, k: usize) -> &BTreeSet<Edge> {
        &self.edges[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{EventTable, Kind};
    use crate::plant::composition::tests::{automaton, machine};

    #[test]
    fn only_transitions_the_closed_loop_reaches_count() {
        let m = machine("M", "a", "b");
        // The supervisor allows `a` from its state 0 and, in a state the loop never reaches, `a` again.
        let s = automaton("S", Kind::Supervisor, 3, &[0], &["a"], &[(0, "a", 1), (1, "b", 0), (2, "a", 0)]);
        let table = EventTable::build([&m, &s]).unwrap();
        let closed = Composition::new(&[&m, &s], &table).unwrap();
        let controllable: Vec<_> = table.ids().map(|e| table.is_controllable(e)).collect();
        let r = reachable_controllable(&closed, 1..2, &controllable, 100).unwrap();
        assert_eq!(r, [BTreeSet::from([(0, table.id("a").unwrap().as_u32())])]);
        assert_eq!(reachable_controllable(&closed, 1..2, &controllable, 1), Err(TooLarge { limit: 1 }));
    }
}
