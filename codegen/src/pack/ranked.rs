//! This module is the home of the `ranked` layout and of its `indexed` variant in the size report: the
//! tables the firmware runs by default (`ranked` on the Cortex-M3, `indexed` on the Cortex-M0+), laid out
//! as `firmware::table` describes and encoded by `firmware::build` ([`super::tables`]), and their decoder
//! back to automata (the encoder's test oracle).
//!
//! Their limits are the layout's (`firmware::table`); a set beyond one is refused with the number and the
//! limit ([`PackError::Layout`]).

use firmware::build::bitset;

use super::tables::{self, Block, Packed};
use super::{decoded::Recovered, DecodeError, Layout, PackError, PackSet, Role};
use crate::model::Automaton;

/// Packs `set` in the `ranked` layout, or says which limit it breaks.
pub fn encode(set: &PackSet) -> Result<Packed, PackError> {
    tables::encode(set, Layout::Ranked)
}

/// Packs `set` in the `indexed` layout, or says which limit it breaks.
pub fn encode_indexed(set: &PackSet) -> Result<Packed, PackError> {
    tables::encode(set, Layout::Indexed)
}

/// Reads `packed` back into automata (plants first), checking every mask id, target, handle, length
/// and padding byte.
///
/// States are named by index and unmarked: layouts keep no marking, the runtime needs none.
pub fn decode(packed: &Packed) -> Result<Vec<Automaton>, DecodeError> {
    let words = packed.event_names.len().div_ceil(32);
    let wrong = |what: &str, len: usize| DecodeError::Inconsistent {
        what: what.to_owned(),
        detail: format!("{len} words where {} events need {words}", packed.event_names.len()),
    };
    if packed.controllable.len() != words {
        return Err(wrong("controllability", packed.controllable.len()));
    }
    if let Some(m) = packed.masks.iter().find(|m| m.len() != words) {
        return Err(wrong("mask pool", m.len()));
    }
    let mut out = Vec::with_capacity(packed.automata.len());
    for (a, b) in packed.automata.iter().enumerate() {
        if b.alphabet.len() != words {
            return Err(wrong(&b.name, b.alphabet.len()));
        }
        let role = if a < packed.plants { Role::Plant } else { Role::Supervisor };
        out.push(decode_block(b, role, packed)?);
    }
    Ok(out)
}

