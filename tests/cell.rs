//! The manufacturing cell under QEMU: the real firmware image, synthesised from the cell's manifest,
//! against the virtual plant for 100 000 events.

use codegen::closed_loop::Options;
use codegen::config::ChoicePolicy;
use codegen::project::Project;
use end_to_end::{example, qemu_closed_loop};

#[test]
fn cell_is_safe_live_and_fully_covered_for_100_000_events() {
    let project = Project::load(&example("cell/cell.toml")).unwrap();
    assert_eq!(project.runtime.policy, ChoicePolicy::RandomLocalQueue);
    let mut options = Options { events: 100_000, ..Options::default() };
    options.plant.delay_us = (0, 100);
    let report = qemu_closed_loop(&project, &options);
    eprintln!("{report}");

    assert!(report.events >= 100_000);
    assert_eq!(report.violations, 0, "{report}");
    // Marked states throughout: on average every few dozen events, never a long stretch without.
    assert!(report.marked_visits >= report.events / 100, "{report}");
    assert!(report.longest_marked_gap < 2_000, "{report}");
    assert!(report.events_since_marked < 2_000, "{report}");
    assert!(report.full_coverage(), "{report}");
    assert_eq!((report.lost, report.overflows, report.stalls), (0, 0, 0), "{report}");
}
