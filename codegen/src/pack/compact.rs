//! This module is the home of the `compact` layout: bit-packed, each automaton over its own alphabet.
//!
//! An automaton with `s` states over an alphabet of `a` events numbers its events locally `0..a` (in
//! global-id order) and needs `w = ⌈log₂ s⌉` bits for a state. Its block is one bit stream, most
//! significant bit first; per state in index order:
//!
//! * an `a`-bit mask, bit `i` set when local event `i` leaves the state;
//! * for each set bit, in order, the target state index in `w` bits.
//!
//! So a state costs `a` bits and a transition `w` bits. A directory gives the bit offset of every
//! [`STRIDE`]-th state (states 16, 32, …; state 0 starts at bit 0) in `d` bits, `d` the width of the
//! block's bit length. A step jumps to the nearest directory entry and skips at most 15 states, each by a
//! popcount of its mask: bounded work whatever `s` is, no walk over the automaton.
//!
//! Side tables: per automaton its state count and initial state (u16 each), its alphabet (⌈e/8⌉ bytes) and
//! its directory; for the set the block offsets (u32 each) and the controllability bitset (⌈e/8⌉ bytes).
//!
//! Limits: 65 535 states per automaton; no limit on events or transitions per state.

use super::bits::{width, Reader, Writer};
use firmware::build::bitset;

use super::{decoded::Recovered, DecodeError, Measure, Names, PackError, PackSet, Size};
use crate::model::Automaton;

/// Layout name, as given to `--layout`.
pub const NAME: &str = "compact";
/// Most states the u16 state count holds.
pub const MAX_STATES: usize = 65_535;
/// Every `STRIDE`-th state has a directory entry.
pub const STRIDE: usize = 16;

/// A set in the `compact` layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Packed {
    /// Bitset over global event ids, bytes (bit `e % 8` of byte `e / 8`): the controllable ones.
    pub controllable: Vec<u8>,
    /// Plants first, then supervisors.
    pub automata: Vec<Block>,
    /// Names of the events and automata (not counted).
    pub names: Names,
}

/// One automaton in the `compact` layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    /// Number of states.
    pub states: u16,
    /// Initial state index.
    pub initial: u16,
    /// Bitset over global event ids, bytes: the alphabet, whose order numbers the local events.
    pub alphabet: Vec<u8>,
    /// Bit offsets of states `STRIDE`, `2·STRIDE`, …, each in [`Block::directory_width`] bits.
    pub directory: Vec<u8>,
    /// The bit stream of masks and targets.
    pub block: Vec<u8>,
}

impl Block {
    /// Bits of one directory entry: enough for any bit offset in the block.
    pub fn directory_width(&self) -> u32 {
        width(self.block.len() * 8 + 1)
    }
}

impl Measure for Packed {
    /// Bytes per automaton and of each side table.
    fn size(&self) -> Size {
        let n = self.automata.len();
        Size {
            layout: NAME,
            per_automaton: self.names.with_bytes(self.automata.iter().map(|b| b.block.len())),
            side_tables: vec![
                ("controllability", self.controllable.len()),
                ("automaton offsets", 4 * n),
                ("state counts and initial states", 4 * n),
                ("alphabets", self.automata.iter().map(|b| b.alphabet.len()).sum()),
                ("directories", self.automata.iter().map(|b| b.directory.len()).sum()),
            ],
        }
    }
}

fn byte_set(ids: impl IntoIterator<Item = usize>, len: usize) -> Vec<u8> {
    let mut bytes = vec![0u8; len.div_ceil(8)];
    for e in ids {
        bytes[e / 8] |= 1 << (e % 8);
    }
    bytes
}

fn byte_set_ids(bytes: &[u8]) -> Vec<usize> {
    (0..bytes.len() * 8).filter(|&e| bytes[e / 8] & (1 << (e % 8)) != 0).collect()
}

/// Packs `set` in the `compact` layout, or says which limit it breaks.
pub fn encode(set: &PackSet) -> Result<Packed, PackError> {
    let events = set.events();
    let mut automata = Vec::with_capacity(set.members().len());
    for m in set.members() {
        let s = m.state_count();
        if s > MAX_STATES {
            return Err(PackError::TooManyStates {
                layout: NAME,
                automaton: m.name().to_owned(),
                states: s,
                limit: MAX_STATES,
            });
        }
        let alphabet = m.alphabet();
        let w = width(s);
        let mut stream = Writer::default();
        let mut starts = Vec::with_capacity(s / STRIDE);
        for state in 0..s {
            if state > 0 && state.is_multiple_of(STRIDE) {
                starts.push(stream.bit_len());
            }
            // `out` is sorted by global id, the order that numbers local events: one pass merges them.
            let mut next = m.out(state).peekable();
            for &e in &alphabet {
                let here = next.peek().is_some_and(|(ev, _)| *ev == e);
                stream.put(usize::from(here), 1);
                if here {
                    next.next();
                }
            }
            for (_, t) in m.out(state) {
                stream.put(t.index(), w);
            }
        }
        let block = stream.into_bytes();
        let d = width(block.len() * 8 + 1);
        let mut directory = Writer::default();
        for start in starts {
            directory.put(start, d);
        }
        automata.push(Block {
            // Checked against MAX_STATES above.
            states: s as u16,
            initial: m.initial().index() as u16,
            alphabet: byte_set(alphabet.iter().map(|e| e.index()), events.len()),
            directory: directory.into_bytes(),
            block,
        });
    }
    Ok(Packed {
        controllable: byte_set(
            events.ids().filter(|&e| events.is_controllable(e)).map(|e| e.index()),
            events.len(),
        ),
        automata,
        names: Names::of(set),
    })
}

