//! Automata the check tests share.

use crate::model::{Automaton, Kind};

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

/// The livelock example of DESIGN.md §4.1 (the reference paper's Figure 5): 1 –a→ 3, 1 –b→ 2, 3 –a→ 4,
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
