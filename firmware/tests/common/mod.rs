//! Hand-built tables for the runtime's host tests: an encoder of the `ranked` layout for small automata
//! given as transition lists (independent of codegen, which depends on this crate) and the livelock
//! example of the design notes.
#![allow(dead_code)]

use firmware::table::{Automaton, SupervisorSet};

/// What an automaton does in the loop (plants come first in a set).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Plant,
    Supervisor,
}

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

/// A spec's states in the order of their records: the initial state first, then the others by index.
fn order(spec: &Spec) -> Vec<usize> {
    std::iter::once(spec.initial).chain((0..spec.states).filter(|&q| q != spec.initial)).collect()
}

/// Handles of a spec's states, by state index, in the records `encode` writes (scale 1, 1-byte fields:
/// a record is the mask id and one byte per transition).
pub fn handles(spec: &Spec) -> Vec<u16> {
    let mut hs = vec![0u16; spec.states];
    let mut at = 0u16;
    for q in order(spec) {
        hs[q] = at;
        at += 1 + spec.transitions.iter().filter(|t| t.0 == q).count() as u16;
    }
    hs
}

fn bits(events: impl IntoIterator<Item = u8>) -> u32 {
    events.into_iter().fold(0, |w, e| w | 1 << e)
}

fn leak<T>(v: Vec<T>) -> &'static [T] {
    Box::leak(v.into_boxed_slice())
}

/// Encodes `specs` (plants first) over `names.len()` events, `controllable` flags per event; at most 32
/// events and small automata (1-byte handles). Leaks the tables (tests only).
pub fn encode(
    names: &[&'static str],
    controllable: &[bool],
    specs: &[Spec],
) -> &'static SupervisorSet<'static, 1> {
    assert!(names.len() <= 8);
    let events = names.len() as u8;
    let mut masks: Vec<[u32; 1]> = Vec::new();
    let mut automata = Vec::new();
    let mut block = Vec::new();
    let mut starts = Vec::new();
    for s in specs {
        let hs = handles(s);
        let start = u16::try_from(block.len()).unwrap();
        starts.push(start);
        for q in order(s) {
            let mut out: Vec<_> = s.transitions.iter().filter(|t| t.0 == q).collect();
            out.sort_by_key(|t| t.1);
            let mask = [bits(out.iter().map(|t| t.1))];
            let id = masks.iter().position(|m| *m == mask).unwrap_or_else(|| {
                masks.push(mask);
                masks.len() - 1
            });
            block.push(u8::try_from(id).unwrap());
            block.extend(out.iter().map(|t| u8::try_from(hs[t.2]).unwrap()));
        }
        let alphabet = [bits(s.alphabet.iter().copied())];
        automata.push(Automaton { alphabet, start, scale: 1 });
    }
    // At most 8 automata: one byte per holder mask.
    assert!(specs.len() <= 8);
    let holders: Vec<u8> = (0..events)
        .map(|e| specs.iter().enumerate().filter(|(_, s)| s.alphabet.contains(&e)).map(|(i, _)| 1 << i).sum())
        .collect();
    let owner: Vec<u8> = (0..events)
        .map(|e| {
            let plant = specs.iter().position(|s| s.role == Role::Plant && s.alphabet.contains(&e));
            match plant {
                Some(p) if controllable[usize::from(e)] => p as u8,
                _ => NO_OWNER,
            }
        })
        .collect();
    let plants = specs.iter().take_while(|s| s.role == Role::Plant).count();
    let plant_events: Vec<[u32; 1]> =
        (0..plants).map(|i| [bits((0..events).filter(|&e| owner[usize::from(e)] == i as u8))]).collect();
    let mut sites = Vec::new();
    for (i, s) in specs.iter().enumerate().take(plants) {
        for (st, &h) in handles(s).iter().enumerate() {
            let n = s.transitions.iter().filter(|t| t.0 == st && owner[usize::from(t.1)] == i as u8).count();
            if n >= 2 {
                sites.push(starts[i] + h);
            }
        }
    }
    sites.sort_unstable();
    Box::leak(Box::new(SupervisorSet {
        controllable: [bits((0..events).filter(|&e| controllable[usize::from(e)]))],
        plants: plants as u8,
        automata: leak(automata),
        block: leak(block),
        wide: false,
        // At most 8 events: a byte per mask, then the padding of a whole word.
        masks: leak(masks.iter().map(|m| m[0] as u8).chain([0; 3]).collect()),
        mask_bytes: 1,
        holders: leak(holders),
        plant_events: leak(plant_events),
        sites: leak(sites),
    }))
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
