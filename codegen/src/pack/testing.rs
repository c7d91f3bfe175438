//! Test helpers shared by the layouts: small automata, random sets, and the round-trip oracle.

use std::collections::BTreeSet;

use proptest::prelude::*;

use super::PackSet;
use crate::model::{Automaton, EventId, Kind, StateId};

/// Two states: 0 –a→ 1 –b→ 0, `a` controllable, `b` not.
pub fn toggle(name: &str) -> Automaton {
    let mut t = Automaton::new(name, Kind::Plant);
    let s0 = t.add_state("0", true).unwrap();
    let s1 = t.add_state("1", false).unwrap();
    let a = t.add_event("a", true).unwrap();
    let b = t.add_event("b", false).unwrap();
    t.initial = Some(s0);
    t.add_transition(s0, a, s1);
    t.add_transition(s1, b, s0);
    t
}

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

/// A random deterministic automaton over events `e0..e{pool}` (even ids controllable).
pub fn arb_automaton(name: String, pool: usize, max_states: usize) -> impl Strategy<Value = Automaton> {
    (1..=max_states, proptest::collection::vec(any::<bool>(), pool)).prop_flat_map(move |(n, used)| {
        let alphabet: Vec<usize> = (0..pool).filter(|&i| used[i]).collect();
        let slots = n * alphabet.len();
        let name = name.clone();
        (0..n, proptest::collection::vec(proptest::option::of(0..n), slots)).prop_map(
            move |(init, targets)| {
                let mut a = Automaton::new(name.clone(), Kind::Unknown);
                for s in 0..n {
                    a.add_state(format!("q{s}"), s % 3 == 0).unwrap();
                }
                for &e in &alphabet {
                    a.add_event(format!("e{e}"), e % 2 == 0).unwrap();
                }
                a.initial = Some(StateId::from_u32(init as u32));
                for (slot, t) in targets.iter().enumerate() {
                    if let Some(t) = t {
                        let (s, e) = (slot / alphabet.len(), slot % alphabet.len());
                        a.add_transition(
                            StateId::from_u32(s as u32),
                            EventId::from_u32(e as u32),
                            StateId::from_u32(*t as u32),
                        );
                    }
                }
                a
            },
        )
    })
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
