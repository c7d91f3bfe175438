//! This module is the home of the decoder of the `compact` layout (`firmware::table::compact` describes
//! it): the firmware's blocks — header, directory, bit stream — read back into automata, every field and
//! directory entry checked: the oracle the encoder is tested against.
//!
//! An automaton with `s` states over an alphabet of `a` events costs `a` bits a state and `⌈log₂ s⌉` a
//! transition; a directory entry every 16 states bounds a step whatever `s` is.

use firmware::build::bitset;
use firmware::table::compact::{HEADER, PADDING, STRIDE};

use super::bits::{width, Reader};
use super::tables::{Block, Packed};
use super::{decoded::Recovered, DecodeError, Role};
use crate::model::Automaton;

/// Reads the blocks of `packed`, a `compact` set, back into automata (plants first), checking every
/// field and the directory.
pub fn decode(packed: &Packed) -> Result<Vec<Automaton>, DecodeError> {
    let last = packed.automata.len().saturating_sub(1);
    packed.automata.iter().enumerate().map(|(a, b)| decode_block(a, b, packed, a == last)).collect()
}

fn decode_block(a: usize, b: &Block, packed: &Packed, last: bool) -> Result<Automaton, DecodeError> {
    let what = || b.name.clone();
    let bad = |detail: String| DecodeError::Inconsistent { what: what(), detail };
    let bytes = &b.block;
    let header = bytes.get(..HEADER).ok_or(DecodeError::Truncated { what: what(), at: bytes.len() })?;
    let field = |i: usize| usize::from(u16::from_le_bytes([header[i], header[i + 1]]));
    let (s, alphabet_len, w, d, dir) =
        (field(0), field(2), u32::from(header[4]), u32::from(header[5]), field(6));
    let alphabet: Vec<usize> = bitset::ids(&b.alphabet).collect();
    if alphabet_len != alphabet.len() || w != width(s) || s == 0 {
        return Err(bad(format!("header says {s} states of {w} bits over {alphabet_len} events")));
    }
    let directory =
        bytes.get(HEADER..HEADER + dir).ok_or(DecodeError::Truncated { what: what(), at: bytes.len() })?;
    let stream_bytes = &bytes[HEADER + dir..];
    let truncated = |r: &Reader| DecodeError::Truncated { what: what(), at: HEADER + dir + r.at / 8 };
    let mut stream = Reader::new(stream_bytes, 0);
    let mut entries = Reader::new(directory, 0);
    let mut starts = Vec::with_capacity(s);
    let mut edges = Vec::new();
    for state in 0..s {
        if state > 0 && state.is_multiple_of(STRIDE) {
            let entry = entries.get(d).ok_or_else(|| truncated(&entries))?;
            if entry != stream.at {
                return Err(bad(format!(
                    "directory puts state {state} at bit {entry}, the stream at {}",
                    stream.at
                )));
            }
        }
        starts.push(stream.at);
        let mut present = Vec::new();
        for &e in &alphabet {
            if stream.get(1).ok_or_else(|| truncated(&stream))? == 1 {
                present.push(e);
            }
        }
        for e in present {
            let at = HEADER + dir + stream.at / 8;
            let target = stream.get(w).ok_or_else(|| truncated(&stream))?;
            if target >= s {
                return Err(DecodeError::BadState { what: what(), at, target });
            }
            edges.push((state, e, target));
        }
    }
    let used = stream.at.div_ceil(8);
    let spare = if last { PADDING } else { 0 };
    if stream_bytes.len() != used + spare {
        return Err(bad(format!("{} bytes of stream, {used} used", stream_bytes.len())));
    }
    // The initial state's handle is its position (states over an empty alphabet share theirs).
    let initial = Some(b.initial).filter(|&i| starts.get(i) == Some(&b.handle));
    let initial = initial.ok_or(DecodeError::BadState { what: what(), at: 0, target: b.handle })?;
    let role = if a < packed.plants { Role::Plant } else { Role::Supervisor };
    Recovered { name: &b.name, role, alphabet, states: s, initial, edges }
        .build(&packed.event_names, &packed.controllable)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::testing::{arb_set, assert_round_trip, corrupt};
    use crate::pack::{tables, Layout, PackSet};

    #[test]
    fn the_toggle_is_one_byte_of_stream() {
        // One bit per target. State 0: mask 10, target 1; state 1: mask 01, target 0 → 101 010, padded;
        // behind the header (2 states, 2 events, w 1, d 4, no directory), then 2 bytes of padding.
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let packed = tables::encode(&set, Layout::Compact).unwrap();
        assert_eq!(packed.automata[0].block, [2, 0, 2, 0, 1, 4, 0, 0, 0b1010_1000, 0, 0]);
        assert_round_trip(&set, &decode(&packed).unwrap());
    }

    proptest::proptest! {
        #[test]
        fn corrupted_blocks_never_panic(set in arb_set(20), edits in proptest::collection::vec((0usize..4096, proptest::num::u8::ANY), 1..6)) {
            let mut packed = tables::encode(&set, Layout::Compact).unwrap();
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
        #[test]
        fn random_sets_round_trip_and_size_formula(set in arb_set(40)) {
            let packed = tables::encode(&set, Layout::Compact).unwrap();
            assert_round_trip(&set, &decode(&packed).unwrap());
            let last = packed.automata.len() - 1;
            for (a, (m, b)) in set.members().iter().zip(&packed.automata).enumerate() {
                let bits = m.state_count() * m.dfa.alphabet().len() + m.transition_count() * width(m.state_count()) as usize;
                let d = usize::from(b.block[5]);
                let entries = (m.state_count() - 1) / STRIDE;
                let padding = if a == last { PADDING } else { 0 };
                proptest::prop_assert_eq!(b.block.len(), HEADER + (entries * d).div_ceil(8) + bits.div_ceil(8) + padding);
            }
        }
    }
}
