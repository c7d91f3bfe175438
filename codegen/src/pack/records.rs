//! This module is the home of the decoder of the record layouts, `memory-safe` and `offset`
//! (`firmware::table::records` describes them): the firmware's blocks read back into automata, every
//! count, event and target checked — the oracle the encoder is tested against.

use firmware::build::bitset;

use super::tables::{Block, Packed};
use super::{decoded::Recovered, DecodeError, Role};
use crate::model::Automaton;

/// Reads the blocks of `packed`, a `memory-safe` or `offset` set, back into automata (plants first).
/// States are named by index and unmarked: layouts keep no marking, the runtime needs none.
pub fn decode(packed: &Packed) -> Result<Vec<Automaton>, DecodeError> {
    packed.automata.iter().enumerate().map(|(a, b)| decode_block(a, b, packed)).collect()
}

fn decode_block(a: usize, b: &Block, packed: &Packed) -> Result<Automaton, DecodeError> {
    let what = || b.name.clone();
    let memory_safe = packed.layout == firmware::build::Layout::MemorySafe;
    let transition = packed.transition_bytes();
    let bytes = &b.block;
    // First pass: where each state starts.
    let mut starts = Vec::new();
    let mut at = 0usize;
    while at < bytes.len() {
        starts.push(at);
        at += 1 + transition * usize::from(bytes[at]);
    }
    if at != bytes.len() {
        return Err(DecodeError::Truncated { what: what(), at: bytes.len() });
    }
    // A target: a state index (`memory-safe`) or the offset of a record (`offset`).
    let state_of = |target: usize, at: usize| {
        let bad = || DecodeError::BadState { what: what(), at, target };
        if memory_safe {
            (target < starts.len()).then_some(target).ok_or_else(bad)
        } else {
            starts.binary_search(&target).map_err(|_| bad())
        }
    };
    let mut edges = Vec::new();
    for (s, &start) in starts.iter().enumerate() {
        let mut last = None;
        for r in 0..usize::from(bytes[start]) {
            let at = start + 1 + transition * r;
            let event = usize::from(bytes[at]);
            if !bitset::contains(&b.alphabet, event) {
                return Err(DecodeError::BadEvent { what: what(), at, event });
            }
            if last.is_some_and(|l| event <= l) {
                return Err(DecodeError::Nondeterministic { what: what(), state: s, event });
            }
            last = Some(event);
            let target = bytes[at + 1..at + transition].iter().fold(0, |t, &x| t << 8 | usize::from(x));
            edges.push((s, event, state_of(target, at + 1)?));
        }
    }
    let initial = if memory_safe { starts.binary_search(&b.handle).ok() } else { state_of(b.handle, 0).ok() };
    let initial = initial.filter(|&i| i == b.initial).ok_or(DecodeError::BadState {
        what: what(),
        at: 0,
        target: b.handle,
    })?;
    let role = if a < packed.plants { Role::Plant } else { Role::Supervisor };
    Recovered {
        name: &b.name,
        role,
        alphabet: bitset::ids(&b.alphabet).collect(),
        states: starts.len(),
        initial,
        edges,
    }
    .build(&packed.event_names, &packed.controllable)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::testing::{arb_set, assert_round_trip, corrupt};
    use crate::pack::{tables, Layout, PackSet};

    #[test]
    fn the_toggle_is_two_records_in_either_layout() {
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        // Count, event, u16 big-endian target: the state index, or the record's offset.
        let ms = tables::encode(&set, Layout::MemorySafe).unwrap();
        assert_eq!(ms.automata[0].block, [1, 0, 0, 1, 1, 1, 0, 0]);
        let off = tables::encode(&set, Layout::Offset).unwrap();
        assert_eq!(off.automata[0].block, [1, 0, 0, 4, 1, 1, 0, 0]);
        assert!(!off.wide);
        for packed in [ms, off] {
            assert_round_trip(&set, &decode(&packed).unwrap());
        }
    }

    proptest::proptest! {
        #[test]
        fn random_sets_round_trip_and_size_formula(set in arb_set(30)) {
            for layout in [Layout::MemorySafe, Layout::Offset] {
                let packed = tables::encode(&set, layout).unwrap();
                assert_round_trip(&set, &decode(&packed).unwrap());
                for (m, b) in set.members().iter().zip(&packed.automata) {
                    proptest::prop_assert_eq!(b.block.len(), m.state_count() + 3 * m.transition_count());
                }
            }
        }
        #[test]
        fn corrupted_records_never_panic(set in arb_set(8), edits in proptest::collection::vec((0usize..4096, proptest::num::u8::ANY), 1..6)) {
            for layout in [Layout::MemorySafe, Layout::Offset] {
                let mut packed = tables::encode(&set, layout).unwrap();
                for b in &mut packed.automata {
                    corrupt(&mut b.block, &edits);
                }
                // Corruption is either reported or still decodes to valid automata; it never panics.
                if let Ok(automata) = decode(&packed) {
                    for a in automata {
                        proptest::prop_assert_eq!(a.validate(), Ok(()));
                    }
                }
            }
        }
    }
}
