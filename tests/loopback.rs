//! The virtual plant driving the firmware's runtime — the very code that ships, compiled for the host —
//! over an in-memory byte link: the closed loop without QEMU.

use codegen::closed_loop::{attach, parts, ClosedLoopError, Options, Session, SessionConfig, SessionError};
use codegen::config::ChoicePolicy;
use codegen::link::memory;
use codegen::link::protocol::EXIT;
use codegen::link::ByteLink;
use codegen::model::StateId;
use codegen::monitor::ChoiceModel;
use codegen::pack::{ranked, PackSet};
use codegen::project::Project;
use end_to_end::{assert_clean, example, published_cell, spawn_host_firmware, ticker};
use firmware::build::HostTables;
use firmware::choice::{First, Random, RandomLocalQueue};
use firmware::fault::FaultPolicy;
use firmware::runtime::Config;
use firmware::table::layout;

const CONFIG: Config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 1024 };

#[test]
fn cell_closed_loop_is_safe_live_and_covers_every_supervisor_transition() {
    let set = published_cell();
    let tables = HostTables::new(ranked::encode(&set).unwrap()).unwrap();
    let (host, target) = memory::pair();
    // 23 events (one bitset word, 3-byte masks), 4 plants + 6 supervisors, 1-byte fields, 32 input slots;
    // 3 choice sites.
    let policy = RandomLocalQueue::<1, 3>::default();
    let firmware =
        spawn_host_firmware::<_, 1, 10, false, 3, { layout::RANKED }, 33>(tables, CONFIG, policy, 7, target);
    closed_loop(&set, host, firmware);
}

#[test]
fn cell_closed_loop_on_the_cortex_m0_plus_tables() {
    let set = published_cell();
    let tables = HostTables::new(ranked::encode_indexed(&set).unwrap()).unwrap();
    let (host, target) = memory::pair();
    // The `indexed` layout: word masks, a target per event of the alphabet.
    let policy = RandomLocalQueue::<1, 3>::default();
    let firmware =
        spawn_host_firmware::<_, 1, 10, false, 4, { layout::INDEXED }, 33>(tables, CONFIG, policy, 7, target);
    closed_loop(&set, host, firmware);
}

/// A firmware whose loop does not report its tables (a firmware from before TABLES: the host-compiled
/// one here is given no digest) is refused when the run expects tables, at once: its STATUS answer
/// without a TABLES answer before it tells, where waiting would end in `NoAnswer` after the timeout.
#[test]
fn a_firmware_that_does_not_report_its_tables_is_refused_at_once() {
    let set = published_cell();
    let tables = HostTables::new(ranked::encode(&set).unwrap()).unwrap();
    let (mut host, target) = memory::pair();
    let policy = RandomLocalQueue::<1, 3>::default();
    let firmware =
        spawn_host_firmware::<_, 1, 10, false, 3, { layout::RANKED }, 33>(tables, CONFIG, policy, 7, target);
    let options = Options { events: 100, tables: vec!["0123456789abcdef".into()], ..Options::default() };
    let refused = attach(&mut host, &set, "cell", &options, &mut |_| {});
    let Err(ClosedLoopError::Session { source: SessionError::TablesUnreported, .. }) = refused else {
        panic!("not refused as a firmware that does not report its tables: {refused:?}");
    };
    assert!(refused.unwrap_err().to_string().contains("does not report its tables"));
    host.send(&[EXIT]).unwrap();
    assert_eq!(firmware.join().unwrap(), Some(0));
}

/// The cell's virtual plant against `firmware` over `host` for 20 000 events: safe, live, every
/// supervisor transition covered.
fn closed_loop(set: &PackSet, mut host: memory::MemoryLink, firmware: std::thread::JoinHandle<Option<u8>>) {
    let options = Options { events: 20_000, ..Options::default() };
    let report = attach(&mut host, set, "cell", &options, &mut |_| {}).unwrap();
    host.send(&[EXIT]).unwrap();
    assert_eq!(firmware.join().unwrap(), Some(0));

    assert_clean(&report, "cell on the host runtime");
    assert!(report.marked_visits > 200, "{report}");
    assert!(report.longest_marked_gap < 2_000, "{report}");
    assert!(report.full_coverage(), "{report}");
}

/// The ticker plant alone, packed.
fn ticker_set() -> PackSet {
    let a = ticker();
    assert_eq!(a.state_id("odd"), Some(StateId::new(1).unwrap()));
    PackSet::new(vec![a], vec![]).unwrap()
}

