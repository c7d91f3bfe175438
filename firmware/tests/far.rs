//! Sets past 64 KiB: random sets with two automata of 10 000 to 14 000 states each, whose tables take
//! more than 64 KiB (8 KiB of `compact` bits) in every layout, encoded with 32-bit positions (and wide
//! fields where the layout needs them: 2-byte handles in `ranked` and `indexed`, 4-byte targets in
//! `offset`), read off the image the firmware compiles and run against the definition
//! (`common::definition`) under two policies — the initial states far in the tables and the targets
//! spread over them, so that the runtime's positions and reads cross 64 KiB.

mod common;

use common::definition::{agree, Op};
use common::{encode_in, packed, Role, Spec};
use firmware::build::Layout;
use firmware::choice::{Choose, First, RandomLocalQueue};
use firmware::fault::FaultPolicy;
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Runtime};
use firmware::table::{layout as id, CheckedSet};
use proptest::prelude::*;

const NAMES: [&str; 6] = ["e0", "e1", "e2", "e3", "e4", "e5"];

/// An automaton of `states` states drawn from `seed`: a random alphabet of 4 to 6 of the 6 events, each
/// event of it leaving each state with probability ½ for a random state (so that an `offset` automaton
/// spans more than 64 KiB); initially in the last state.
fn large(role: Role, states: usize, seed: u64) -> Spec {
    let mut x = seed | 1;
    let mut next = move || {
        // xorshift64: the test's draws depend on no crate's version.
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let alphabet: Vec<u8> = loop {
        let bits = next() % 64;
        if bits.count_ones() >= 4 {
            break (0..6u8).filter(|&e| bits >> e & 1 == 1).collect();
        }
    };
    let mut transitions = Vec::new();
    for s in 0..states {
        for &e in &alphabet {
            if next() % 2 == 0 {
                transitions.push((s, e, (next() % states as u64) as usize));
            }
        }
    }
    Spec { role, states, initial: states - 1, transitions, alphabet }
}

/// A small automaton over 2 events drawn from `seed`: 3 states, a cycle.
fn small(role: Role, seed: u64) -> Spec {
    let (a, b) = ((seed % 6) as u8, ((seed / 6) % 6) as u8);
    let alphabet = if a == b { vec![a] } else { vec![a.min(b), a.max(b)] };
    let transitions = (0..3).map(|s| (s, alphabet[s % alphabet.len()], (s + 1) % 3)).collect();
    Spec { role, states: 3, initial: 1, transitions, alphabet }
}

/// A large plant, a small plant, a large supervisor and a small supervisor, and which events are
/// controllable.
fn sets() -> impl Strategy<Value = (Vec<Spec>, Vec<bool>)> {
    (10_000usize..14_000, 10_000usize..14_000, any::<u64>(), proptest::collection::vec(any::<bool>(), 6))
        .prop_map(|(plant, sup, seed, controllable)| {
            let specs = vec![
                large(Role::Plant, plant, seed),
                small(Role::Plant, seed >> 8),
                large(Role::Supervisor, sup, seed.rotate_left(32) ^ 0x9e37_79b9),
                small(Role::Supervisor, seed >> 16),
            ];
            (specs, controllable)
        })
}

/// The runtime on `specs` in layout `LAYOUT` (masks of `MASK` bytes, wide fields exactly when `WIDE`),
/// with 32-bit positions, against the definition under two policies.
fn far<const MASK: usize, const LAYOUT: u8, const WIDE: bool>(
    specs: &[Spec],
    controllable: &[bool],
    ops: &[Op],
) -> Result<(), TestCaseError> {
    let layout = Layout::of_id(LAYOUT).unwrap();
    let tables = packed(layout, &NAMES, controllable, specs);
    prop_assert_eq!((tables.position_bytes, tables.wide), (4, WIDE));
    // The handles of every state in the set's own tables (fields as wide as the set's).
    let handles: Vec<Vec<usize>> = (0..specs.len()).map(|a| tables.handles(a).unwrap()).collect();
    let set = encode_in::<u32>(layout, &NAMES, controllable, specs);
    let checked = CheckedSet::<1, 4, WIDE, MASK, LAYOUT, u32>::new(set).unwrap();
    // The large supervisor's states reach beyond 16-bit positions.
    let last = handles[2].iter().max().map_or(0, |&h| u32::try_from(h).unwrap());
    prop_assert!(set.position(&set.automata[2], last) > 0xFFFF);
    run(checked, First, specs, controllable, ops, &handles)?;
    run(checked, RandomLocalQueue::<1, 8>::default(), specs, controllable, ops, &handles)
}

/// The runtime on `checked` choosing with `policy`, against the definition.
fn run<P: Choose<1>, const MASK: usize, const LAYOUT: u8, const WIDE: bool>(
    checked: CheckedSet<'static, 1, 4, WIDE, MASK, LAYOUT, u32>,
    policy: P,
    specs: &[Spec],
    controllable: &[bool],
    ops: &[Op],
    handles: &[Vec<usize>],
) -> Result<(), TestCaseError> {
    let config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 5 };
    let mut rt = Runtime::new(checked, config, policy, SeedEntropy::new(9));
    agree(&mut rt, 6, specs, controllable, ops, handles)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases(6)))]

    #[test]
    fn ranked_sets_past_64_kib_agree_with_the_definition((specs, controllable) in sets(), ops in common::definition::ops(6)) {
        far::<1, { id::RANKED }, true>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn indexed_sets_past_64_kib_agree_with_the_definition((specs, controllable) in sets(), ops in common::definition::ops(6)) {
        far::<4, { id::INDEXED }, true>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn memory_safe_sets_past_64_kib_agree_with_the_definition((specs, controllable) in sets(), ops in common::definition::ops(6)) {
        far::<0, { id::MEMORY_SAFE }, false>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn offset_sets_past_64_kib_agree_with_the_definition((specs, controllable) in sets(), ops in common::definition::ops(6)) {
        far::<0, { id::OFFSET }, true>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn compact_sets_past_64_kib_agree_with_the_definition((specs, controllable) in sets(), ops in common::definition::ops(6)) {
        far::<0, { id::COMPACT }, false>(&specs, &controllable, &ops)?;
    }
}
