//! The runtime against a brute-force reference on random small sets (`common::definition`): the same
//! states after every input, every fired event enabled by the definition (every automaton holding it can
//! take it), idle exactly when nothing is enabled, the same counters — under every choice policy, in every
//! record layout; and corrupted tables of every layout refused by the check or read in bounds. Sets past
//! 64 KiB: `far.rs`.

mod common;

use std::cell::Cell;

use common::definition::{agree, Op};
use common::Role;
use common::{encode_in, handles_in, Spec};
use firmware::build::Layout;
use firmware::choice::{Choose, First, GlobalQueue, LocalQueue, Random, RandomGlobalQueue, RandomLocalQueue};
use firmware::fault::FaultPolicy;
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Runtime};
use firmware::table::{layout as id, CheckedSet};
use proptest::prelude::*;

const NAMES: [&str; 6] = ["e0", "e1", "e2", "e3", "e4", "e5"];

/// A random deterministic automaton over the 6 events.
fn spec(role: Role) -> impl Strategy<Value = Spec> {
    (1usize..5, proptest::collection::vec(any::<bool>(), 6)).prop_flat_map(move |(states, alpha)| {
        let alphabet: Vec<u8> = (0..6u8).filter(|&e| alpha[usize::from(e)]).collect();
        let cells = states * alphabet.len();
        (
            Just(states),
            Just(alphabet),
            proptest::collection::vec(proptest::option::weighted(0.6, 0..states), cells),
        )
            .prop_map(move |(states, alphabet, targets)| {
                let mut transitions = Vec::new();
                for s in 0..states {
                    for (i, &e) in alphabet.iter().enumerate() {
                        if let Some(t) = targets[s * alphabet.len() + i] {
                            transitions.push((s, e, t));
                        }
                    }
                }
                Spec { role, states, initial: states / 2, transitions, alphabet }
            })
    })
}

/// Inputs over the 6 events and one more (an unknown byte), and decisions.
fn ops() -> impl Strategy<Value = Vec<Op>> {
    common::definition::ops(6)
}

/// The encoder's layout of the runtime's layout id `LAYOUT`.
fn layout<const LAYOUT: u8>() -> Layout {
    Layout::of_id(LAYOUT).unwrap()
}

/// The runtime on `specs` in the layout `LAYOUT` (masks of `MASK` bytes: 1 ranked, 4 indexed, 0 for the
/// layouts without a pool) against the definition, choosing with `P`.
fn check<P: Choose<1> + Default, const MASK: usize, const LAYOUT: u8>(
    specs: &[Spec],
    controllable: &[bool],
    ops: &[Op],
) -> Result<(), TestCaseError> {
    let layout = layout::<LAYOUT>();
    let set = encode_in(layout, &NAMES, controllable, specs);
    let config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 5 };
    // N is fixed at 4 here: pad with automata that hold nothing.
    let mut rt = Runtime::new(
        CheckedSet::<1, 4, false, MASK, LAYOUT>::new(set).unwrap(),
        config,
        P::default(),
        SeedEntropy::new(9),
    );
    let handles: Vec<Vec<usize>> = specs.iter().map(|s| handles_in(layout, s)).collect();
    agree(&mut rt, 6, specs, controllable, ops, &handles)
}

