//! Races under QEMU: the plant answers every command at once, so its events race the firmware's next
//! decision. Desynchronisations (commands decided before the firmware read the plant's latest event) are
//! counted with the inexact-synchronisation guard off and on. The guard catches an event that reaches the
//! input buffer while a choice is made; those still on the wire no guard can catch.
//!
//! Timing is the subject, so the session runs in the plant's own timing, not in lock-step rounds. What
//! it asserts does not depend on how fast the machine is: a race is a command decided before an event
//! was read, which any speed makes (the plant answers every command at once); no stall is asserted. The
//! one margin is the monitor's read window (0.5 s): a command arriving later than that after an event
//! counts as decided on it, so a host or QEMU held off the processor for half a second in between would
//! turn a race into a violation — QEMU reads its UART within milliseconds.

use codegen::closed_loop::{Options, SessionConfig};
use codegen::monitor::Report;
use codegen::project::Project;
use end_to_end::{example, qemu_closed_loop};

fn run(guard: bool) -> Report {
    let mut project = Project::load(&example("cell/cell.toml")).unwrap();
    project.runtime.guard = guard;
    let mut options = Options { events: 20_000, session: SessionConfig::realtime(), ..Options::default() };
    options.plant.race_per_mille = 1000;
    options.plant.delay_us = (0, 50);
    let report = qemu_closed_loop(&project, &options);
    eprintln!(
        "guard {}: {} desyncs, {} guard re-decisions\n{report}",
        if guard { "on" } else { "off" },
        report.desyncs,
        report.guard_redecisions
    );
    report
}

#[test]
fn races_desynchronise_and_no_guard_catches_what_is_on_the_wire() {
    let off = run(false);
    let on = run(true);
    for r in [&off, &on] {
        assert_eq!(r.violations, 0, "{r}");
        assert_eq!(r.lost, 0, "{r}");
        assert_eq!(r.firmware.events_in, r.uncontrollable, "{r}");
        assert_eq!(r.firmware.commands_out, r.commands, "{r}");
        // Answering every command at once must race, guard or not: the racing events are still on the
        // wire when the firmware decides. (The guard's own effect — a choice dropped when an input
        // arrived while choosing — is shown where an input can be made to arrive during a decision:
        // `firmware/tests/link.rs`.)
        assert!(r.desyncs > 0, "answering every command at once must race: {r}");
    }
}
