//! The distribution station's state feedback on the microcontroller (`[runtime] mode = "state"`,
//! docs/state-based.md): the QEMU firmware built on the state tables — F_σ as cubes over the packed
//! signal word, no supervisor tables — against the virtual plant, judged by the monitor against plants ‖
//! supervisors. The monitor also carries the free plant G as an observer that disables nothing: its
//! controllable transitions reachable in the closed loop are the (plant state, command) pairs f allows,
//! so its coverage line says whether the firmware fired every one of them.

use codegen::closed_loop::Options;
use codegen::config::{ChoicePolicy, Mode};
use codegen::model::Kind;
use codegen::pack::{PackSet, Role};
use codegen::project::Project;
use codegen::synth::{product, Config};
use end_to_end::{assert_clean, example, qemu_closed_loops_judged};

/// The plant's seeds tried.
const SEEDS: [u64; 3] = [1, 2, 3];

/// The reachable (plant state, command) pairs the closed loop allows: |f|'s complement over the
/// commands, the figure `tests/plc_state.rs` reaches with `--choice random` (docs/state-based.md).
const ALLOWED_PAIRS: usize = 27;

#[test]
fn the_station_runs_state_based_under_qemu_safe_live_and_fully_covered() {
    let project = Project::load(&example("distribution/distribution-state.toml")).unwrap();
    assert_eq!((project.runtime.mode, project.runtime.policy), (Mode::State, ChoicePolicy::Random));
    let members = project.set.members();
    let plants: Vec<_> =
        members.iter().filter(|m| m.role == Role::Plant).map(|m| m.automaton.clone()).collect();
    let mut supervisors: Vec<_> =
        members.iter().filter(|m| m.role == Role::Supervisor).map(|m| m.automaton.clone()).collect();
    let mut g = product(&plants, &Config::default()).unwrap();
    (g.name, g.kind) = ("G".into(), Kind::Supervisor);
    assert_eq!((g.states.len(), g.transitions.len()), (128, 512), "the free plant of the paper");
    supervisors.push(g);
    let judged = PackSet::new(plants, supervisors).unwrap();
    assert_eq!(judged.events(), project.set.events(), "the observer adds no event");

    let options = Options { events: 1_500, ..Options::default() };
    let reports = qemu_closed_loops_judged(&project, &judged, &options, &SEEDS);
    for (seed, report) in SEEDS.iter().zip(&reports) {
        let what = format!("state-based station, seed {seed}");
        eprintln!("{what}: {report}");
        assert_clean(report, &what);
        assert!(report.commands > 0 && report.events >= 1_500, "{what}: {report}");
        assert!(report.marked_visits >= report.events / 200, "{what}: {report}");
        assert!(report.longest_marked_gap < 750, "{what}: {report}");
        let g = report.coverage.iter().find(|c| c.supervisor == "G").unwrap();
        assert_eq!((g.taken, g.reachable), (ALLOWED_PAIRS, Some(ALLOWED_PAIRS)), "{what}: {report}");
        assert!(report.full_coverage(), "{what}: {report}");
    }
}
