//! Test helpers shared by the layouts: random sets, the round-trip oracle and corruption.

use std::collections::BTreeSet;

use proptest::prelude::*;

use super::PackSet;
use crate::model::testing::arb_automaton;
use crate::model::Automaton;

/// Transitions as `(source, event name, target)`, the part of an automaton every layout keeps.
fn edges(a: &Automaton) -> BTreeSet<(usize, String, usize)> {
    a.transitions
        .iter()
        .map(|t| (t.source.index(), a.events[t.event.index()].name.clone(), t.target.index()))
        .collect()
}

/// Asserts that `decoded` is the set's automata with the same states (by index), initial state,
/// alphabet (names and controllability) and transitions. Identical transition graphs accept the same
/// language, which is the property the tables must keep.
pub fn assert_round_trip(set: &PackSet, decoded: &[Automaton]) {
    assert_eq!(set.members().len(), decoded.len());
    for (m, d) in set.members().iter().zip(decoded) {
        let a = &m.automaton;
        assert_eq!(d.name, a.name);
        assert_eq!(d.kind, m.role.kind());
        assert_eq!(d.states.len(), a.states.len(), "{}", a.name);
        assert_eq!(d.initial, a.initial, "{}", a.name);
        let alphabet = |x: &Automaton| x.events.iter().map(|e| (e.name.clone(), e.controllable)).collect();
        let (want, got): (BTreeSet<_>, BTreeSet<_>) = (alphabet(a), alphabet(d));
        assert_eq!(got, want, "{}", a.name);
        assert_eq!(edges(d), edges(a), "{}", a.name);
    }
}

/// A random set: 1–3 plants and 0–3 supervisors over up to 12 events, up to `max_states` states each.
pub fn arb_set(max_states: usize) -> impl Strategy<Value = PackSet> {
    (1usize..=3, 0usize..=3, 1usize..=12).prop_flat_map(move |(p, s, pool)| {
        let plants: Vec<_> = (0..p).map(|i| arb_automaton(format!("G{i}"), pool, max_states)).collect();
        let sups: Vec<_> = (0..s).map(|i| arb_automaton(format!("S{i}"), pool, max_states)).collect();
        (plants, sups).prop_map(|(p, s)| PackSet::new(p, s).unwrap())
    })
}

/// Flips bytes of `bytes` at the given (wrapped) positions to the given values.
pub fn corrupt(bytes: &mut [u8], edits: &[(usize, u8)]) {
    if bytes.is_empty() {
        return;
    }
    let len = bytes.len();
    for &(at, v) in edits {
        bytes[at % len] = v;
    }
}