fn sets() -> impl Strategy<Value = (Vec<Spec>, Vec<bool>)> {
    (
        proptest::collection::vec(spec(Role::Plant), 2),
        proptest::collection::vec(spec(Role::Supervisor), 2),
        proptest::collection::vec(any::<bool>(), 6),
    )
        .prop_map(|(plants, sups, controllable)| (plants.into_iter().chain(sups).collect(), controllable))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases(128)))]

    #[test]
    fn runtime_agrees_with_the_definition_under_every_policy((specs, controllable) in sets(), ops in ops()) {
        every_policy::<1, { id::RANKED }>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn indexed_runtime_agrees_with_the_definition_under_every_policy(
        (specs, controllable) in sets(),
        ops in ops(),
    ) {
        every_policy::<4, { id::INDEXED }>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn memory_safe_runtime_agrees_with_the_definition_under_every_policy(
        (specs, controllable) in sets(),
        ops in ops(),
    ) {
        every_policy::<0, { id::MEMORY_SAFE }>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn offset_runtime_agrees_with_the_definition_under_every_policy(
        (specs, controllable) in sets(),
        ops in ops(),
    ) {
        every_policy::<0, { id::OFFSET }>(&specs, &controllable, &ops)?;
    }

    #[test]
    fn compact_runtime_agrees_with_the_definition_under_every_policy(
        (specs, controllable) in sets(),
        ops in ops(),
    ) {
        every_policy::<0, { id::COMPACT }>(&specs, &controllable, &ops)?;
    }
}

/// [`check`] under each of the six policies, in the layout `LAYOUT` (masks of `MASK` bytes).
fn every_policy<const MASK: usize, const LAYOUT: u8>(
    specs: &[Spec],
    controllable: &[bool],
    ops: &[Op],
) -> Result<(), TestCaseError> {
    check::<First, MASK, LAYOUT>(specs, controllable, ops)?;
    check::<Random, MASK, LAYOUT>(specs, controllable, ops)?;
    check::<GlobalQueue, MASK, LAYOUT>(specs, controllable, ops)?;
    check::<RandomGlobalQueue<1>, MASK, LAYOUT>(specs, controllable, ops)?;
    check::<LocalQueue<8>, MASK, LAYOUT>(specs, controllable, ops)?;
    check::<RandomLocalQueue<1, 8>, MASK, LAYOUT>(specs, controllable, ops)
}

/// Runs `ops` on `set` under the default policy if the check accepts it (and says whether it did); with
/// debug assertions every unchecked read of the runtime asserts its bounds, so a set that passed the
/// check but is read out of bounds panics.
fn exercise<const MASK: usize, const LAYOUT: u8>(
    set: &'static firmware::table::SupervisorSet<'static, 1>,
    ops: &[Op],
) -> bool {
    let config = Config { guard: false, on_fault: FaultPolicy::Continue, reseed_every: 3 };
    let policy = RandomLocalQueue::<1, 8>::default();
    let Ok(set) = CheckedSet::<1, 4, false, MASK, LAYOUT>::new(set) else { return false };
    let mut rt = Runtime::new(set, config, policy, SeedEntropy::new(3));
    for op in ops {
        match *op {
            Op::Input(e) => {
                rt.apply(e);
            }
            Op::Decide => {
                rt.decide(|| false);
            }
        }
    }
    true
}

/// Corrupted tables: the check refuses them, or the runtime runs on them within bounds. Both outcomes
/// must occur often — a check that refused everything, or a corruption the check always missed, would
/// make the property say nothing.
#[test]
fn corrupted_tables_are_refused_or_read_in_bounds() {
    corrupted::<1, { id::RANKED }>();
}

/// As [`corrupted_tables_are_refused_or_read_in_bounds`], in the `indexed` layout.
#[test]
fn corrupted_indexed_tables_are_refused_or_read_in_bounds() {
    corrupted::<4, { id::INDEXED }>();
}

/// As [`corrupted_tables_are_refused_or_read_in_bounds`], in the `memory-safe` layout.
#[test]
fn corrupted_memory_safe_tables_are_refused_or_read_in_bounds() {
    corrupted::<0, { id::MEMORY_SAFE }>();
}

/// As [`corrupted_tables_are_refused_or_read_in_bounds`], in the `offset` layout.
#[test]
fn corrupted_offset_tables_are_refused_or_read_in_bounds() {
    corrupted::<0, { id::OFFSET }>();
}

/// As [`corrupted_tables_are_refused_or_read_in_bounds`], in the `compact` layout.
#[test]
fn corrupted_compact_tables_are_refused_or_read_in_bounds() {
    corrupted::<0, { id::COMPACT }>();
}

/// Where to write `to`, the handle of state `to_state`, as target `slot` of state `from` of `spec`, in
/// `good`'s block at automaton `i` in the layout `LAYOUT` (`None`: a state without targets, or the
/// `compact` layout, whose targets are bit fields).
fn target_field<const LAYOUT: u8>(
    good: &firmware::table::SupervisorSet<'_, 1>,
    spec: &Spec,
    i: usize,
    [from, slot, to]: [usize; 3],
) -> Option<(usize, Vec<u8>)> {
    let at = good.automata[i];
    let hs = handles_in(layout::<LAYOUT>(), spec);
    let targets = if LAYOUT == id::INDEXED {
        spec.alphabet.len()
    } else {
        spec.transitions.iter().filter(|t| t.0 == from).count()
    };
    if targets == 0 {
        return None;
    }
    let slot = slot % targets;
    let record = usize::from(at.start) + hs[from] * usize::from(at.scale);
    match LAYOUT {
        id::RANKED | id::INDEXED => Some((record + 1 + slot, vec![hs[to] as u8])),
        id::MEMORY_SAFE => Some((record + 2 + 3 * slot, (to as u16).to_be_bytes().to_vec())),
        id::OFFSET => Some((record + 2 + 3 * slot, (hs[to] as u16).to_be_bytes().to_vec())),
        _ => None,
    }
}

/// Corrupts tables in the layout `LAYOUT` (masks of `MASK` bytes) and runs them.
fn corrupted<const MASK: usize, const LAYOUT: u8>() {
    let cases = common::cases(512);
    let (accepted, refused) = (Cell::new(0u32), Cell::new(0u32));
    let corruptions = (
        sets(),
        // A byte of the block set to any value, or to a copy of another of its bytes (another plausible
        // handle or mask id: what a check can miss).
        proptest::collection::vec(
            (
                any::<proptest::sample::Index>(),
                any::<u8>(),
                proptest::option::of(any::<proptest::sample::Index>()),
            ),
            1..3,
        ),
        proptest::option::weighted(0.2, (0usize..6, 0u32..4)),
        proptest::option::weighted(0.2, (any::<proptest::sample::Index>(), 0u32..32)),
        // An entry of the indexed layout's holder lists set to any value.
        proptest::option::weighted(0.2, (any::<proptest::sample::Index>(), any::<u16>())),
        // Or instead (half of the cases): a transition retargeted to another state of its automaton,
        // tables the check must accept.
        proptest::option::of(any::<[proptest::sample::Index; 4]>()),
        ops(),
    );
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig::with_cases(cases));
    let result = runner.run(
        &corruptions,
        |((specs, controllable), flips, holder_flip, mask_flip, list_flip, retarget, ops)| {
            let good = encode_in(layout::<LAYOUT>(), &NAMES, &controllable, &specs);
            let (flips, holder_flip, mask_flip, list_flip) = if retarget.is_some() && LAYOUT != id::COMPACT {
                (vec![], None, None, None)
            } else {
                (flips, holder_flip, mask_flip, list_flip)
            };
            let mut block = good.block.to_vec();
            if let Some([automaton, state, slot, to]) = retarget {
                let i = automaton.index(specs.len());
                let spec = &specs[i];
                let states = [state.index(spec.states), slot.index(256), to.index(spec.states)];
                if let Some((byte, value)) = target_field::<LAYOUT>(good, spec, i, states) {
                    block[byte..byte + value.len()].copy_from_slice(&value);
                }
            }
            for (at, value, copy_of) in &flips {
                if !block.is_empty() {
                    let i = at.index(block.len());
                    block[i] = copy_of.as_ref().map_or(*value, |j| block[j.index(block.len())]);
                }
            }
            let mut holders = good.holders.to_vec();
            if let Some((e, a)) = holder_flip {
                holders[e] ^= 1 << a;
            }
            // A bit of a mask (the padding included): the records' lengths no longer match it.
            let mut masks = good.masks.to_vec();
            if let Some((at, bit)) = mask_flip.filter(|_| !masks.is_empty()) {
                let i = at.index(masks.len());
                masks[i] ^= 1 << bit;
            }
            let mut lists = good.holder_lists.to_vec();
            if let Some((at, value)) = list_flip.filter(|_| !lists.is_empty()) {
                let i = at.index(lists.len());
                lists[i] = value;
            }
            let set = Box::leak(Box::new(firmware::table::SupervisorSet {
                block: Box::leak(block.into_boxed_slice()),
                holders: Box::leak(holders.into_boxed_slice()),
                masks: Box::leak(masks.into_boxed_slice()),
                holder_lists: Box::leak(lists.into_boxed_slice()),
                ..*good
            }));
            let changed = set.block != good.block
                || set.holders != good.holders
                || set.masks != good.masks
                || set.holder_lists != good.holder_lists;
            let ran = exercise::<MASK, LAYOUT>(set, &ops);
            if changed {
                let outcome = if ran { &accepted } else { &refused };
                outcome.set(outcome.get() + 1);
            }
            Ok(())
        },
    );
    result.unwrap_or_else(|e| panic!("{e}"));
    let (accepted, refused) = (accepted.get(), refused.get());
    eprintln!("{accepted} corrupted sets accepted, {refused} refused (of {cases}, the rest unchanged)");
    // Measured: 134 accepted, 225 refused (before the retargeting, 1 of 512 got past the check).
    assert!(
        accepted >= cases / 10,
        "only {accepted} of {} corrupted sets got past the check",
        accepted + refused
    );
    assert!(refused >= cases / 10, "only {refused} of {} corrupted sets refused", accepted + refused);
}
