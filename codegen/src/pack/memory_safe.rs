//! This module is the home of the `memory-safe` layout: the reference microcontroller tool's vector, to the
//! byte.
//!
//! All automata back to back in one transition vector. Per automaton, for each state in index order: one
//! count byte `n`, then `n` records `[global event id][target state index, u16 big-endian]`. A second
//! vector holds one byte per event, 1 when it is controllable. Size Σs + 3Σt + e: for the six published
//! supervisors of the manufacturing cell 233 + 3·697 + 23 = 2347 bytes, the paper's figure.
//!
//! The reference runtime finds state k by walking the records of states 0..k-1, so a step costs O(s). The
//! [`offset`](super::offset) layout has the same size and no walk.
//!
//! Side tables, listed apart from the 2347: the offset of each automaton in the vector (u32 BE), its
//! initial state (u16 BE) and its alphabet (a bitset of ⌈e/8⌉ bytes, bit `e % 8` of byte `e / 8`). The
//! reference tool had no alphabets; the runtime needs them so that an event outside an automaton's
//! alphabet never blocks it.
//!
//! Limits: at most 256 events, 255 transitions out of one state, 65 535 states per automaton.

use super::{decoded::Recovered, DecodeError, Measure, Names, PackError, PackSet, Size};
use crate::model::Automaton;

/// Layout name, as given to `--layout`.
pub const NAME: &str = "memory-safe";
/// Most events the one-byte event field numbers.
pub const MAX_EVENTS: usize = 256;
/// Most transitions the one-byte count holds.
pub const MAX_TRANSITIONS_PER_STATE: usize = 255;
/// Most states the u16 target addresses, as the reference tool states it.
pub const MAX_STATES: usize = 65_535;

/// A set in the `memory-safe` layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Packed {
    /// The transition vector: every automaton's states and records, plants first.
    pub vector: Vec<u8>,
    /// One byte per global event id: 1 controllable, 0 uncontrollable.
    pub controllable: Vec<u8>,
    /// Per automaton, its place in [`Packed::vector`] and its side data.
    pub automata: Vec<Entry>,
    /// Names of the events and automata (not counted).
    pub names: Names,
}

/// Where one automaton sits in the vector, with the data the vector does not hold.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// First byte of the automaton in the vector.
    pub offset: u32,
    /// Initial state index.
    pub initial: u16,
    /// Bitset over global event ids, bytes: the automaton's alphabet.
    pub alphabet: Vec<u8>,
}

impl Packed {
    /// The transition vector followed by the controllability vector: the paper's Σs + 3Σt + e bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        [self.vector.as_slice(), self.controllable.as_slice()].concat()
    }
}

impl Measure for Packed {
    /// Bytes per automaton and of each side table.
    fn size(&self) -> Size {
        let ends = self.automata.iter().skip(1).map(|e| e.offset as usize).chain([self.vector.len()]);
        let n = self.automata.len();
        Size {
            layout: NAME,
            per_automaton: self
                .names
                .with_bytes(self.automata.iter().zip(ends).map(|(e, end)| end - e.offset as usize)),
            side_tables: vec![
                ("controllability", self.controllable.len()),
                ("automaton offsets", 4 * n),
                ("initial states", 2 * n),
                ("alphabets", self.automata.iter().map(|e| e.alphabet.len()).sum()),
            ],
        }
    }
}

/// Packs `set` in the `memory-safe` layout, or says which limit it breaks.
pub fn encode(set: &PackSet) -> Result<Packed, PackError> {
    let events = set.events();
    if events.len() > MAX_EVENTS {
        return Err(PackError::TooManyEvents { layout: NAME, events: events.len(), limit: MAX_EVENTS });
    }
    let mut vector = Vec::with_capacity(set.state_count() + 3 * set.transition_count());
    let mut automata = Vec::with_capacity(set.members().len());
    for m in set.members() {
        if m.state_count() > MAX_STATES {
            return Err(PackError::TooManyStates {
                layout: NAME,
                automaton: m.name().to_owned(),
                states: m.state_count(),
                limit: MAX_STATES,
            });
        }
        let offset = u32::try_from(vector.len()).map_err(|_| PackError::BlockTooLarge {
            layout: NAME,
            automaton: m.name().to_owned(),
            bytes: vector.len(),
            limit: u32::MAX as usize,
        })?;
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
            // Counts ≤ 255, event ids < 256 and state indices < 65 536 were checked above.
            vector.push(degree as u8);
            for (e, t) in m.out(s) {
                vector.push(e.index() as u8);
                vector.extend_from_slice(&(t.index() as u16).to_be_bytes());
            }
        }
        let mut alphabet = vec![0u8; events.len().div_ceil(8)];
        for e in m.alphabet() {
            alphabet[e.index() / 8] |= 1 << (e.index() % 8);
        }
        automata.push(Entry { offset, initial: m.initial().index() as u16, alphabet });
    }
    Ok(Packed {
        vector,
        controllable: events.ids().map(|e| u8::from(events.is_controllable(e))).collect(),
        automata,
        names: Names::of(set),
    })
}

