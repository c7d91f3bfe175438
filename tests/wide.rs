//! Sets of the other shape than the cell's: 2-byte handles (a plant ring of 300 states, beyond 1-byte
//! handles) and 4-byte masks (32 events) or two-word event sets (40 events). The host-compiled runtime
//! steps as the checked readers say, and the Cortex-M3 build runs closed loop under QEMU.

use codegen::closed_loop::Options;
use codegen::config::RuntimeConfig;
use codegen::model::{Automaton, Kind, StateId};
use codegen::pack::{ranked, PackSet};
use codegen::project::Project;
use end_to_end::{assert_clean, qemu_closed_loop};
use firmware::build::HostTables;
use firmware::choice::First;
use firmware::fault::FaultPolicy;
use firmware::rng::SeedEntropy;
use firmware::runtime::{Applied, Config, Decision, Runtime};
use firmware::table::{layout, CheckedSet, TableError};

/// States of the plant's ring.
const RING: u32 = 300;

/// A ring of `RING` states over `events` events: `go` (controllable) leaves the even states, `tick`
/// (uncontrollable) the odd ones; the other events, uncontrollable, loop on state 1 (where no command is
/// enabled, so they never race one).
fn ring(events: u32) -> Automaton {
    let mut g = Automaton::new("Ring", Kind::Plant);
    for i in 0..RING {
        g.add_state(i.to_string(), i == 0).unwrap();
    }
    g.initial = Some(StateId::from_u32(0));
    let go = g.add_event("go", true).unwrap();
    let tick = g.add_event("tick", false).unwrap();
    for i in 0..RING {
        let e = if i % 2 == 0 { go } else { tick };
        g.add_transition(StateId::from_u32(i), e, StateId::from_u32((i + 1) % RING));
    }
    for k in 0..events - 2 {
        let e = g.add_event(format!("x{k}"), false).unwrap();
        g.add_transition(StateId::from_u32(1), e, StateId::from_u32(1));
    }
    g
}

/// Two states over `go`: it toggles between them.
fn toggle() -> Automaton {
    let mut s = Automaton::new("Toggle", Kind::Supervisor);
    let a = s.add_state("a", true).unwrap();
    let b = s.add_state("b", false).unwrap();
    s.initial = Some(a);
    let go = s.add_event("go", true).unwrap();
    s.add_transition(a, go, b);
    s.add_transition(b, go, a);
    s
}

#[test]
fn wide_fields_and_word_masks_run_as_the_checked_readers_step() {
    let set = PackSet::new(vec![ring(32)], vec![toggle()]).unwrap();
    run_as_the_checked_readers_step::<{ layout::RANKED }>(ranked::encode(&set).unwrap());
}

#[test]
fn wide_fields_run_as_the_checked_readers_step_in_the_indexed_layout() {
    let set = PackSet::new(vec![ring(32)], vec![toggle()]).unwrap();
    run_as_the_checked_readers_step::<{ layout::INDEXED }>(ranked::encode_indexed(&set).unwrap());
}

/// The host-compiled runtime on `packed` (the ring of 32 events and the toggle, in the layout
/// `LAYOUT`): twice round the ring, every state as the checked readers step.
fn run_as_the_checked_readers_step<const LAYOUT: u8>(packed: codegen::pack::tables::Packed) {
    assert!(packed.wide);
    assert_eq!(packed.mask_width(), 4);
    let host = HostTables::<1>::new(packed).unwrap();
    let tables = host.set();
    assert_eq!(CheckedSet::<1, 2, false, 4, LAYOUT>::new(&tables).err(), Some(TableError::Shape));
    let other = if LAYOUT == layout::INDEXED {
        CheckedSet::<1, 2, true, 4, { layout::RANKED }>::new(&tables).err()
    } else {
        CheckedSet::<1, 2, true, 4, { layout::INDEXED }>::new(&tables).err()
    };
    assert_eq!(other, Some(TableError::Shape), "a runtime of the other layout");
    let checked = CheckedSet::<1, 2, true, 4, LAYOUT>::new(&tables).unwrap();
    let config = Config { guard: false, on_fault: FaultPolicy::Continue, reseed_every: 0 };
    let mut rt: Runtime<'_, First, SeedEntropy, 1, 2, true, 4, LAYOUT> =
        Runtime::new(checked, config, First, SeedEntropy::new(1));
    let event = |name: &str| -> u8 {
        let id = host.event_names().iter().position(|n| n == name).unwrap();
        u8::try_from(id).unwrap()
    };
    let (go, tick, x7) = (event("go"), event("tick"), event("x7"));
    let (mut expected, mut highest) = (rt.states(), 0);
    let advance = |states: &mut [u16; 2], e: u8| {
        for (a, h) in states.iter_mut().enumerate() {
            if tables.holders_of(e, tables.holder_bytes()).is_some_and(|m| m & (1 << a) != 0) {
                *h = tables.step(a, *h, e).unwrap();
            }
        }
    };
    // Twice round the ring: at even states `go` is fired, at odd ones `tick` arrives; at state 0 also a
    // `tick` that is unexpected there, at state 1 one of the looping events.
    for i in 0..2 * RING {
        match i % RING {
            0 => assert_eq!(rt.apply(tick), Applied::Unexpected { automaton: 0 }),
            1 => assert_eq!(rt.apply(x7), Applied::Taken),
            _ => {}
        }
        if i % 2 == 0 {
            assert_eq!(rt.decide(|| false), Decision::Fired(go));
            advance(&mut expected, go);
        } else {
            assert_eq!(rt.decide(|| false), Decision::Idle);
            assert_eq!(rt.apply(tick), Applied::Taken);
            advance(&mut expected, tick);
        }
        assert_eq!(rt.states(), expected, "step {i}");
        highest = highest.max(expected[0]);
    }
    // Back at both initial states, having passed handles that need 2 bytes.
    assert_eq!(expected, [0, 0]);
    assert!(highest > 255, "{highest}");
}

#[test]
fn wide_handles_and_two_word_event_sets_run_closed_loop_on_the_cortex_m3() {
    let project = Project::new("wide", vec![ring(40)], vec![toggle()], RuntimeConfig::default()).unwrap();
    let packed = ranked::encode(&project.set).unwrap();
    assert!(packed.wide, "300 states need 2-byte handles");
    assert_eq!(packed.mask_width(), 5, "40 events: 5-byte masks, two-word event sets");
    let report = qemu_closed_loop(&project, &Options { events: 3_000, ..Options::default() });
    assert_clean(&report, "wide");
    assert!(report.full_coverage(), "{report}");
    assert!(report.marked_visits > 0, "{report}");
}
