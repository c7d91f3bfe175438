//! Which controllable transitions of each supervisor the closed loop can take, which it took, and how
//! far the closed loop is from one it has not taken yet.

use std::collections::{BTreeSet, VecDeque};

use crate::model::{Composition, EventId};
use crate::synth::Reachable;

/// A supervisor transition, as (local source state, global event id).
pub type Edge = (u32, u32);

/// The closed loop has more reachable states than [`Graph::explore`] was allowed to visit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("closed loop exceeds the exploration limit of {limit} states")]
pub struct TooLarge {
    /// The limit that was hit.
    pub limit: usize,
}

/// The reachable part of a composition, explicit: states numbered in breadth-first order from the
/// initial state (number 0), with their outgoing transitions — synthesis's product walk
/// ([`Reachable`]) over the composition's members.
#[derive(Clone, Debug)]
pub struct Graph {
    reach: Reachable,
}

impl Graph {
    /// Explores `closed` breadth first from its initial state; stops with [`TooLarge`] past `limit`
    /// states.
    pub fn explore(closed: &Composition, limit: usize) -> Result<Graph, TooLarge> {
        let reach = Reachable::explore(&closed.dfas(), limit).map_err(|_| TooLarge { limit })?;
        Ok(Graph { reach })
    }

    /// Number of reachable states.
    pub fn len(&self) -> usize {
        self.reach.dfa().state_count()
    }

    /// Whether the graph is empty (never: the initial state is always there).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The number of `state`, when it is reachable.
    pub fn id(&self, state: &[u32]) -> Option<u32> {
        self.reach.id(state)
    }

    /// The local states of state number `s`.
    pub fn tuple(&self, s: u32) -> Vec<u32> {
        self.reach.tuple(s)
    }

