//! This module is the home of the `offset` layout: the memory-safe records with targets stored as
//! record offsets, the offset-addressed variant the design notes ask the size report to show (and the
//! runtime's table before [`ranked`](super::ranked) replaced it).
//!
//! Each automaton is one byte block. For every state in index order: one count byte `n`, then `n` records
//! `[global event id][target offset, u16 big-endian]`, where the target is the byte offset of the target
//! state's count byte within the same block. It is the memory-safe vector with state indices replaced by
//! record offsets: the same Σs + 3Σt bytes, but a step is one jump instead of a walk over k records.
//!
//! Side tables: per automaton its initial offset (2 bytes) and its alphabet (⌈e/32⌉ words); for the set the
//! controllability bitset (⌈e/32⌉ words) and the event names.
//!
//! Limits: at most 256 events, 255 transitions out of one state, 65 536 bytes per block.

use firmware::build::bitset;

use super::{decoded::Recovered, DecodeError, Measure, Names, PackError, PackSet, Size};
use crate::model::Automaton;

/// Layout name, as given to `--layout`.
pub const NAME: &str = "offset";
/// Most events the one-byte event field numbers.
pub const MAX_EVENTS: usize = 256;
/// Most transitions the one-byte count holds.
pub const MAX_TRANSITIONS_PER_STATE: usize = 255;
/// Longest block the u16 offsets address (the last count byte sits at 65 535 at most).
pub const MAX_BLOCK_BYTES: usize = 65_536;

/// A set in the `offset` layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Packed {
    /// Names of the events and automata (not counted).
    pub names: Names,
    /// Bitset over global event ids: the controllable ones.
    pub controllable: Vec<u32>,
    /// Plants first, then supervisors.
    pub automata: Vec<Block>,
}

/// One automaton in the `offset` layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    /// Offset of the initial state's count byte in [`Block::block`].
    pub initial: u16,
    /// The states and transitions (see the module documentation).
    pub block: Vec<u8>,
    /// Bitset over global event ids: the automaton's alphabet.
    pub alphabet: Vec<u32>,
}

impl Measure for Packed {
    /// Bytes per automaton and of each side table (bitsets in whole u32 words, as the runtime holds them).
    fn size(&self) -> Size {
        let n = self.automata.len();
        Size {
            layout: NAME,
            per_automaton: self.names.with_bytes(self.automata.iter().map(|b| b.block.len())),
            side_tables: vec![
                ("controllability", 4 * self.controllable.len()),
                ("automaton offsets", 4 * n),
                ("initial states", 2 * n),
                ("alphabets", self.automata.iter().map(|b| 4 * b.alphabet.len()).sum()),
            ],
        }
    }
}

/// Packs `set` in the `offset` layout, or says which limit it breaks.
pub fn encode(set: &PackSet) -> Result<Packed, PackError> {
    let events = set.events();
    if events.len() > MAX_EVENTS {
        return Err(PackError::TooManyEvents { layout: NAME, events: events.len(), limit: MAX_EVENTS });
    }
    let mut automata = Vec::with_capacity(set.members().len());
    for m in set.members() {
        let mut offsets = Vec::with_capacity(m.state_count());
        let mut at = 0usize;
        for s in 0..m.state_count() {
            let degree = m.degree(s);
            if degree > MAX_TRANSITIONS_PER_STATE {
                return Err(PackError::TooManyTransitions {
                    layout: NAME,
                    automaton: m.name().to_owned(),
                    state: m.automaton.states[s].name.clone(),
                    transitions: degree,
                    limit: MAX_TRANSITIONS_PER_STATE,
                });
            }
            offsets.push(at);
            at += 1 + 3 * degree;
        }
        if at > MAX_BLOCK_BYTES {
            return Err(PackError::BlockTooLarge {
                layout: NAME,
                automaton: m.name().to_owned(),
                bytes: at,
                limit: MAX_BLOCK_BYTES,
            });
        }
        // Every offset is below `at` ≤ 65 536, every count ≤ 255 and every event id < 256: the casts
        // below cannot truncate.
        let mut block = Vec::with_capacity(at);
        for s in 0..m.state_count() {
            block.push(m.degree(s) as u8);
            for (e, t) in m.out(s) {
                block.push(e.index() as u8);
                block.extend_from_slice(&(offsets[t.index()] as u16).to_be_bytes());
            }
        }
        automata.push(Block {
            initial: offsets[m.initial().index()] as u16,
            block,
            alphabet: bitset::from_ids(m.alphabet().iter().map(|e| e.index()), events.len()),
        });
    }
    Ok(Packed {
        names: Names::of(set),
        controllable: bitset::from_ids(
            events.ids().filter(|&e| events.is_controllable(e)).map(|e| e.index()),
            events.len(),
        ),
        automata,
    })
}

/// Reads `packed` back into automata (plants first), checking every offset and event id.
///
/// States are named by index and unmarked: layouts keep no marking, the runtime needs none.
pub fn decode(packed: &Packed) -> Result<Vec<Automaton>, DecodeError> {
    packed.automata.iter().enumerate().map(|(a, b)| decode_block(a, b, packed)).collect()
}

