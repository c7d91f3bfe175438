//! The manufacturing cell under QEMU: the real firmware image, synthesised from the cell's manifest,
//! against the virtual plant for 10 000 events on each of several seeds — the verdict must not depend on
//! the seed. In lock-step rounds (the default, as `codegen run`): each run is a function of its seed,
//! whatever the machine's load.

use codegen::closed_loop::Options;
use codegen::config::ChoicePolicy;
use codegen::project::Project;
use end_to_end::{assert_clean, example, qemu_closed_loops};

/// The plant's seeds tried: the figures of docs/measurements.md come from 1..=20 (`codegen run --events 10000 --seed S`).
const SEEDS: [u64; 6] = [1, 2, 3, 7, 13, 20];

#[test]
fn cell_is_safe_live_and_fully_covered_within_10_000_events_on_every_seed() {
    let project = Project::load(&example("cell/cell.toml")).unwrap();
    assert_eq!(project.runtime.policy, ChoicePolicy::RandomLocalQueue);
    let options = Options { events: 10_000, ..Options::default() };
    let reports = qemu_closed_loops(&project, &options, &SEEDS);

    for (seed, report) in SEEDS.iter().zip(&reports) {
        eprintln!("seed {seed}: {report}");
        let what = format!("seed {seed}");
        assert_eq!(report.seed, *seed);
        assert_clean(report, &what);
        // Marked states throughout: on average every few dozen events, never a long stretch without.
        assert!(report.marked_visits >= report.events / 100, "{what}: {report}");
        assert!(report.longest_marked_gap < 2_000, "{what}: {report}");
        assert!(report.events_since_marked < 2_000, "{what}: {report}");
        // Every reachable controllable supervisor transition of the cell (365) taken, well within the run.
        let taken: usize = report.coverage.iter().map(|c| c.taken).sum();
        assert_eq!(taken, 365, "{what}: {report}");
        assert!(report.full_coverage(), "{what}: {report}");
        assert!(report.full_coverage_at.is_some_and(|at| at <= 10_000), "{what}: {report}");
    }
}
