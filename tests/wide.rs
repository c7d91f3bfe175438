//! A set of the other shape than the cell's, built for the Cortex-M3 and run closed loop under QEMU:
//! 2-byte handles (a plant ring of 300 states) and 40 events (two-word event sets, 5-byte masks).

use codegen::closed_loop::Options;
use codegen::config::RuntimeConfig;
use codegen::model::{Automaton, Kind, StateId};
use codegen::pack::ranked;
use codegen::project::Project;
use end_to_end::{assert_clean, qemu_closed_loop};

/// States of the plant's ring.
const RING: u32 = 300;
/// Events: `go`, `tick` and the self-loops `x0`…
const EVENTS: u32 = 40;

/// A ring of `RING` states: `go` (controllable) leaves the even ones, `tick` (uncontrollable) the odd
/// ones; the other uncontrollable events loop on state 0.
fn plant() -> Automaton {
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
    for k in 0..EVENTS - 2 {
        let e = g.add_event(format!("x{k}"), false).unwrap();
        g.add_transition(StateId::from_u32(0), e, StateId::from_u32(0));
    }
    g
}

/// Two states over `go`: it toggles between them.
fn supervisor() -> Automaton {
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
fn wide_handles_and_two_word_event_sets_run_closed_loop_on_the_cortex_m3() {
    let project = Project::new("wide", vec![plant()], vec![supervisor()], RuntimeConfig::default()).unwrap();
    let packed = ranked::encode(&project.set).unwrap();
    assert!(packed.wide, "300 states need 2-byte handles");
    assert_eq!(packed.mask_width(), 5, "40 events: 5-byte masks, two-word event sets");
    let report = qemu_closed_loop(&project, &Options { events: 3_000, ..Options::default() });
    assert_clean(&report, "wide");
    assert!(report.full_coverage(), "{report}");
    assert!(report.marked_visits > 0, "{report}");
}
