//! Tables for the runtime's host tests, built with the crate's own encoder (`firmware::build`) from
//! automata given as transition lists, read off the image the firmware compiles; the definition the
//! runtime is held to ([`definition`]); the livelock example of the design notes; and a recording link
//! port.
#![allow(dead_code)]

pub mod definition;

use firmware::build::{encode_as, HostTables, Layout, Packed, Source, SourceAutomaton};
use firmware::event_loop::{Note, Port};
use firmware::table::{Position, SupervisorSet};

/// `default` proptest cases, or `PROPTEST_CASES` when set: each suite picks its own count, and an
/// interpreter as slow as Miri lowers them all.
pub fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// What an automaton does in the loop (plants come first in a set).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Plant,
    Supervisor,
}

/// An automaton given by its states, global-id transitions and alphabet.
#[derive(Clone, Debug)]
pub struct Spec {
    pub role: Role,
    pub states: usize,
    pub initial: usize,
    pub transitions: Vec<(usize, u8, usize)>,
    pub alphabet: Vec<u8>,
}

/// `specs` (plants first) over events named `names`, `controllable` flags per event, as the encoder
/// takes them.
fn source(names: Vec<String>, controllable: &[bool], specs: &[Spec]) -> Source {
    let automata = specs
        .iter()
        .enumerate()
        .map(|(i, s)| SourceAutomaton {
            name: format!("A{i}"),
            initial: s.initial,
            alphabet: s.alphabet.iter().map(|&e| usize::from(e)).collect(),
            out: (0..s.states)
                .map(|q| {
                    let mut out: Vec<_> =
                        s.transitions.iter().filter(|t| t.0 == q).map(|t| (usize::from(t.1), t.2)).collect();
                    out.sort_unstable();
                    out
                })
                .collect(),
        })
        .collect();
    Source {
        event_names: names,
        controllable: controllable.to_vec(),
        plants: specs.iter().take_while(|s| s.role == Role::Plant).count(),
        automata,
    }
}

/// Handles of a spec's states, by state index, in the `ranked` records the encoder writes for it.
pub fn handles(spec: &Spec) -> Vec<usize> {
    handles_in(Layout::Ranked, spec)
}

/// Handles of a spec's states, by state index, in the records the encoder writes for it in `layout`.
pub fn handles_in(layout: Layout, spec: &Spec) -> Vec<usize> {
    let events =
        spec.alphabet.iter().chain(spec.transitions.iter().map(|t| &t.1)).max().map_or(0, |&e| e + 1);
    let names = (0..events).map(|e| format!("e{e}")).collect();
    let source = source(names, &vec![false; usize::from(events)], std::slice::from_ref(spec));
    encode_as(&source, layout).unwrap().handles(0).unwrap()
}

/// The encoder's tables of `specs` (plants first) over `names`, `controllable` flags per event, in
/// `layout`.
pub fn packed(layout: Layout, names: &[&str], controllable: &[bool], specs: &[Spec]) -> Packed {
    let names = names.iter().map(|n| n.to_string()).collect();
    encode_as(&source(names, controllable, specs), layout).unwrap()
}

/// Encodes `specs` (plants first) over `names.len()` events, `controllable` flags per event, in one-word
/// bitsets, in the `ranked` layout. Leaks the tables (tests only).
pub fn encode(
    names: &[&'static str],
    controllable: &[bool],
    specs: &[Spec],
) -> &'static SupervisorSet<'static, 1> {
    encode_in(Layout::Ranked, names, controllable, specs)
}

/// As [`encode`], in `layout`, positions of type `Q` (the encoder's choice for the set: the call fails
/// for the other).
pub fn encode_in<Q: Position>(
    layout: Layout,
    names: &[&'static str],
    controllable: &[bool],
    specs: &[Spec],
) -> &'static SupervisorSet<'static, 1, Q> {
    let tables = HostTables::<1, Q>::new(packed(layout, names, controllable, specs)).unwrap();
    let tables: &'static HostTables<1, Q> = Box::leak(Box::new(tables));
    Box::leak(Box::new(tables.set()))
}

/// Event ids of the livelock example.
pub const A: u8 = 0;
pub const B: u8 = 1;
pub const TO4: u8 = 2;
pub const TO1: u8 = 3;

/// The livelock example (states 1–4 as indices 0–3; 4 marked): 1 –a→ 3, 1 –b→ 2, 3 –a→ 4, 3 –b→ 1
/// controllable; 2 –to4→ 4 and 4 –to1→ 1 uncontrollable. One plant, no supervisor.
pub fn livelock() -> (&'static SupervisorSet<'static, 1>, Spec) {
    let spec = Spec {
        role: Role::Plant,
        states: 4,
        initial: 0,
        transitions: vec![(0, A, 2), (0, B, 1), (1, TO4, 3), (2, A, 3), (2, B, 0), (3, TO1, 0)],
        alphabet: vec![A, B, TO4, TO1],
    };
    let set = encode(&["a", "b", "to4", "to1"], &[true, true, false, false], &[spec]);
    let spec = Spec {
        role: Role::Plant,
        states: 4,
        initial: 0,
        transitions: vec![(0, A, 2), (0, B, 1), (1, TO4, 3), (2, A, 3), (2, B, 0), (3, TO1, 0)],
        alphabet: vec![A, B, TO4, TO1],
    };
    (set, spec)
}

/// A link port that records what the event loop sends and notes (the link tests of both runtimes).
#[derive(Default)]
pub struct Wire {
    pub sent: Vec<u8>,
    pub notes: Vec<Note>,
}

impl Port for Wire {
    fn send(&mut self, byte: u8) {
        self.sent.push(byte);
    }

    fn note(&mut self, note: Note) {
        self.notes.push(note);
    }
}
