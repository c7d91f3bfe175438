//! Shortest traces from the initial state, by breadth-first search.

use std::collections::VecDeque;

use crate::model::{Automaton, EventId, StateId};

/// The reachable part of an automaton, with a shortest trace to every reachable state and a transition
/// lookup by (state, event).
pub struct Paths<'a> {
    automaton: &'a Automaton,
    /// Per state: the predecessor and the event on a shortest trace; `None` for the initial state and
    /// for unreachable states (told apart by [`Paths::order`]).
    parent: Vec<Option<(StateId, EventId)>>,
    /// Reachable states in breadth-first order, events tried in increasing id.
    order: Vec<StateId>,
    /// Per state: `(event, target)` sorted by event.
    out: Vec<Vec<(EventId, StateId)>>,
}

impl<'a> Paths<'a> {
    /// Explores `a` from its initial state.
    pub fn new(a: &'a Automaton) -> Self {
        let n = a.states.len();
        let mut out = vec![Vec::new(); n];
        for t in &a.transitions {
            out[t.source.index()].push((t.event, t.target));
        }
        for edges in &mut out {
            edges.sort_unstable();
        }
        let mut parent = vec![None; n];
        let mut seen = vec![false; n];
        let mut order = Vec::new();
        let mut queue = VecDeque::new();
        if let Some(init) = a.initial {
            seen[init.index()] = true;
            queue.push_back(init);
        }
        while let Some(s) = queue.pop_front() {
            order.push(s);
            for &(e, t) in &out[s.index()] {
                if !seen[t.index()] {
                    seen[t.index()] = true;
                    parent[t.index()] = Some((s, e));
                    queue.push_back(t);
                }
            }
        }
        Paths { automaton: a, parent, order, out }
    }

    /// The automaton explored.
    pub fn automaton(&self) -> &'a Automaton {
        self.automaton
    }

    /// Reachable states, nearest first.
    pub fn order(&self) -> &[StateId] {
        &self.order
    }

    /// Outgoing `(event, target)` pairs of `s`, sorted by event.
    pub fn out(&self, s: StateId) -> &[(EventId, StateId)] {
        &self.out[s.index()]
    }

    /// The state `e` leads to from `s`, if any.
    pub fn step(&self, s: StateId, e: EventId) -> Option<StateId> {
        let edges = &self.out[s.index()];
        edges.binary_search_by_key(&e, |&(ev, _)| ev).ok().map(|i| edges[i].1)
    }

    /// A shortest trace from the initial state to `s` (of a reachable `s`), as event names.
    pub fn trace(&self, s: StateId) -> Vec<String> {
        let mut events = Vec::new();
        let mut at = s;
        while let Some((prev, e)) = self.parent[at.index()] {
            events.push(self.automaton.events[e.index()].name.clone());
            at = prev;
        }
        events.reverse();
        events
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::livelock;

    #[test]
    fn traces_are_shortest() {
        let a = livelock();
        let p = Paths::new(&a);
        let s4 = a.state_id("4").unwrap();
        assert_eq!(p.trace(s4), ["a", "a"]);
        assert_eq!(p.order().len(), 4);
        assert!(p.trace(a.state_id("1").unwrap()).is_empty());
    }
}
