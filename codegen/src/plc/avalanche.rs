//! The avalanche effect in a scan, and the two ways the bit encoding removes it.
//!
//! In the bit encoding every transition is one statement `IF X_p AND trigger THEN X_p := FALSE;
//! X_q := TRUE; END_IF`, run top to bottom. An event σ with p –σ→ q –σ→ r (p ≠ q, q ≠ r) in one automaton
//! would take both steps in one scan if q's statement came after p's. Two remedies, per event and
//! automaton:
//!
//! * **order** — put the statements in reverse topological order of σ's transition graph (self-loops
//!   aside): q's statements before p's, so when p's fires, q's has already been passed. Possible when the
//!   graph has no cycle; the statements of one automaton have one order, so the graphs of all events
//!   ordered this way must have no cycle together.
//! * **AEEM** (avalanche effect elimination method) — a memory bit per event, set when the event occurs,
//!   used as the trigger and reset by every transition that uses it (and at the end of the scan): the
//!   first transition taken consumes the event. Always possible; costs a bit and two statements.
//!
//! `auto` orders what it can (events in id order, each while the union of ordered graphs stays acyclic)
//! and uses AEEM for the rest. In the int encoding a `CASE` on the state picks one branch, so no event
//! can chain there ([`Method::Case`]).

use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};

use crate::model::{EventId, StateId};

/// How avalanche events are eliminated (`--avalanche`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Avalanche {
    /// Statement order where the event's graph is acyclic, AEEM elsewhere.
    #[default]
    Auto,
    /// AEEM for every avalanche event.
    Aeem,
    /// Statement order for every avalanche event (refused where a graph has a cycle).
    Order,
    /// No elimination: the scan may chain transitions (for comparison).
    None,
}

impl Avalanche {
    /// The option's name.
    pub fn name(self) -> &'static str {
        match self {
            Avalanche::Auto => "auto",
            Avalanche::Aeem => "aeem",
            Avalanche::Order => "order",
            Avalanche::None => "none",
        }
    }
}

/// What removes one event's avalanche in one automaton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Method {
    /// Reverse topological statement order.
    Order,
    /// A memory bit.
    Aeem,
    /// Nothing (`--avalanche none`): the event can chain.
    None,
    /// The int encoding's `CASE`.
    Case,
}

impl Method {
    /// The name the report prints.
    pub fn name(self) -> &'static str {
        match self {
            Method::Order => "order",
            Method::Aeem => "aeem",
            Method::None => "none",
            Method::Case => "case",
        }
    }
}

/// `--avalanche order` cannot order an event.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("event id {} has a cycle among its transitions{}", event.index(), if *conflict { " together with the events ordered before it" } else { "" })]
pub struct Unorderable {
    /// The event.
    pub event: EventId,
    /// The cycle comes from the union with other ordered events, not from the event alone.
    pub conflict: bool,
}

/// The plan of one automaton for one pass of transition statements (the events of `events`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    /// States in the order their statements are written.
    pub order: Vec<usize>,
    /// Method per avalanche event of the pass (events that chain in this automaton).
    pub methods: BTreeMap<EventId, Method>,
}

/// Per state (by index) the outgoing `(event, target)` pairs, as [`crate::pack::Member::out`] holds them.
pub type Out = [Vec<(EventId, StateId)>];

/// The events of `pass` with p –σ→ q –σ→ r, p ≠ q, q ≠ r, in id order.
pub fn chain_events(out: &Out, pass: &dyn Fn(EventId) -> bool) -> Vec<EventId> {
    let step = |s: usize, e: EventId| out[s].iter().find(|(x, _)| *x == e).map(|&(_, t)| t.index());
    let mut found: Vec<EventId> = Vec::new();
    for (p, edges) in out.iter().enumerate() {
        for &(e, q) in edges {
            let q = q.index();
            if pass(e) && q != p && step(q, e).is_some_and(|r| r != q) && !found.contains(&e) {
                found.push(e);
            }
        }
    }
    found.sort_unstable();
    found
}

/// Decides the method of every avalanche event of the pass and the statement order of the states.
pub fn plan(out: &Out, pass: &dyn Fn(EventId) -> bool, option: Avalanche) -> Result<Plan, Unorderable> {
    let mut methods = BTreeMap::new();
    let mut ordered: Vec<EventId> = Vec::new();
    for e in chain_events(out, pass) {
        let method = match option {
            Avalanche::None => Method::None,
            Avalanche::Aeem => Method::Aeem,
            Avalanche::Order | Avalanche::Auto => {
                let alone = reverse_topological(out, &[e]).is_some();
                let with: Vec<EventId> = ordered.iter().copied().chain([e]).collect();
                let together = alone && reverse_topological(out, &with).is_some();
                match (together, option) {
                    (true, _) => {
                        ordered.push(e);
                        Method::Order
                    }
                    (false, Avalanche::Order) => return Err(Unorderable { event: e, conflict: alone }),
                    (false, _) => Method::Aeem,
                }
            }
        };
        methods.insert(e, method);
    }
    let order = reverse_topological(out, &ordered).unwrap_or_else(|| (0..out.len()).collect());
    Ok(Plan { order, methods })
}