fn decode_block(b: &Block, role: Role, packed: &Packed) -> Result<Automaton, DecodeError> {
    let what = || b.name.clone();
    let records = packed.walk(b)?;
    if b.initial >= records.len() {
        return Err(DecodeError::BadState { what: what(), at: 0, target: b.initial });
    }
    let handles: Vec<u16> = records.iter().map(|r| r.handle).collect();
    let state_of = |handle: u16, at: usize| {
        handles.binary_search(&handle).map(|r| records[r].state).map_err(|_| DecodeError::BadState {
            what: what(),
            at,
            target: usize::from(handle),
        })
    };
    let t_bytes = packed.field_bytes();
    let mut edges = Vec::new();
    for r in &records {
        // `walk` checked the id.
        let mask = packed.out_mask(b, r.mask).unwrap_or_default();
        for (i, (e, &t)) in bitset::ids(&mask).zip(&r.targets).enumerate() {
            if !bitset::contains(&b.alphabet, e) {
                return Err(DecodeError::BadEvent { what: what(), at: r.at, event: e });
            }
            // The target's field: its rank in the mask, or its place in the alphabet (`indexed`).
            let field =
                if packed.indexed() { bitset::ids(&b.alphabet).position(|x| x == e).unwrap_or(i) } else { i };
            edges.push((r.state, e, state_of(t, r.at + (1 + field) * t_bytes)?));
        }
    }
    Recovered {
        name: &b.name,
        role,
        alphabet: bitset::ids(&b.alphabet).collect(),
        states: records.len(),
        initial: b.initial,
        edges,
    }
    .build(&packed.event_names, &packed.controllable)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::model::{Automaton as Model, Kind, StateId};
    use crate::pack::testing::{arb_set, assert_round_trip, corrupt};
    use firmware::build::image::{check, CheckError};
    use firmware::build::{extent, HostTables, NARROW_HANDLE, WIDE_HANDLE};
    use firmware::table::SupervisorSet;

    /// The firmware's check on the image of `packed`, as the build script runs it.
    fn runtime_check(packed: &Packed) -> Result<(), CheckError> {
        check(&tables::image(packed).unwrap())
    }

    /// Runs `f` on the firmware's view of `packed` (one-word bitsets, 16-bit positions), read off its
    /// image.
    fn with_runtime_set<R>(packed: &Packed, f: impl FnOnce(&SupervisorSet<'_, 1>) -> R) -> R {
        let host = HostTables::<1>::new(packed.clone()).unwrap();
        f(&host.set())
    }

    /// The firmware's check passes on `packed`, and every step it reads is the set's transition, handle
    /// for handle.
    fn assert_runtime_steps(set: &PackSet, packed: &Packed) {
        assert_eq!(runtime_check(packed), Ok(()));
        with_runtime_set(packed, |rt| {
            for (a, m) in set.members().iter().enumerate() {
                let mut handles = vec![0u16; m.state_count()];
                for r in packed.records(a).unwrap() {
                    handles[r.state] = r.handle;
                }
                assert_eq!(handles[m.initial().index()], 0);
                for s in 0..m.state_count() {
                    for e in 0..set.events().len() {
                        let want = m.out(s).find(|(ev, _)| ev.index() == e).map(|(_, t)| handles[t.index()]);
                        assert_eq!(rt.step(a, handles[s], e as u8), want, "{} state {s} event {e}", m.name());
                    }
                }
            }
        });
    }

    #[test]
    fn toggle_matches_the_runtime_example() {
        // `firmware/src/runtime.rs`'s example: masks {a} (id 0) and {b} (id 1), records [id][target],
        // so state 1 is handle 2 at scale 1.
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.masks, [vec![0b01], vec![0b10]]);
        let b = &packed.automata[0];
        assert_eq!((b.initial, b.scale, packed.wide), (0, 1, false));
        assert_eq!(b.block, [0, 2, 1, 0]);
        assert_eq!(b.alphabet, [0b11]);
        assert_eq!(packed.controllable, [0b01]);
        assert_eq!(packed.event_names, ["a", "b"]);
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn the_pool_is_shared() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S")]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.masks.len(), 2);
        assert_eq!(packed.automata[1].block, [0, 2, 1, 0]);
        assert_round_trip(&set, &decode(&packed).unwrap());
        let size = tables::size(&packed).unwrap();
        assert_eq!(size.blocks(), 8);
        // Two 1-byte masks and 3 bytes of padding to read a whole word, in whole words; two descriptors
        // (alphabet word, 2-byte start, scale, padding); the controllable word. Besides: the plant's
        // events and a holder byte per event.
        assert_eq!(
            size.side_tables,
            [
                ("mask pool", 8),
                ("automaton descriptors", 16),
                ("initial states", 0),
                ("holder lists", 0),
                ("controllability", 4)
            ]
        );
        assert_eq!(size.shared, [("plant events", 4), ("choice sites", 0), ("holders", 2)]);
        // Indexed: a target per event of the alphabet (2 of them), word masks, per event the list of
        // its holders with its place (automata 0 and 1 hold a at place 0, b at place 1).
        let indexed = encode_indexed(&set).unwrap();
        assert_eq!(indexed.automata[1].block, [0, 3, 0, 1, 0, 0]);
        assert_eq!(indexed.mask_pool(), [0b01, 0b10]);
        assert_eq!(indexed.holder_lists(), [3, 5, 7, 0x0000, 0x0001, 0x0100, 0x0101]);
        assert_round_trip(&set, &decode(&indexed).unwrap());
        assert_eq!(tables::size(&indexed).unwrap().layout, "indexed");
    }

    /// A ring of `n` states over one event: records of 2 bytes (1-byte handles) or 3 (2-byte).
    fn ring(n: u32) -> Model {
        let mut ring = Model::new("R", Kind::Plant);
        let e = ring.add_event("e", false).unwrap();
        for i in 0..n {
            ring.add_state(i.to_string(), i == 0).unwrap();
        }
        ring.initial = Some(StateId::from_u32(0));
        for i in 0..n {
            ring.add_transition(StateId::from_u32(i), e, StateId::from_u32((i + 1) % n));
        }
        ring
    }

    #[test]
    fn the_smaller_of_scaled_narrow_and_wide_handles_is_chosen() {
        // 256 states of 2 bytes: narrow at scale 2 (512 bytes) beats wide at scale 1 (1024).
        let set = PackSet::new(vec![ring(256)], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        let b = &packed.automata[0];
        assert_eq!((b.scale, packed.wide, b.block.len()), (2, false, 512));
        assert_eq!(packed.padding(0), Ok(0));
        assert_runtime_steps(&set, &packed);
        // 1000 states: narrow needs scale 8 (8000 bytes), wide (2-byte ids and handles) takes 4000.
        let set = PackSet::new(vec![ring(1000)], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        let b = &packed.automata[0];
        assert_eq!((b.scale, packed.wide, b.block.len()), (1, true, 4000));
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn the_scale_fits_the_records_with_the_initial_state_first() {
        // States 0..127 each with one 2-byte record (a → next), state 127 with five events back to 0
        // (6 bytes). In index order the last record starts at byte 254, a 1-byte handle at scale 1; with
        // the initial state 127 first it starts at 6 + 126 · 2 = 258, so the scale must be 2.
        let mut m = Model::new("P", Kind::Plant);
        for i in 0..128u32 {
            m.add_state(i.to_string(), false).unwrap();
        }
        m.initial = Some(StateId::from_u32(127));
        let a = m.add_event("a", false).unwrap();
        for i in 0..127u32 {
            m.add_transition(StateId::from_u32(i), a, StateId::from_u32(i + 1));
        }
        for k in 0..5 {
            let e = m.add_event(format!("b{k}"), false).unwrap();
            m.add_transition(StateId::from_u32(127), e, StateId::from_u32(0));
        }
        let set = PackSet::new(vec![m], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!((packed.wide, packed.automata[0].scale), (false, 2));
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn a_set_without_events_still_has_a_mask_byte_per_mask() {
        let mut lone = Model::new("L", Kind::Plant);
        let q = lone.add_state("q", true).unwrap();
        lone.initial = Some(q);
        let set = PackSet::new(vec![lone], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.mask_pool(), [0]);
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn one_automaton_beyond_narrow_handles_makes_every_block_wide() {
        // The ring needs 2-byte handles; the toggle then takes 2-byte fields too: [id][target] × 2.
        let set = PackSet::new(vec![ring(1000), toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert!(packed.wide);
        assert_eq!(packed.automata[1].block, [1, 0, 4, 0, 2, 0, 0, 0]);
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    /// A ring of 150 states with a self-loop on a second event at every odd state: records of 2 and 3
    /// bytes alternately, the last one of 3.
    fn padded_ring() -> PackSet {
        let mut r = ring(150);
        let f = r.add_event("f", true).unwrap();
        for i in (1..150).step_by(2) {
            r.add_transition(StateId::from_u32(i), f, StateId::from_u32(i));
        }
        PackSet::new(vec![r], vec![]).unwrap()
    }

    #[test]
    fn padding_fills_records_up_to_the_scale() {
        // 375 bytes of records: 1-byte handles need scale 2, which pads every 3-byte record but the last
        // (the block ends right after it): 74 bytes. 2-byte fields would take 750.
        let set = padded_ring();
        let packed = encode(&set).unwrap();
        let b = &packed.automata[0];
        assert_eq!((b.scale, packed.wide), (2, false));
        assert_eq!(packed.padding(0), Ok(74));
        assert_eq!(b.block.len(), 375 + 74);
        assert_eq!(packed.records(0).unwrap().last().map(|r| r.handle), Some(223));
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn mask_ids_beyond_a_byte_make_the_set_wide() {
        // One state per subset of 9 events (self-loops on the subset's events), chained by a tenth.
        let mut a = Model::new("P", Kind::Plant);
        let events: Vec<_> = (0..10).map(|i| a.add_event(format!("e{i}"), false).unwrap()).collect();
        for s in 0..512u32 {
            a.add_state(s.to_string(), false).unwrap();
        }
        a.initial = Some(StateId::from_u32(0));
        for s in 0..512u32 {
            for (i, &e) in events[..9].iter().enumerate() {
                if s & (1 << i) != 0 {
                    a.add_transition(StateId::from_u32(s), e, StateId::from_u32(s));
                }
            }
            a.add_transition(StateId::from_u32(s), events[9], StateId::from_u32((s + 1) % 512));
        }
        let set = PackSet::new(vec![a], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.masks.len(), 512);
        assert!(packed.wide);
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn limits_are_refused_with_numbers() {
        let mut wide = Model::new("W", Kind::Plant);
        let s = wide.add_state("hub", true).unwrap();
        wide.initial = Some(s);
        for i in 0..257 {
            wide.add_event(format!("e{i}"), false).unwrap();
        }
        let err = encode(&PackSet::new(vec![wide], vec![]).unwrap()).unwrap_err();
        assert_eq!(err.to_string(), "layout ranked: the set has 257 events, more than the limit of 256");
        let err = encode(&PackSet::new(vec![ring(65_537)], vec![]).unwrap()).unwrap_err();
        assert_eq!(err.to_string(), "layout ranked: 'R' has 65537 states, more than the limit of 65536");
    }

    #[test]
    fn positions_take_32_bits_past_64_kib() {
        // 16 000 wide records of 4 bytes: the last starts at 63 996, a 16-bit position.
        let packed = encode(&PackSet::new(vec![ring(16_000)], vec![]).unwrap()).unwrap();
        assert_eq!((packed.wide, packed.position_bytes), (true, 2));
        // 20 000 of them: the last ones start beyond 65 535, and so do the second ring's of two of 9 000
        // (36 000 bytes each) back to back.
        let set = PackSet::new(vec![ring(20_000)], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.position_bytes, 4);
        assert_eq!(runtime_check(&packed), Ok(()));
        let mut second = ring(9_000);
        second.name = String::from("Q");
        let packed = encode(&PackSet::new(vec![ring(9_000), second], vec![]).unwrap()).unwrap();
        assert_eq!(packed.position_bytes, 4);
        assert_eq!(runtime_check(&packed), Ok(()));
    }

    #[test]
    fn corruption_is_reported_by_kind() {
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        let with = |f: &dyn Fn(&mut Packed)| {
            let mut p = packed.clone();
            f(&mut p);
            decode(&p).unwrap_err()
        };
        assert_eq!(
            with(&|p| p.automata[0].block[2] = 7),
            DecodeError::BadMask { what: "T".into(), at: 2, id: 7 }
        );
        assert_eq!(
            with(&|p| p.automata[0].block[1] = 1),
            DecodeError::BadState { what: "T".into(), at: 1, target: 1 }
        );
        assert_eq!(
            with(&|p| p.automata[0].block.truncate(3)),
            DecodeError::Truncated { what: "T".into(), at: 3 }
        );
        assert_eq!(
            with(&|p| p.automata[0].initial = 2),
            DecodeError::BadState { what: "T".into(), at: 0, target: 2 }
        );
        // A mask with an event outside the alphabet.
        assert_eq!(
            with(&|p| p.masks[0] = vec![0b100]),
            DecodeError::BadEvent { what: "T".into(), at: 0, event: 2 }
        );
        assert!(matches!(with(&|p| p.automata[0].scale = 0), DecodeError::Inconsistent { .. }));
        assert_eq!(
            with(&|p| p.automata[0].block.push(0)),
            DecodeError::Truncated { what: "T".into(), at: 5 }
        );
        assert!(matches!(with(&|p| p.controllable.push(0)), DecodeError::Inconsistent { .. }));
        // Padding must be 0, and the block ends with its last record.
        let mut padded = encode(&padded_ring()).unwrap();
        padded.automata[0].block[5] = 9;
        assert_eq!(decode(&padded).unwrap_err().to_string(), "R: padding byte 5 is not 0");
        padded.automata[0].block[5] = 0;
        padded.automata[0].block.push(0);
        assert_eq!(decode(&padded).unwrap_err().to_string(), "R: 1 bytes after the last record");
    }

    proptest::proptest! {
        #[test]
        fn corrupted_tables_never_panic(set in arb_set(40), edits in proptest::collection::vec((0usize..4096, proptest::num::u8::ANY), 1..6), scale in proptest::option::of(0u8..5)) {
            let mut packed = encode(&set).unwrap();
            for b in &mut packed.automata {
                corrupt(&mut b.block, &edits);
                if let Some(s) = scale {
                    b.scale = s;
                }
            }
            // Corruption is either reported or still decodes to valid automata, whose image the runtime's
            // check then accepts too; nothing panics.
            let checked = tables::image(&packed).ok().map(|image| check(&image));
            if let Ok(automata) = decode(&packed) {
                proptest::prop_assert_eq!(checked, Some(Ok(())));
                for a in automata {
                    proptest::prop_assert_eq!(a.validate(), Ok(()));
                }
            }
        }
        #[test]
        fn random_sets_round_trip_and_run_indexed(set in arb_set(60)) {
            let packed = encode_indexed(&set).unwrap();
            assert_round_trip(&set, &decode(&packed).unwrap());
            assert_runtime_steps(&set, &packed);
            proptest::prop_assert_eq!(packed.mask_width(), 4);
            for (a, (m, b)) in set.members().iter().zip(&packed.automata).enumerate() {
                // A record per state, a target per event of the alphabet, and padding.
                let records = m.state_count() * (1 + m.alphabet().len()) * packed.field_bytes();
                proptest::prop_assert_eq!(b.block.len(), records + packed.padding(a).unwrap());
            }
        }
        #[test]
        fn random_sets_round_trip_and_run(set in arb_set(60)) {
            let packed = encode(&set).unwrap();
            assert_round_trip(&set, &decode(&packed).unwrap());
            assert_runtime_steps(&set, &packed);
            for (a, (m, b)) in set.members().iter().zip(&packed.automata).enumerate() {
                // Records plus padding, and no smaller scale would do with the same handle width.
                let records = (m.state_count() + m.transition_count()) * packed.field_bytes();
                proptest::prop_assert_eq!(b.block.len(), records + packed.padding(a).unwrap());
                let last = packed.records(a).unwrap().last().map_or(0, |r| r.handle);
                let max = if packed.wide { WIDE_HANDLE } else { NARROW_HANDLE };
                proptest::prop_assert!(usize::from(last) <= max);
                if b.scale > 1 && !packed.wide {
                    // In the block's order of records (the initial state's first).
                    let order = packed.records(a).unwrap();
                    let lens: Vec<usize> = order.iter().map(|r| 1 + m.degree(r.state)).collect();
                    proptest::prop_assert!(extent(&lens, usize::from(b.scale) - 1).0 > NARROW_HANDLE);
                }
            }
        }
    }
}