/// Reads `packed` back into automata (plants first), checking every index and event id.
pub fn decode(packed: &Packed) -> Result<Vec<Automaton>, DecodeError> {
    let events = packed.names.events.len();
    if packed.controllable.len() != events {
        return Err(DecodeError::Inconsistent {
            what: NAME.to_owned(),
            detail: format!("{} controllability bytes for {events} events", packed.controllable.len()),
        });
    }
    let controllable = firmware::build::bitset::from_ids(
        packed.controllable.iter().enumerate().filter(|(_, &c)| c == 1).map(|(e, _)| e),
        events,
    );
    let ends = packed.automata.iter().skip(1).map(|e| e.offset as usize).chain([packed.vector.len()]);
    let mut out = Vec::with_capacity(packed.automata.len());
    for (a, (entry, end)) in packed.automata.iter().zip(ends).enumerate() {
        let (name, role) = packed.names.automaton(a)?;
        let what = || name.to_owned();
        let start = entry.offset as usize;
        let block = packed
            .vector
            .get(start..end)
            .ok_or_else(|| DecodeError::Truncated { what: what(), at: start.max(end) })?;
        let in_alphabet = |e: usize| entry.alphabet.get(e / 8).is_some_and(|b| b & (1 << (e % 8)) != 0);
        let mut edges = Vec::new();
        let mut states = 0;
        let mut at = 0;
        while at < block.len() {
            let n = usize::from(block[at]);
            let records = block
                .get(at + 1..at + 1 + 3 * n)
                .ok_or(DecodeError::Truncated { what: what(), at: start + block.len() })?;
            let mut seen = Vec::with_capacity(n);
            for (r, rec) in records.chunks_exact(3).enumerate() {
                let event = usize::from(rec[0]);
                if !in_alphabet(event) {
                    return Err(DecodeError::BadEvent { what: what(), at: start + at + 1 + 3 * r, event });
                }
                if seen.contains(&event) {
                    return Err(DecodeError::Nondeterministic { what: what(), state: states, event });
                }
                seen.push(event);
                edges.push((states, event, usize::from(u16::from_be_bytes([rec[1], rec[2]]))));
            }
            states += 1;
            at += 1 + 3 * n;
        }
        if let Some(&(s, _, target)) = edges.iter().find(|&&(_, _, t)| t >= states) {
            return Err(DecodeError::BadState { what: what(), at: s, target });
        }
        if usize::from(entry.initial) >= states {
            return Err(DecodeError::BadState { what: what(), at: 0, target: usize::from(entry.initial) });
        }
        let alphabet = (0..events).filter(|&e| in_alphabet(e)).collect();
        out.push(
            Recovered { name, role, alphabet, states, initial: usize::from(entry.initial), edges }
                .build(&packed.names.events, &controllable)?,
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::testing::{arb_set, assert_round_trip};

    #[test]
    fn toggle_pair_bytes() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S")]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.to_bytes(), [1, 0, 0, 1, 1, 1, 0, 0, 1, 0, 0, 1, 1, 1, 0, 0, 1, 0]);
        assert_eq!(packed.automata[1].offset, 8);
        assert_round_trip(&set, &decode(&packed).unwrap());
    }

    proptest::proptest! {
        #[test]
        fn corrupted_vectors_never_panic(set in arb_set(8), edits in proptest::collection::vec((0usize..4096, proptest::num::u8::ANY), 1..6)) {
            let mut packed = encode(&set).unwrap();
            crate::pack::testing::corrupt(&mut packed.vector, &edits);
            crate::pack::testing::corrupt(&mut packed.controllable, &edits);
            // Corruption is either reported or still decodes to valid automata; it never panics.
            if let Ok(automata) = decode(&packed) {
                for a in automata {
                    proptest::prop_assert_eq!(a.validate(), Ok(()));
                }
            }
        }
        #[test]
        fn random_sets_round_trip_and_size_formula(set in arb_set(8)) {
            let packed = encode(&set).unwrap();
            assert_round_trip(&set, &decode(&packed).unwrap());
            let size = packed.size();
            proptest::prop_assert_eq!(size.blocks(), set.state_count() + 3 * set.transition_count());
            proptest::prop_assert_eq!(packed.to_bytes().len(), size.blocks() + set.events().len());
            for (m, (_, bytes)) in set.members().iter().zip(&size.per_automaton) {
                proptest::prop_assert_eq!(*bytes, m.state_count() + 3 * m.transition_count());
            }
        }
    }

    #[test]
    fn too_many_states_is_refused() {
        use crate::model::{Automaton, Kind};
        let mut a = Automaton::new("Big", Kind::Plant);
        for i in 0..=MAX_STATES {
            a.add_state(i.to_string(), false).unwrap();
        }
        a.initial = a.state_id("0");
        let err = encode(&PackSet::new(vec![], vec![a]).unwrap()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "layout memory-safe: 'Big' has 65536 states, more than the limit of 65535"
        );
    }
}
