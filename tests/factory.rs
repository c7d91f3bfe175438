//! The second system, as a user brings it: Wonham's small factory written as a Supremica module
//! (`examples/factory/factory.wmod`) under a manifest that adds the run-time settings and the Pico's pin
//! map — synthesised, packed, built for the Cortex-M3 and run closed loop under QEMU, as `codegen run
//! examples/factory/factory.toml` does, on two seeds.

use codegen::closed_loop::Options;
use codegen::project::Project;
use end_to_end::{assert_clean, example, qemu_closed_loops};

#[test]
fn the_small_factory_from_a_supremica_module_is_safe_live_and_fully_covered() {
    let project = Project::load(&example("factory/factory.toml")).unwrap();
    let names: Vec<&str> = project.set.members().iter().map(|m| m.name()).collect();
    assert_eq!(names, ["M1", "M2", "S_Buffer", "S_Repair"], "plants and supervisors from the module's kinds");
    assert!(project.board.is_some(), "the manifest's pin map");
    let seeds = [1, 2];
    let reports = qemu_closed_loops(&project, &Options { events: 10_000, ..Options::default() }, &seeds);
    for (seed, report) in seeds.iter().zip(&reports) {
        let what = format!("factory, seed {seed}");
        eprintln!("{what}: {report}");
        assert_clean(report, &what);
        assert!(report.full_coverage(), "{what}: {report}");
        assert!(report.marked_visits >= report.events / 100, "{what}: {report}");
        assert!(report.longest_marked_gap < 2_000, "{what}: {report}");
    }
}
