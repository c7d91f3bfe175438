//! This module is the home of the reference microcontroller tool's vector, to the byte: the firmware's
//! `memory-safe` blocks (`firmware::table::records`) back to back, then the tool's controllability
//! vector, one byte per event (1 when it is controllable).
//!
//! Per automaton, for each state in index order: one count byte `n`, then `n` records `[global event
//! id][target state index, u16 big-endian]`. Size Σs + 3Σt + e: for the six published supervisors of the
//! manufacturing cell 233 + 3·697 + 23 = 2347 bytes, the paper's figure (`tests/gen/cell.memory-safe.bin`).
//! The reference runtime finds state k by walking the records of states 0..k-1, as the firmware's
//! `memory-safe` reader does; `offset` keeps the same bytes with targets as offsets, and jumps.
//!
//! Limits: at most 256 events, 255 transitions out of one state, 65 535 states per automaton.

use firmware::build::bitset;

use super::tables::Packed;

/// The reference tool's transition vector and controllability vector of `packed` (a `memory-safe`
/// set): the paper's Σs + 3Σt + e bytes.
pub fn vector(packed: &Packed) -> Vec<u8> {
    let blocks = packed.automata.iter().flat_map(|b| b.block.iter().copied());
    let events = packed.event_names.len();
    let controllable = (0..events).map(|e| u8::from(bitset::contains(&packed.controllable, e)));
    blocks.chain(controllable).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::{tables, Layout, PackSet};

    #[test]
    fn a_toggle_pair_is_the_papers_vector() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S")]).unwrap();
        let packed = tables::encode(&set, Layout::MemorySafe).unwrap();
        assert_eq!(vector(&packed), [1, 0, 0, 1, 1, 1, 0, 0, 1, 0, 0, 1, 1, 1, 0, 0, 1, 0]);
    }

    #[test]
    fn more_states_than_a_target_indexes_are_refused_by_name() {
        use crate::model::{Automaton, Kind};
        let mut a = Automaton::new("Big", Kind::Plant);
        for i in 0..=65_535 {
            a.add_state(i.to_string(), false).unwrap();
        }
        a.initial = a.state_id("0");
        let err = tables::encode(&PackSet::new(vec![], vec![a]).unwrap(), Layout::MemorySafe).unwrap_err();
        assert_eq!(
            err.to_string(),
            "layout memory-safe: 'Big' has 65536 states, more than the limit of 65535"
        );
    }
}