/// Reads `packed` back into automata (plants first), checking every field and the directory.
pub fn decode(packed: &Packed) -> Result<Vec<Automaton>, DecodeError> {
    let controllable = bitset::from_ids(byte_set_ids(&packed.controllable), packed.names.events.len());
    packed.automata.iter().enumerate().map(|(a, b)| decode_block(a, b, packed, &controllable)).collect()
}

fn decode_block(
    a: usize,
    b: &Block,
    packed: &Packed,
    controllable: &[u32],
) -> Result<Automaton, DecodeError> {
    let (name, role) = packed.names.automaton(a)?;
    let what = || name.to_owned();
    let s = usize::from(b.states);
    let alphabet = byte_set_ids(&b.alphabet);
    let w = width(s);
    let d = b.directory_width();
    let truncated = |r: &Reader| DecodeError::Truncated { what: what(), at: r.at / 8 };
    let mut stream = Reader::new(&b.block, 0);
    let mut directory = Reader::new(&b.directory, 0);
    let mut edges = Vec::new();
    for state in 0..s {
        if state > 0 && state.is_multiple_of(STRIDE) {
            let entry = directory.get(d).ok_or_else(|| truncated(&directory))?;
            if entry != stream.at {
                return Err(DecodeError::Inconsistent {
                    what: what(),
                    detail: format!(
                        "directory puts state {state} at bit {entry}, the stream at {}",
                        stream.at
                    ),
                });
            }
        }
        let mut present = Vec::new();
        for &e in &alphabet {
            if stream.get(1).ok_or_else(|| truncated(&stream))? == 1 {
                present.push(e);
            }
        }
        for e in present {
            let at = stream.at / 8;
            let target = stream.get(w).ok_or_else(|| truncated(&stream))?;
            if target >= s {
                return Err(DecodeError::BadState { what: what(), at, target });
            }
            edges.push((state, e, target));
        }
    }
    if stream.at.div_ceil(8) != b.block.len() {
        return Err(DecodeError::Inconsistent {
            what: what(),
            detail: format!("{} bytes of block, {} used", b.block.len(), stream.at.div_ceil(8)),
        });
    }
    if usize::from(b.initial) >= s {
        return Err(DecodeError::BadState { what: what(), at: 0, target: usize::from(b.initial) });
    }
    Recovered { name, role, alphabet, states: s, initial: usize::from(b.initial), edges }
        .build(&packed.names.events, controllable)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::testing::{arb_set, assert_round_trip};

    #[test]
    fn toggle_is_one_byte() {
        // One bit per target. State 0: mask 10, target 1; state 1: mask 01, target 0 → 101 010, padded.
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.automata[0].block, [0b1010_1000]);
        assert_eq!(packed.controllable, [0b01]);
        assert_round_trip(&set, &decode(&packed).unwrap());
    }

    proptest::proptest! {
        #[test]
        fn corrupted_streams_never_panic(set in arb_set(20), edits in proptest::collection::vec((0usize..4096, proptest::num::u8::ANY), 1..6)) {
            let mut packed = encode(&set).unwrap();
            for b in &mut packed.automata {
                crate::pack::testing::corrupt(&mut b.block, &edits);
                crate::pack::testing::corrupt(&mut b.directory, &edits);
                crate::pack::testing::corrupt(&mut b.alphabet, &edits);
            }
            // Corruption is either reported or still decodes to valid automata; it never panics.
            if let Ok(automata) = decode(&packed) {
                for a in automata {
                    proptest::prop_assert_eq!(a.validate(), Ok(()));
                }
            }
        }
        #[test]
        fn random_sets_round_trip_and_size_formula(set in arb_set(40)) {
            let packed = encode(&set).unwrap();
            assert_round_trip(&set, &decode(&packed).unwrap());
            for (m, b) in set.members().iter().zip(&packed.automata) {
                let bits = m.state_count() * m.dfa.alphabet().len() + m.transition_count() * width(m.state_count()) as usize;
                proptest::prop_assert_eq!(b.block.len(), bits.div_ceil(8));
                let entries = (m.state_count() - 1) / STRIDE;
                proptest::prop_assert_eq!(b.directory.len(), (entries * b.directory_width() as usize).div_ceil(8));
            }
        }
    }
}
