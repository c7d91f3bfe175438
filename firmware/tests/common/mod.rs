//! Hand-built tables for the runtime's host tests: an encoder of the `offset` layout for small automata
//! given as transition lists (independent of codegen, which depends on this crate) and the livelock
//! example of the design notes.
#![allow(dead_code)]

use firmware::table::{Automaton, Role, Site, SupervisorSet};

const NO_OWNER: u8 = 0xFF;

/// An automaton given by its states, global-id transitions and alphabet.
#[derive(Clone, Debug)]
pub struct Spec {
    pub role: Role,
    pub states: usize,
    pub initial: usize,
    pub transitions: Vec<(usize, u8, usize)>,
    pub alphabet: Vec<u8>,
}

/// State offsets of a spec's block, by state index.
pub fn offsets(spec: &Spec) -> Vec<u16> {
    let mut at = 0u16;
    (0..spec.states)
        .map(|s| {
            let here = at;
            let n = spec.transitions.iter().filter(|t| t.0 == s).count() as u16;
            at += 1 + 3 * n;
            here
        })
        .collect()
}

fn block(spec: &Spec) -> Vec<u8> {
    let offs = offsets(spec);
    let mut out = Vec::new();
    for s in 0..spec.states {
        let ts: Vec<_> = spec.transitions.iter().filter(|t| t.0 == s).collect();
        out.push(ts.len() as u8);
        for t in ts {
            out.push(t.1);
            out.extend_from_slice(&offs[t.2].to_be_bytes());
        }
    }
    out
}

fn bits(events: impl IntoIterator<Item = u8>) -> Vec<u32> {
    let mut w = vec![0u32; 1];
    for e in events {
        w[usize::from(e / 32)] |= 1 << (e % 32);
    }
    w
}

/// Encodes `specs` (plants first) over `events` names, the first `controllable` flags true where
/// controllable; at most 32 events. Leaks the tables (tests only).
pub fn encode(
    names: &[&'static str],
    controllable: &[bool],
    specs: &[Spec],
) -> &'static SupervisorSet<'static> {
    let automata: Vec<Automaton<'static>> = specs
        .iter()
        .enumerate()
        .map(|(i, s)| Automaton {
            name: ["A0", "A1", "A2", "A3", "A4", "A5", "A6", "A7"][i],
            role: s.role,
            initial: offsets(s)[s.initial],
            block: Box::leak(block(s).into_boxed_slice()),
            alphabet: Box::leak(bits(s.alphabet.iter().copied()).into_boxed_slice()),
        })
        .collect();
    let holders: Vec<u32> = (0..names.len() as u8)
        .map(|e| specs.iter().enumerate().filter(|(_, s)| s.alphabet.contains(&e)).map(|(i, _)| 1 << i).sum())
        .collect();
    let owner: Vec<u8> = (0..names.len() as u8)
        .map(|e| {
            let plant = specs.iter().position(|s| s.role == Role::Plant && s.alphabet.contains(&e));
            match plant {
                Some(p) if controllable[usize::from(e)] => p as u8,
                _ => NO_OWNER,
            }
        })
        .collect();
    let plant_events: Vec<u32> = specs
        .iter()
        .enumerate()
        .filter(|(_, s)| s.role == Role::Plant)
        .flat_map(|(i, _)| bits((0..names.len() as u8).filter(|&e| owner[usize::from(e)] == i as u8)))
        .collect();
    let mut sites = Vec::new();
    for (i, s) in specs.iter().enumerate().filter(|(_, s)| s.role == Role::Plant) {
        let offs = offsets(s);
        for (st, &off) in offs.iter().enumerate() {
            let n = s.transitions.iter().filter(|t| t.0 == st && owner[usize::from(t.1)] == i as u8).count();
            if n >= 2 {
                sites.push(Site { automaton: i as u8, state: off });
            }
        }
    }
    Box::leak(Box::new(SupervisorSet {
        event_names: Box::leak(names.to_vec().into_boxed_slice()),
        controllable: Box::leak(
            bits((0..names.len() as u8).filter(|&e| controllable[usize::from(e)])).into_boxed_slice(),
        ),
        automata: Box::leak(automata.into_boxed_slice()),
        holders: Box::leak(holders.into_boxed_slice()),
        plant_events: Box::leak(plant_events.into_boxed_slice()),
        sites: Box::leak(sites.into_boxed_slice()),
    }))
}

/// Event ids of the livelock example.
pub const A: u8 = 0;
pub const B: u8 = 1;
pub const TO4: u8 = 2;
pub const TO1: u8 = 3;

/// The livelock example (states 1–4 as indices 0–3; 4 marked): 1 –a→ 3, 1 –b→ 2, 3 –a→ 4, 3 –b→ 1
/// controllable; 2 –to4→ 4 and 4 –to1→ 1 uncontrollable. One plant, no supervisor.
pub fn livelock() -> (&'static SupervisorSet<'static>, Spec) {
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
