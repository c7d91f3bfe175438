//! The distribution station (`examples/station/`) as a user brings it — a Supremica module under a
//! manifest — synthesised, packed and run on the firmware's runtime compiled for the host, behind an
//! in-memory link: a controller that never runs out of commands (its actuators may switch at will) under
//! the paper's interlocks, safe, in step with the plant, and fully covered within 10 000 events: the
//! session runs in steps (STEP: one decision, then the plant's turn), so the plant's sensor edges get in
//! between the commands of a controller that never runs out of them (docs/steering.md).

use codegen::closed_loop::{attach, Options};
use codegen::link::memory;
use codegen::link::protocol::EXIT;
use codegen::link::ByteLink;
use codegen::monitor::{ChoiceModel, Report};
use codegen::pack::ranked;
use codegen::project::Project;
use end_to_end::{assert_clean, example, spawn_host_firmware};
use firmware::build::HostTables;
use firmware::choice::RandomLocalQueue;
use firmware::fault::FaultPolicy;
use firmware::runtime::Config;
use firmware::table::layout;

const CONFIG: Config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 1024 };

/// The station's closed loop on the host runtime for 10 000 events with plant seed `seed`.
fn station(seed: u64) -> Report {
    let project = Project::load(&example("station/station.toml")).unwrap();
    let tables = HostTables::new(ranked::encode(&project.set).unwrap()).unwrap();
    let (mut host, target) = memory::pair();
    // 18 events (one bitset word, 3-byte masks), 3 plants + 6 supervisors, 12 choice sites.
    let policy = RandomLocalQueue::<1, 12>::default();
    let firmware = spawn_host_firmware::<_, 1, 9, false, 3, { layout::RANKED }, 33>(
        tables, CONFIG, policy, seed, target,
    );
    let mut options =
        Options { events: 10_000, choices: ChoiceModel::of(project.runtime.policy), ..Options::default() };
    options.plant.seed = seed;
    let report = attach(&mut host, &project.set, "station", &options, &mut |_| {}).unwrap();
    host.send(&[EXIT]).unwrap();
    assert_eq!(firmware.join().unwrap(), Some(0));
    report
}

#[test]
fn the_station_from_a_supremica_module_is_safe_in_step_and_fully_covered_on_the_host_runtime() {
    let project = Project::load(&example("station/station.toml")).unwrap();
    let names: Vec<&str> = project.set.members().iter().map(|m| m.name()).collect();
    assert_eq!(
        names,
        [
            "Piston",
            "Arm",
            "Gripper",
            "S_L_ArmExclusive",
            "S_I1_GripAtLeft",
            "S_I2_NoStartWhileSwitching",
            "S_I3_NoReleaseWhileMoving",
            "S_I4_ArmLeftPistonNotFront",
            "S_I5_PistonFrontArmNotLeft"
        ],
        "the module's three device models and one supervisor per interlock"
    );
    for seed in [1, 2, 3] {
        let report = station(seed);
        let what = format!("station, seed {seed}");
        eprintln!("{what}: {report}");
        assert_clean(&report, &what);
        assert!(report.commands > 0 && report.events >= 10_000, "{what}: {report}");
        // Every reachable controllable transition of the six supervisors (340), well within the run
        // (docs/steering.md: about 3 000 events under QEMU on seeds 1 to 20), without a steering reset.
        let taken: usize = report.coverage.iter().map(|c| c.taken).sum();
        assert_eq!(taken, 340, "{what}: {report}");
        assert!(report.full_coverage_at.is_some_and(|at| at <= 10_000), "{what}: {report}");
        assert_eq!(report.steering_resets, 0, "{what}: {report}");
    }
}

/// Two runs with one seed take one trace, byte for byte: the firmware boots on hold and decides nothing
/// before the session's RESET and first STEP, so its random generator starts every run from the seed
/// (docs/steering.md). The runs go side by side, so that their timings differ.
#[test]
fn two_runs_with_one_seed_take_the_same_trace() {
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| station(1));
        let b = s.spawn(|| station(1));
        (a.join().unwrap(), b.join().unwrap())
    });
    let fingerprint = |r: &Report| {
        (
            r.trace_sha256.clone(),
            r.events,
            r.commands,
            r.full_coverage_at,
            r.firmware.commands_out,
            r.marked_visits,
        )
    };
    assert_eq!(fingerprint(&a), fingerprint(&b), "seed 1 twice:\n{a}\n{b}");
}
