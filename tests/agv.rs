//! Wonham's AGV system (`examples/agv/`) closed loop: the manifest's reduced set (`[runtime]
//! supervisors = "reduced"`, 183 states for the full set's 7 902, proven to keep its closed loop) built
//! for the Cortex-M3 and run under QEMU, and the Pico application on an emulated RP2040, its vehicles'
//! sensors as levels on shared pins; and the full set (7 902 states, its merged supervisor 7 800), whose
//! tables are data checked at emit time and by the build script, so it builds in about a minute from a
//! cold cache — under QEMU, and as the Pico's link build on the emulated RP2040 (its `indexed` tables,
//! 449 188 B, fit the Pico's flash only). Through the pins only safety and the zones' coverage are
//! asserted, not liveness: through pins the plant cannot make the firmware wait (the RP2040 harness has
//! no STEP there), and in real time the loop settles into a cycle that does not come back to the marked
//! state (QEMU does the same in real time without steering: `codegen run examples/agv/agv.toml --timing
//! realtime --guide 0`). Over the link build's UART0 the run is in lock-step, and liveness is asserted.

use codegen::closed_loop::Options;
use codegen::config::{SamplingSpec, SupervisorChoice};
use codegen::monitor::Report;
use codegen::project::Project;
use codegen::synth::Config;
use end_to_end::{assert_clean, example, pico_closed_loop, pico_link_closed_loop, qemu_closed_loop};

/// Events of a QEMU run (seed 1: 613 of the merged supervisor's 614 reachable controllable transitions
/// taken, every other supervisor's all), and of a Pico run (slower: the RP2040 is emulated in JavaScript).
const EVENTS: u64 = 40_000;
const PICO_EVENTS: u64 = 10_000;
/// Events of the full set's run on the RP2040 over its link (lock-step; see the test for its cost).
const PICO_LINK_EVENTS: u64 = 3_000;

/// Safe, a clean link, marked states visited throughout, and at least `percent` % of every
/// supervisor's reachable controllable transitions taken (full coverage of the 614 of the merged
/// supervisor takes more events than CI spends; `codegen run --events N` shows what is left).
fn check(report: &Report, what: &str, percent: usize) {
    eprintln!("{what}: {report}");
    assert_clean(report, what);
    assert!(report.marked_visits >= report.events / 500, "{what}: {report}");
    assert!(report.longest_marked_gap < 5_000, "{what}: {report}");
    for line in &report.coverage {
        let reachable = line.reachable.expect("reachable transitions counted");
        assert!(line.taken * 100 >= reachable * percent, "{what}: {}: {report}", line.supervisor);
    }
}

#[test]
fn the_reduced_agv_set_is_safe_live_and_fully_covered_under_qemu() {
    let project = Project::load(&example("agv/agv.toml")).unwrap();
    assert_eq!(project.deployed.choice, SupervisorChoice::Reduced);
    check(
        &qemu_closed_loop(&project, &Options { events: EVENTS, ..Options::default() }),
        "agv reduced, QEMU",
        99,
    );
}

/// The reduced set on the emulated RP2040 for `PICO_EVENTS` events, its inputs by edge interrupt.
fn pico_run() -> Report {
    let project = Project::load(&example("agv/agv.toml")).unwrap();
    pico_closed_loop(&project, SamplingSpec::Interrupt, &Options::for_events(PICO_EVENTS))
}

/// Safe and in step through the pins: every command enabled when it came, no reboot, every edge taken
/// as its event, every vehicle through every zone. Before the edges latched at boot were cleared, the
/// first command was judged disabled and the board rebooted at every event.
#[test]
fn the_reduced_agv_set_runs_on_the_pico_through_its_pins() {
    let report = pico_run();
    eprintln!("agv reduced, RP2040: {report}");
    assert_clean(&report, "agv reduced, RP2040");
    let board = report.board.as_ref().expect("the harness's figures");
    assert_eq!((board.missed, board.unmapped), (0, 0), "{report}");
    let zones: Vec<_> = report.coverage.iter().filter(|l| l.supervisor.starts_with("S_Z")).collect();
    assert_eq!(zones.len(), 4, "{report}");
    for line in zones {
        assert_eq!(Some(line.taken), line.reachable, "{}: {report}", line.supervisor);
    }
}

#[test]
fn the_full_agv_set_is_safe_and_live_under_qemu() {
    let mut project = Project::load(&example("agv/agv.toml")).unwrap();
    project.choose_supervisors(SupervisorChoice::Full, &Config::default()).unwrap();
    assert_eq!(project.deployed.size, (7902, 26404));
    check(
        &qemu_closed_loop(&project, &Options { events: EVENTS, ..Options::default() }),
        "agv full, QEMU",
        60,
    );
}

/// The full set (the merged supervisor's 7 800 states) as the Pico's link build on the emulated RP2040,
/// lock-step over UART0: safe, in step, and live. Coverage is not asserted: the merged supervisor's
/// 4 408 reachable controllable transitions take more events than CI spends (docs/layouts.md).
#[test]
fn the_full_agv_set_is_safe_and_live_on_the_pico_over_its_link() {
    let mut project = Project::load(&example("agv/agv.toml")).unwrap();
    project.choose_supervisors(SupervisorChoice::Full, &Config::default()).unwrap();
    let report = pico_link_closed_loop(&project, &Options::for_events(PICO_LINK_EVENTS));
    let what = "agv full, RP2040 link";
    eprintln!("{what}: {report}");
    assert_eq!(report.target, "rp2040", "{what}");
    assert!(report.events >= PICO_LINK_EVENTS, "{what}: {report}");
    assert_clean(&report, what);
    assert!(report.marked_visits >= report.events / 500, "{what}: {report}");
    assert!(report.longest_marked_gap < 2_000, "{what}: {report}");
}