/// The states ordered so that for every transition p –σ→ q of an event of `events` (p ≠ q), q comes
/// before p; among the states free to go next, the lowest index first (so with no events, ascending).
/// `None` when those transitions have a cycle.
pub fn reverse_topological(out: &Out, events: &[EventId]) -> Option<Vec<usize>> {
    let n = out.len();
    let mut preds: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut pending = vec![0usize; n];
    for (p, edges) in out.iter().enumerate() {
        let mut targets: Vec<usize> = edges
            .iter()
            .filter(|(e, q)| events.contains(e) && q.index() != p)
            .map(|(_, q)| q.index())
            .collect();
        targets.sort_unstable();
        targets.dedup();
        pending[p] = targets.len();
        for q in targets {
            preds[q].push(p);
        }
    }
    let mut ready: BinaryHeap<Reverse<usize>> = (0..n).filter(|&s| pending[s] == 0).map(Reverse).collect();
    let mut order = Vec::with_capacity(n);
    while let Some(Reverse(s)) = ready.pop() {
        order.push(s);
        for &p in &preds[s] {
            pending[p] -= 1;
            if pending[p] == 0 {
                ready.push(Reverse(p));
            }
        }
    }
    (order.len() == n).then_some(order)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn out(n: usize, edges: &[(usize, u32, usize)]) -> Vec<Vec<(EventId, StateId)>> {
        let mut out = vec![Vec::new(); n];
        for &(p, e, q) in edges {
            out[p].push((EventId::from_u32(e), StateId::new(q).unwrap()));
        }
        out
    }

    /// `seed/TEST.ADS` with events 1..6 as ids 1..6.
    fn seed() -> Vec<Vec<(EventId, StateId)>> {
        out(
            5,
            &[
                (0, 1, 1),
                (0, 2, 4),
                (1, 3, 3),
                (1, 2, 0),
                (1, 1, 2),
                (1, 5, 4),
                (2, 3, 1),
                (2, 1, 3),
                (3, 1, 2),
                (3, 6, 2),
                (4, 2, 2),
                (4, 6, 0),
                (3, 4, 0),
            ],
        )
    }

    #[test]
    fn the_seed_has_avalanche_events_1_2_3_and_auto_picks_per_event() {
        let all = |_: EventId| true;
        let ids: Vec<u32> = chain_events(&seed(), &all).iter().map(|e| e.as_u32()).collect();
        assert_eq!(ids, [1, 2, 3]);
        // 1: 0→1→2→3→2 has the cycle 2↔3; 2: 0→4→2 and 1→0 acyclic; 3: 1→3 and 2→1 acyclic, but with 2
        // (1→0→4→2) the union has 2→1→0→4→2.
        let p = plan(&seed(), &all, Avalanche::Auto).unwrap();
        let methods: Vec<(u32, Method)> = p.methods.iter().map(|(e, m)| (e.as_u32(), *m)).collect();
        assert_eq!(methods, [(1, Method::Aeem), (2, Method::Order), (3, Method::Aeem)]);
        assert_eq!(p.order, [2, 3, 4, 0, 1], "for 2: 2 before 4 before 0 before 1");
        assert_eq!(
            plan(&seed(), &all, Avalanche::Order),
            Err(Unorderable { event: EventId::from_u32(1), conflict: false })
        );
        let p = plan(&seed(), &all, Avalanche::Aeem).unwrap();
        assert_eq!(p.order, [0, 1, 2, 3, 4]);
        assert!(p.methods.values().all(|&m| m == Method::Aeem));
    }

    proptest! {
        /// The order puts every ordered event's target before its source; `auto` orders exactly the
        /// events whose graph, with those ordered before, is acyclic.
        #[test]
        fn orders_respect_every_ordered_edge(edges in proptest::collection::vec((0usize..5, 0u32..3, 0usize..5), 0..14)) {
            let mut edges = edges;
            edges.sort_unstable();
            edges.dedup_by(|a, b| a.0 == b.0 && a.1 == b.1);
            let o = out(5, &edges);
            let p = plan(&o, &|_| true, Avalanche::Auto).unwrap();
            let rank = |s: usize| p.order.iter().position(|&x| x == s).unwrap();
            for &(s, e, t) in &edges {
                if s != t && p.methods.get(&EventId::from_u32(e)) == Some(&Method::Order) {
                    prop_assert!(rank(t) < rank(s));
                }
            }
            for (e, m) in &p.methods {
                let alone_acyclic = reverse_topological(&o, &[*e]).is_some();
                if !alone_acyclic {
                    prop_assert_eq!(*m, Method::Aeem);
                }
            }
        }
    }
}