fn decode_block(a: usize, b: &Block, packed: &Packed) -> Result<Automaton, DecodeError> {
    let (name, role) = packed.names.automaton(a)?;
    let what = || name.to_owned();
    let bytes = &b.block;
    // First pass: where each state starts.
    let mut starts = Vec::new();
    let mut at = 0usize;
    while at < bytes.len() {
        starts.push(at);
        at += 1 + 3 * usize::from(bytes[at]);
    }
    if at != bytes.len() {
        return Err(DecodeError::Truncated { what: what(), at: bytes.len() });
    }
    let state_at = |offset: usize, at: usize| {
        starts.binary_search(&offset).map_err(|_| DecodeError::BadState { what: what(), at, target: offset })
    };
    let mut edges = Vec::new();
    for (s, &start) in starts.iter().enumerate() {
        let n = usize::from(bytes[start]);
        let mut seen = Vec::with_capacity(n);
        for r in 0..n {
            let at = start + 1 + 3 * r;
            let event = usize::from(bytes[at]);
            if !bitset::contains(&b.alphabet, event) {
                return Err(DecodeError::BadEvent { what: what(), at, event });
            }
            if seen.contains(&event) {
                return Err(DecodeError::Nondeterministic { what: what(), state: s, event });
            }
            seen.push(event);
            let target = usize::from(u16::from_be_bytes([bytes[at + 1], bytes[at + 2]]));
            edges.push((s, event, state_at(target, at + 1)?));
        }
    }
    let initial = state_at(usize::from(b.initial), 0)?;
    Recovered {
        name,
        role,
        alphabet: bitset::ids(&b.alphabet).collect(),
        states: starts.len(),
        initial,
        edges,
    }
    .build(&packed.names.events, &packed.controllable)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::testing::assert_round_trip;

    #[test]
    fn toggle_is_two_records() {
        // Two records of one transition each: count, event, u16 big-endian offset.
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.automata[0].block, [1, 0, 0, 4, 1, 1, 0, 0]);
        assert_eq!(packed.automata[0].alphabet, [0b11]);
        assert_eq!(packed.automata[0].initial, 0);
        assert_eq!(packed.controllable, [0b01]);
        assert_eq!(packed.names.events, ["a", "b"]);
    }

    #[test]
    fn decode_inverts_encode() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S")]).unwrap();
        assert_round_trip(&set, &decode(&encode(&set).unwrap()).unwrap());
    }

    proptest::proptest! {
        #[test]
        fn corrupted_blocks_never_panic(set in crate::pack::testing::arb_set(8), edits in proptest::collection::vec((0usize..4096, proptest::num::u8::ANY), 1..6)) {
            let mut packed = encode(&set).unwrap();
            for b in &mut packed.automata {
                crate::pack::testing::corrupt(&mut b.block, &edits);
            }
            // Corruption is either reported or still decodes to valid automata; it never panics.
            if let Ok(automata) = decode(&packed) {
                for a in automata {
                    proptest::prop_assert_eq!(a.validate(), Ok(()));
                }
            }
        }
        #[test]
        fn random_sets_round_trip_and_size_formula(set in crate::pack::testing::arb_set(8)) {
            let packed = encode(&set).unwrap();
            assert_round_trip(&set, &decode(&packed).unwrap());
            proptest::prop_assert_eq!(packed.size().blocks(), set.state_count() + 3 * set.transition_count());
        }
    }

    #[test]
    fn corrupt_offset_is_reported() {
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let mut packed = encode(&set).unwrap();
        packed.automata[0].block[3] = 5;
        let err = decode(&packed).unwrap_err();
        assert_eq!(err, DecodeError::BadState { what: "T".into(), at: 2, target: 5 });
    }

    #[test]
    fn limits_are_refused_with_numbers() {
        use crate::model::{Automaton, Kind};
        let mut wide = Automaton::new("W", Kind::Plant);
        let s = wide.add_state("hub", true).unwrap();
        wide.initial = Some(s);
        for i in 0..257 {
            let e = wide.add_event(format!("e{i}"), false).unwrap();
            if i < 256 {
                wide.add_transition(s, e, s);
            }
        }
        let err = encode(&PackSet::new(vec![wide.clone()], vec![]).unwrap()).unwrap_err();
        assert_eq!(err.to_string(), "layout offset: the set has 257 events, more than the limit of 256");
        wide.events.pop();
        let err = encode(&PackSet::new(vec![wide], vec![]).unwrap()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "layout offset: state 'hub' of 'W' has 256 outgoing transitions, more than the limit of 255"
        );
    }

    #[test]
    fn block_over_64_kib_is_refused() {
        use crate::model::{Automaton, Kind};
        // A ring of 21 846 states with 1 transition each: 4 bytes per state, 87 384 bytes.
        let mut ring = Automaton::new("R", Kind::Plant);
        let e = ring.add_event("e", false).unwrap();
        let n = 21_846;
        for i in 0..n {
            ring.add_state(i.to_string(), false).unwrap();
        }
        ring.initial = Some(crate::model::StateId::from_u32(0));
        for i in 0..n {
            ring.add_transition(
                crate::model::StateId::from_u32(i),
                e,
                crate::model::StateId::from_u32((i + 1) % n),
            );
        }
        let err = encode(&PackSet::new(vec![ring], vec![]).unwrap()).unwrap_err();
        assert!(matches!(err, PackError::BlockTooLarge { bytes: 87_384, limit: 65_536, .. }), "{err}");
    }
}