/// HOLD, a burst of `n` events, GO; returns (events the firmware took, overflows it reported).
fn burst(n: usize) -> (u64, u64) {
    let set = ticker_set();
    let tables = HostTables::new(ranked::encode(&set).unwrap()).unwrap();
    let (mut host, target) = memory::pair();
    // 8 input slots: 7 events fit.
    let firmware = spawn_host_firmware::<Random, 1, 1, false, 1, { layout::RANKED }, 8>(
        tables, CONFIG, Random, 1, target,
    );
    let options = Options::default();
    let (mut plant, mut monitor) = parts(&set, &options).unwrap();
    let mut session = Session::new(&mut host, &mut plant, &mut monitor, SessionConfig::default());
    session.sync(false).unwrap();
    assert_eq!(session.burst(n).unwrap(), n);
    let report = session.finish().unwrap();
    host.send(&[EXIT]).unwrap();
    firmware.join().unwrap();
    (report.firmware.events_in, report.overflows)
}

#[test]
fn a_burst_up_to_the_buffer_loses_nothing_and_beyond_it_the_overflow_is_reported() {
    assert_eq!(burst(7), (7, 0));
    let (taken, overflows) = burst(12);
    assert_eq!((taken, overflows), (7, 5), "every event is either taken or counted");
}

/// A firmware whose choices can never cover the cell (`first` takes the lowest enabled command, so a
/// choice site's other commands never come), steered as if it chose at random: the steering, stuck,
/// restarts the closed loop after [`STEERING_RESET`] events without a new transition — and that is
/// neither a violation nor a link resync. In lock-step, so the run is a function of the seeds: the same
/// restarts on any machine, loaded or not.
#[test]
fn a_stuck_steering_restarts_the_closed_loop() {
    let set = published_cell();
    let tables = HostTables::new(ranked::encode(&set).unwrap()).unwrap();
    let (mut host, target) = memory::pair();
    let firmware =
        spawn_host_firmware::<_, 1, 10, false, 3, { layout::RANKED }, 33>(tables, CONFIG, First, 7, target);
    // Without steps: in steps the plant's answers after every command find new transitions under
    // `first` too (339 of 365 in 12 000 events), too slowly for a test to wait for the plateaus.
    let session = SessionConfig { step: false, steering_reset: STEERING_RESET, ..SessionConfig::default() };
    let options = Options { events: 4 * STEERING_RESET, session, ..Options::default() };
    let report = attach(&mut host, &set, "cell", &options, &mut |_| {}).unwrap();
    host.send(&[EXIT]).unwrap();
    assert_eq!(firmware.join().unwrap(), Some(0));
    assert!(!report.full_coverage(), "first cannot cover the cell: {report}");
    assert!(report.steering_resets >= 1, "{report}");
    assert_eq!((report.violations, report.resyncs, report.stalls), (0, 0, 0), "{report}");
}

/// Events without a new transition after which [`a_stuck_steering_restarts_the_closed_loop`]'s steering
/// restarts (2 000 in a run of `codegen run`): short, so the test is.
const STEERING_RESET: u64 = 500;

/// The distribution station under its own `first` policy (the state-based paper's rung order): every
/// transition `first` can fire taken, and the marked state visited throughout — the steering chases no
/// transition `first` never fires (it did, and the run never came home: docs/steering.md).
#[test]
fn the_distribution_station_under_first_is_covered_and_comes_home() {
    let project = Project::load(&example("distribution/distribution.toml")).unwrap();
    assert_eq!(project.runtime.policy, ChoicePolicy::First);
    let tables = HostTables::new(ranked::encode(&project.set).unwrap()).unwrap();
    let (mut host, target) = memory::pair();
    // 14 events (one bitset word, 2-byte masks), 4 plants + 6 supervisors, 2-byte fields.
    let firmware =
        spawn_host_firmware::<_, 1, 10, true, 2, { layout::RANKED }, 33>(tables, CONFIG, First, 1, target);
    // In lock-step (the default), as `codegen run` runs it.
    let choices = ChoiceModel::of(project.runtime.policy);
    let options = Options { events: 10_000, choices, ..Options::default() };
    let report = attach(&mut host, &project.set, "distribution", &options, &mut |_| {}).unwrap();
    host.send(&[EXIT]).unwrap();
    assert_eq!(firmware.join().unwrap(), Some(0));
    eprintln!("{report}");
    assert_clean(&report, "distribution on the host runtime");
    assert!(report.full_coverage(), "{report}");
    assert_eq!(report.steering_resets, 0, "{report}");
    assert!(report.marked_visits >= 1_000 && report.longest_marked_gap < 2_000, "{report}");
}