    /// The transitions out of state number `s`: `(global event, target state number)`, in one fixed
    /// order.
    pub fn edges(&self, s: u32) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.reach.dfa().edges(s)
    }

    /// The state reached from state number `from` by `event`, if any.
    pub fn next(&self, from: u32, event: EventId) -> Option<u32> {
        if from as usize >= self.len() {
            return None;
        }
        self.reach.dfa().step(from, event.as_u32())
    }

    /// For every member in `supervisors` (indices into `closed`, which the graph explored), the
    /// controllable transitions it takes in some state the controller can lead the closed loop to. A
    /// transition counts once per (supervisor state, event), however many closed-loop states reach it.
    ///
    /// `fires(enabled, event)` says whether the controller's policy can fire `event` where `enabled` are
    /// the enabled commands (in event-id order): a command it never picks there is not taken, and the
    /// states only such commands lead to are not reached (the `first` policy never fires a command
    /// while one with a lower id is enabled).
    pub fn controllable_edges(
        &self,
        closed: &Composition,
        supervisors: std::ops::Range<usize>,
        controllable: &[bool],
        fires: impl Fn(&[u32], u32) -> bool,
    ) -> Vec<BTreeSet<Edge>> {
        let mut out = vec![BTreeSet::new(); supervisors.len()];
        let dfa = self.reach.dfa();
        let mut seen = vec![false; self.len()];
        let mut queue = VecDeque::from([0u32]);
        seen[0] = true;
        while let Some(s) = queue.pop_front() {
            let enabled: Vec<u32> =
                dfa.edges(s).map(|(e, _)| e).filter(|&e| controllable[e as usize]).collect();
            for (e, t) in dfa.edges(s) {
                if controllable[e as usize] {
                    if !fires(&enabled, e) {
                        continue;
                    }
                    for (k, i) in supervisors.clone().enumerate() {
                        if closed.has_event(i, EventId::from_u32(e)) {
                            out[k].insert((self.reach.component_state(s, i), e));
                        }
                    }
                }
                if !std::mem::replace(&mut seen[t as usize], true) {
                    queue.push_back(t);
                }
            }
        }
        out
    }

    /// Per state number: the fewest events to a state where `wanted(state, k)` holds for its `k`-th
    /// outgoing transition (in the order of [`Graph::edges`]; `u32::MAX` when none can be reached),
    /// along transitions for which `usable(state, k)` holds. Breadth first over the reversed transitions.
    pub fn distances(
        &self,
        wanted: impl Fn(u32, usize) -> bool,
        usable: impl Fn(u32, usize) -> bool,
    ) -> Vec<u32> {
        let dfa = self.reach.dfa();
        let n = self.len();
        let mut into: Vec<Vec<u32>> = vec![Vec::new(); n];
        for s in 0..n as u32 {
            for (k, (_, t)) in dfa.edges(s).enumerate() {
                if usable(s, k) {
                    into[t as usize].push(s);
                }
            }
        }
        let mut dist = vec![u32::MAX; n];
        let mut queue = VecDeque::new();
        for s in 0..n as u32 {
            if (0..dfa.edges(s).count()).any(|k| wanted(s, k)) {
                dist[s as usize] = 0;
                queue.push_back(s);
            }
        }
        while let Some(s) = queue.pop_front() {
            for &p in &into[s as usize] {
                if dist[p as usize] == u32::MAX {
                    dist[p as usize] = dist[s as usize] + 1;
                    queue.push_back(p);
                }
            }
        }
        dist
    }
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
    /// `first_supervisor` on) holding it; returns whether any of them took a transition for the first time.
    pub fn record(
        &mut self,
        closed: &Composition,
        first_supervisor: usize,
        state: &[u32],
        event: EventId,
    ) -> bool {
        let mut new = false;
        for (k, set) in self.edges.iter_mut().enumerate() {
            let i = first_supervisor + k;
            if closed.has_event(i, event) {
                new |= set.insert((state[i], event.as_u32()));
            }
        }
        new
    }

    /// The transitions taken by supervisor `k`.
    pub fn of(&self, k: usize) -> &BTreeSet<Edge> {
        &self.edges[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::{automaton, machine};
    use crate::model::{EventTable, Kind};

    #[test]
    fn only_transitions_the_closed_loop_reaches_count_and_distances_lead_to_them() {
        let m = machine("M", "a", "b");
        // The supervisor allows `a` from its state 0 and, in a state the loop never reaches, `a` again.
        let s = automaton("S", Kind::Supervisor, 3, &[0], &["a"], &[(0, "a", 1), (1, "b", 0), (2, "a", 0)]);
        let table = EventTable::build([&m, &s]).unwrap();
        let closed = Composition::new(&[&m, &s], &table).unwrap();
        let controllable: Vec<_> = table.ids().map(|e| table.is_controllable(e)).collect();
        let g = Graph::explore(&closed, 100).unwrap();
        assert_eq!(g.len(), 2);
        let a = table.id("a").unwrap();
        assert_eq!(
            g.controllable_edges(&closed, 1..2, &controllable, |_, _| true),
            [BTreeSet::from([(0, a.as_u32())])]
        );
        assert_eq!(Graph::explore(&closed, 1).unwrap_err(), TooLarge { limit: 1 });
        let d = g.distances(|s, k| g.edges(s).nth(k).is_some_and(|(e, _)| e == a.as_u32()), |_, _| true);
        assert_eq!(d, [0, 1]);
        assert_eq!(g.next(0, a), Some(1));
        assert_eq!(g.id(&[1, 1]), Some(1));
    }

    #[test]
    fn a_command_the_policy_never_fires_and_what_lies_behind_it_do_not_count() {
        // From 0 the supervisor allows a (lower id) and b; only after b is c possible.
        let m =
            automaton("M", Kind::Plant, 3, &[0], &["a", "b", "c"], &[(0, "a", 0), (0, "b", 1), (1, "c", 0)]);
        let s = automaton(
            "S",
            Kind::Supervisor,
            2,
            &[0],
            &["a", "b", "c"],
            &[(0, "a", 0), (0, "b", 1), (1, "c", 0)],
        );
        let table = EventTable::build([&m, &s]).unwrap();
        let closed = Composition::new(&[&m, &s], &table).unwrap();
        let controllable: Vec<_> = table.ids().map(|e| table.is_controllable(e)).collect();
        let g = Graph::explore(&closed, 100).unwrap();
        let id = |e: &str| table.id(e).unwrap().as_u32();
        let all = g.controllable_edges(&closed, 1..2, &controllable, |_, _| true);
        assert_eq!(all, [BTreeSet::from([(0, id("a")), (0, id("b")), (1, id("c"))])]);
        // Lowest id only (the `first` policy): a shadows b, and c behind b is never reached.
        let lowest = |on: &[u32], e: u32| on.iter().min() == Some(&e);
        assert_eq!(
            g.controllable_edges(&closed, 1..2, &controllable, lowest),
            [BTreeSet::from([(0, id("a"))])]
        );
    }
}
