//! The cell's board firmware — the Pico application users flash — on an emulated RP2040
//! (`harness/rp2040/`), the virtual plant on its pins: 20 000 events with GPIO edge interrupts and
//! 20 000 with timer sampling. And the harness refuses an image linked for another chip.
//!
//! The harness speaks no SYNC, so these runs take the plant's own timing (realtime), the one mode whose
//! verdicts time could touch. A stall is judged on the closed loop's state, not the clock (asked, the
//! firmware fired nothing while no command is enabled), and the steering waits for the command it
//! prefers however long it takes, so load makes no stall and steers no worse. The margins left: the
//! monitor's read window (0.5 s between an event and a command decided before it was read — the
//! firmware reads an edge within a millisecond of emulated time), 10 s of silence with a command
//! enabled, and full coverage within the 20 000 events: reached after 2 070–2 260 events with edge
//! interrupts and 7 900–8 040 with timer sampling on the loaded 2-core machine (27 Nov 2026).

use codegen::closed_loop::Options;
use codegen::config::SamplingSpec;
use codegen::monitor::Report;
use codegen::project::Project;
use codegen::target::rp2040::{Harness, HarnessConfig, HarnessError};
use end_to_end::{example, firmware_image, pico_closed_loop, pico_image, Scratch};

fn run(sampling: SamplingSpec) -> Report {
    let project = Project::load(&example("cell/cell.toml")).unwrap();
    let options = Options::for_events(20_000);
    let report = pico_closed_loop(&project, sampling, &options);
    eprintln!("{report}");
    report
}

/// Safe, live, nothing lost, every edge read and every command shown on a pin, every reachable
/// controllable supervisor transition taken.
fn check(report: &Report, sampling: &str) {
    assert_eq!(report.target, "rp2040");
    assert!(report.events >= 20_000, "{report}");
    assert_eq!(report.violations, 0, "{report}");
    assert!(report.marked_visits >= report.events / 100, "{report}");
    assert!(report.longest_marked_gap < 2_000, "{report}");
    let fw = &report.firmware;
    assert_eq!(report.uncontrollable, fw.events_in + fw.overflows, "sent = taken + overflows: {report}");
    assert_eq!((report.lost, report.overflows, report.stalls, fw.unexpected), (0, 0, 0, 0), "{report}");
    let board = report.board.as_ref().expect("the harness's figures");
    assert_eq!(board.sampling, sampling);
    assert_eq!(board.edges, report.uncontrollable, "one edge per plant event: {report}");
    assert_eq!(
        (board.missed, board.hidden_commands, board.unmapped, board.forced_answers),
        (0, 0, 0, 0),
        "{report}"
    );
    assert!(board.commands_seen >= report.commands, "{report}");
    assert!(board.cost.apply.calls >= report.uncontrollable && board.cost.decision.calls > 0, "{report}");
    assert!(report.full_coverage(), "{report}");
}

#[test]
fn cell_on_the_pico_with_edge_interrupts_is_safe_live_and_covered_for_20_000_events() {
    check(&run(SamplingSpec::Interrupt), "interrupt");
}

#[test]
fn cell_on_the_pico_with_timer_sampling_is_safe_live_and_covered_for_20_000_events() {
    check(&run(SamplingSpec::Timer), "timer");
}

#[test]
fn the_harness_refuses_an_image_linked_for_another_chip() {
    let project = Project::load(&example("cell/cell.toml")).unwrap();
    let scratch = Scratch::new("pico-wrong-chip");
    let (_, pins) = pico_image(&project, SamplingSpec::Interrupt, &scratch);
    // The QEMU image: vector table at 0, in what is the RP2040's ROM.
    let qemu = firmware_image(&project, &scratch);
    match Harness::start(&qemu, &pins, &HarnessConfig::default()) {
        Err(HarnessError::Exited { stderr, .. }) => {
            assert!(stderr.contains("is not linked for the RP2040"), "{stderr}");
        }
        Err(other) => panic!("{other}"),
        Ok(_) => panic!("the harness took an lm3s6965 image"),
    }
}

/// The harness's own tests (`harness/rp2040/test/`), those that need a Pico image included: run on the
/// cell's, built here, so they run in CI with everything else.
#[test]
fn the_harness_tests_pass_on_the_cell_image() {
    let project = Project::load(&example("cell/cell.toml")).unwrap();
    let scratch = Scratch::new("pico-harness-tests");
    let (elf, pins) = pico_image(&project, SamplingSpec::Interrupt, &scratch);
    let dir = end_to_end::root().join("harness/rp2040");
    let out = std::process::Command::new("node")
        .args(["--test", "test/"])
        .current_dir(&dir)
        .env("PICO_ELF", &elf)
        .env("PICO_PINS", &pins)
        .output()
        .unwrap_or_else(|e| panic!("node: {e} (scripts/setup.sh installs Node and the harness)"));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("# fail 0") && text.contains("# skipped 0"), "{text}");
}
