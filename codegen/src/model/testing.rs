//! Automata the unit tests of every layer build: small named examples and random automata.

use proptest::prelude::*;

use super::{Automaton, EventId, Kind, StateId};

/// Builds an automaton from `(source, event, target)` triples over states `0..states`; events in
/// `controllable` are controllable, states in `marked` are marked, state 0 is initial.
pub fn automaton(
    name: &str,
    kind: Kind,
    states: usize,
    marked: &[usize],
    controllable: &[&str],
    transitions: &[(usize, &str, usize)],
) -> Automaton {
    let mut a = Automaton::new(name, kind);
    for s in 0..states {
        a.add_state(s.to_string(), marked.contains(&s)).unwrap();
    }
    for &(_, e, _) in transitions {
        if a.event_id(e).is_none() {
            a.add_event(e, controllable.contains(&e)).unwrap();
        }
    }
    for &(s, e, t) in transitions {
        let e = a.event_id(e).unwrap();
        a.add_transition(StateId::new(s).unwrap(), e, StateId::new(t).unwrap());
    }
    a.initial = Some(StateId::new(0).unwrap());
    a
}

/// The classic small machine: idle –start→ busy –done→ idle.
pub fn machine(name: &str, start: &str, done: &str) -> Automaton {
    automaton(name, Kind::Plant, 2, &[0], &[start], &[(0, start, 1), (1, done, 0)])
}

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

/// Builds an automaton from `(source, event, target)` triples over named states; the first state is
/// initial, events listed in `controllable` are controllable.
pub fn build(name: &str, states: &[&str], controllable: &[&str], edges: &[(&str, &str, &str)]) -> Automaton {
    let mut a = Automaton::new(name, Kind::Unknown);
    for s in states {
        a.add_state(*s, false).unwrap();
    }
    a.initial = a.state_id(states[0]);
    for &(s, e, t) in edges {
        let ev = match a.event_id(e) {
            Some(ev) => ev,
            None => a.add_event(e, controllable.contains(&e)).unwrap(),
        };
        let (s, t) = (a.state_id(s).unwrap(), a.state_id(t).unwrap());
        a.add_transition(s, ev, t);
    }
    a.canonicalize();
    a.validate().unwrap();
    a
}

/// The livelock example of docs/design.md §4.1 (the reference paper's Figure 5): 1 –a→ 3, 1 –b→ 2, 3 –a→ 4,
/// 3 –b→ 1 controllable; 2 –u→ 4 and 4 –v→ 1 uncontrollable; 4 marked.
pub fn livelock() -> Automaton {
    let mut a = build(
        "livelock",
        &["1", "2", "3", "4"],
        &["a", "b"],
        &[
            ("1", "a", "3"),
            ("1", "b", "2"),
            ("3", "a", "4"),
            ("3", "b", "1"),
            ("2", "u", "4"),
            ("4", "v", "1"),
        ],
    );
    a.states[3].marked = true;
    a
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

/// `a` in the role `kind`: random automata are drawn without one.
pub fn with_kind(mut a: Automaton, kind: Kind) -> Automaton {
    a.kind = kind;
    a
}
