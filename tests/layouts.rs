//! Every table layout runs the same closed loop: the cell and the factory under QEMU, one image per
//! layout (`[runtime] layout`), each run in lock-step rounds with the same seeds — clean, and the same
//! event trace (`trace_sha256`) in every layout. The readers differ; what the firmware decides must not.

use codegen::closed_loop::Options;
use codegen::pack::Layout;
use codegen::project::Project;
use end_to_end::{assert_clean, example, qemu_closed_loop};

/// Events per run: enough for every machine of either example to cycle many times.
const EVENTS: u64 = 2_000;
/// The plant's seed (the contract uses 3).
const SEED: u64 = 3;

/// Runs `manifest` once per layout, two at a time, and checks the runs alike.
fn same_trace_in_every_layout(manifest: &str) {
    let project = Project::load(&example(manifest)).unwrap_or_else(|e| panic!("{manifest}: {e}"));
    // In lock-step rounds (the default): the trace a function of the seeds, whatever the timing.
    let mut options = Options { events: EVENTS, ..Options::default() };
    options.plant.seed = SEED;
    let run = |layout: Layout| {
        let mut project = project.clone();
        project.runtime.layout = Some(layout);
        (layout, qemu_closed_loop(&project, &options))
    };
    let reports: Vec<_> = Layout::ALL
        .chunks(2)
        .flat_map(|pair| {
            std::thread::scope(|s| {
                let runs: Vec<_> = pair.iter().map(|&layout| s.spawn(move || run(layout))).collect();
                runs.into_iter()
                    .map(|r| r.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                    .collect::<Vec<_>>()
            })
        })
        .collect();
    let (first, reference) = &reports[0];
    for (layout, report) in &reports {
        let what = format!("{manifest}, layout {layout}");
        eprintln!("{what}: {report}");
        assert_clean(report, &what);
        assert!(report.events >= EVENTS, "{what}: {report}");
        assert_eq!(
            (report.events, &report.trace_sha256),
            (reference.events, &reference.trace_sha256),
            "{what}: another trace than layout {first}'s"
        );
    }
}

#[test]
fn every_layout_takes_the_cells_trace() {
    same_trace_in_every_layout("cell/cell.toml");
}

#[test]
fn every_layout_takes_the_factorys_trace() {
    same_trace_in_every_layout("factory/factory.toml");
}
