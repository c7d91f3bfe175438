//! `codegen run --target plc` as a binary: the PLC program of every example with a `[plc]` section
//! scanned closed loop by the interpreter, exit 0 with `"violations": 0` and a marked visit in the JSON;
//! the factory and the cell with full coverage and their scan figures; the same seed giving the same
//! bytes; exit 2 for the firmware's options. (Exit 1 on a violation: `tests/plc.rs` runs a broken program through the same
//! `plc::closed_loop::run` the command calls, and the exit status is the QEMU run's `finish`.)

use std::path::Path;
use std::process::{Command, Output};

use codegen::plc::closed_loop::{Driver, Edge, Scan, Scanner};

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel).display().to_string()
}

/// `codegen run MANIFEST --target plc --events N --json` and extra `args`: its exit status, its JSON
/// report and its stdout's bytes.
fn run(manifest: &str, events: u64, args: &[&str]) -> (Option<i32>, serde_json::Value, Vec<u8>) {
    let events = events.to_string();
    let mut all = vec!["run", manifest, "--target", "plc", "--events", &events, "--json"];
    all.extend(args);
    let out = codegen(&all);
    let json = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{manifest}: {e}: {}", String::from_utf8_lossy(&out.stderr)));
    (out.status.code(), json, out.stdout)
}

/// Every example whose manifest has a `[plc]` section, found in `examples/`.
fn plc_examples() -> Vec<String> {
    let mut found = Vec::new();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    for dir in std::fs::read_dir(&examples).unwrap() {
        let dir = dir.unwrap().path();
        let Ok(files) = std::fs::read_dir(&dir) else { continue };
        for file in files {
            let file = file.unwrap().path();
            if file.extension().is_some_and(|e| e == "toml")
                && std::fs::read_to_string(&file).unwrap().lines().any(|l| l.trim() == "[plc]")
            {
                found.push(file.display().to_string());
            }
        }
    }
    found.sort();
    found
}

// See: issue 36 (the contract: every example with a `[plc]` section, 0 violations).
#[test]
fn every_plc_example_runs_with_no_violation() {
    let examples = plc_examples();
    assert!(examples.len() >= 3, "{examples:?}");
    for manifest in &examples {
        let (code, json, _) = run(manifest, 300, &[]);
        assert_eq!(code, Some(0), "{manifest}: {json}");
        assert_eq!(json["violations"].as_u64(), Some(0), "{manifest}: {json}");
        assert_eq!(json["target"].as_str(), Some("plc"), "{manifest}");
        assert!(json["events"].as_u64().unwrap() >= 300, "{manifest}: {json}");
        // Liveness as under QEMU: a marked state of plants ‖ supervisors visited (a fixed choice rule
        // can keep a nonblocking closed loop out of them, as `local-queue` did the EFA buffer's).
        assert!(json["marked_visits"].as_u64() > Some(0), "{manifest}: {json}");
        // No stall, but where the model blocks: net1 is the paper's blocking net (p7's action al is
        // disabled by the piston interlock; the_station_nets_run_closed_loop_and_net1_blocks_at_p7).
        if !manifest.ends_with("station-rtpn/net1.toml") {
            assert_eq!(json["stalls"].as_u64(), Some(0), "{manifest}: {json}");
        }
    }
}

/// A PLC driver behind the wrapper with the test looking on: `on_scan` sees every scan's result,
/// `on_reset` the driver just before each reset (the power-up's first); everything else is the
/// driver's own.
struct Watched<S, R> {
    driver: Driver,
    on_scan: S,
    on_reset: R,
}

impl<S, R> Scanner for Watched<S, R>
where
    S: FnMut(&Scan) + Send,
    R: FnMut(&Driver) + Send,
{
    fn has_input(&self, e: u8) -> bool {
        self.driver.has_input(e)
    }
    fn edge(&mut self, e: u8, used: &mut Vec<String>) -> Result<Edge, String> {
        self.driver.edge(e, used)
    }
    fn hold(&mut self, on: bool) -> Result<(), String> {
        Scanner::hold(&mut self.driver, on)
    }
    fn held(&self) -> Result<bool, String> {
        self.driver.held()
    }
    fn pending(&self) -> Result<bool, String> {
        self.driver.pending()
    }
    fn safe(&self) -> Result<bool, String> {
        self.driver.safe()
    }
    fn scan(&mut self) -> Result<Scan, String> {
        let scan = Scanner::scan(&mut self.driver)?;
        (self.on_scan)(&scan);
        Ok(scan)
    }
    fn reset(&mut self) -> Result<(), String> {
        (self.on_reset)(&self.driver);
        Scanner::reset(&mut self.driver)
    }
    fn status(&self, unknown: u32) -> Result<[u32; 6], String> {
        self.driver.status(unknown)
    }
    fn timed_cycle(&self) -> Option<u32> {
        self.driver.timed_cycle()
    }
    fn set_interval(&mut self, ms: u32) {
        self.driver.set_interval(ms)
    }
    fn new_round(&mut self) -> Result<(), String> {
        Scanner::new_round(&mut self.driver)
    }
    fn quiet_for(&self) -> Result<Option<u32>, String> {
        Scanner::quiet_for(&self.driver)
    }
    fn runs_free_on_time(&self) -> bool {
        self.driver.runs_free_on_time()
    }
}

/// A station net's event-based program run closed loop for `events` events as `run --target plc` runs
/// it (its TIME scanning every task interval with `every_cycle`), with the places marked at each RESET
/// the program took, the power-up's first.
fn station_net(name: &str, events: u64, every_cycle: bool) -> (codegen::monitor::Report, Vec<Vec<String>>) {
    use codegen::plc::closed_loop::{net_driver, run_spawned, spawn_plc};
    use codegen::plc::net_drive::NetDrive;
    use codegen::plc::{Avalanche, Encoding, Form};
    use std::sync::{Arc, Mutex};

    let manifest = repo(&format!("examples/station-rtpn/{name}.toml"));
    let project = codegen::project::Project::load(Path::new(&manifest)).unwrap();
    let form = Form::Event { encoding: Encoding::Int, avalanche: Avalanche::Auto, policy: None };
    let out = project.plc(&form).unwrap().into_event().unwrap();
    let net = NetDrive::new(&project.sequence().unwrap().unwrap());
    let mut options = codegen::closed_loop::Options::for_events(events);
    options.session.own_delays = net.own_delays(out.report.cycle_ms);
    let mut driver =
        net_driver(&out.files[0].1, &out.report, &project.set, Some(&net), options.plant.seed).unwrap();
    driver.scan_every_cycle(every_cycle);
    let seen = Arc::new(Mutex::new(Vec::new()));
    let (places, noted) = (net.places.clone(), Arc::clone(&seen));
    let at_reset = Watched {
        driver,
        on_scan: |_: &Scan| {},
        on_reset: move |driver: &Driver| {
            let marked = places.iter().filter(|p| driver.plc.get_bool(p) == Ok(true)).cloned();
            noted.lock().unwrap().push(marked.collect());
        },
    };
    let (host, target) = codegen::link::memory::pair();
    let plc = spawn_plc(at_reset, target);
    let report =
        run_spawned(host, plc, &(&out.report).into(), &project.set, name, &options, &mut |_| {}).unwrap();
    let seen = seen.lock().unwrap().clone();
    (report, seen)
}

// See: issue 36 (the station's sequences under `--target plc` stalled every round: the driver's inputs
// started FALSE though the arm starts at its left end, nothing drove the free inputs, and a round
// without events was a stall before the net's own delays had run). net3, the corrected sequence, moves
// the plant with no stall; net1, the paper's blocking net, stalls, each time with p7 alone marked (the
// piston interlock disables al, p7's action). Jumping the clock over settled scans to the next delay's
// end gives the same run as scanning every task interval.
#[test]
fn the_station_nets_run_closed_loop_and_net1_blocks_at_p7() {
    let (net3, _) = station_net("net3", 150, false);
    assert_eq!((net3.violations, net3.stalls), (0, 0), "{net3:?}");
    assert!(net3.uncontrollable > 30 && net3.marked_visits > 0, "{net3:?}");
    let (net1, resets) = station_net("net1", 80, false);
    assert_eq!(net1.violations, 0, "{net1:?}");
    assert!(net1.stalls > 0 && net1.uncontrollable > 0, "{net1:?}");
    // The power-up's reset first, then one per resynchronisation, every one a stall at p7.
    assert_eq!((resets.len() as u64, net1.resyncs), (1 + net1.stalls, net1.stalls), "{resets:?}");
    for marked in &resets[1..] {
        assert_eq!(marked, &["seq.P_p7"], "{resets:?}");
    }
    for (name, events, jumped) in [("net3", 150, &net3), ("net1", 80, &net1)] {
        let (every, _) = station_net(name, events, true);
        assert_eq!(every.trace_sha256, jumped.trace_sha256, "{name}: {every:?}");
        assert_eq!((every.commands, every.stalls), (jumped.commands, jumped.stalls), "{name}");
    }
}

// See: issue 36 (the driver's input levels start at the plant's initial state, derived from the plant
// automata: for the station nets they are the levels `[net] initial` gives the sensors for `verify`).
#[test]
fn the_input_levels_from_the_plants_are_the_nets_initial_values() {
    use codegen::net::condition::Value;
    use codegen::net::interpretation::Direction;
    use codegen::plc::closed_loop::IoMap;
    use codegen::plc::{Avalanche, Encoding, Form};
    for name in ["net1", "net3"] {
        let manifest = repo(&format!("examples/station-rtpn/{name}.toml"));
        let project = codegen::project::Project::load(Path::new(&manifest)).unwrap();
        let form = Form::Event { encoding: Encoding::Int, avalanche: Avalanche::Auto, policy: None };
        let out = project.plc(&form).unwrap().into_event().unwrap();
        let io = IoMap::new(&out.report, project.set.events()).unwrap().with_levels_of(&project.set);
        let net = project.sequence().unwrap().unwrap();
        let mut on = Vec::new();
        for (k, s) in net.signals.iter().enumerate() {
            if s.direction != Direction::Input || !s.carried {
                continue;
            }
            let e = net.event_for(k, true).unwrap().as_u32() as u8;
            let level = io.initial_level(e).unwrap();
            assert_eq!(Value::Is(level), s.initial, "{name}: {}", s.name);
            if level {
                on.push(s.name.as_str());
            }
        }
        on.sort_unstable();
        assert_eq!(on, ["sb", "sl"], "{name}: piston back, arm left");
        // The timeouts a delayed transition reads are held TRUE, the others drawn; the stall waits for
        // t15's 6 s and a scan, in rounds a scan shorter than the 0.5 s of t13, t14 and t19.
        let drive = codegen::plc::net_drive::NetDrive::new(&net);
        assert_eq!(drive.held, ["d05s", "d1s", "d2s", "d4s", "d6s"], "{name}");
        assert_eq!(drive.drawn, ["ack", "si"], "{name}");
        let delays = drive.own_delays(out.report.cycle_ms).unwrap();
        assert_eq!((delays.wait_ms, delays.quantum_ms), (6010, 490), "{name}");
    }
}

// See: issue 36 (the EFA buffer, a module with no manifest, reported 0 marked visits in 501 events through
// `--target plc`, 64 under QEMU: with no scan-cycle form of the runtime's default policy the program
// took `local-queue`, whose fixed plant cycle runs the buffer between levels 1 and 2 for ever; `random`,
// as the firmware's random queues, rules no interleaving out).
#[test]
fn the_efa_buffer_empties_with_both_machines_idle_under_the_default_policy() {
    let (code, json, _) = run(&repo("examples/efa/buffer.wmod"), 500, &[]);
    assert_eq!(code, Some(0), "{json}");
    assert_eq!(json["violations"].as_u64(), Some(0), "{json}");
    assert!(json["marked_visits"].as_u64() >= Some(20), "{json}");
    assert!(json["longest_marked_gap"].as_u64() < Some(100), "{json}");
}

// See: issue 36 (`run --target plc` for the state-based form: every example with a `[state]` section,
// its signals driven through the same state vectors the program is written from, 0 violations).
#[test]
fn every_state_based_example_runs_with_no_violation() {
    let examples: Vec<String> = plc_examples()
        .into_iter()
        .filter(|m| {
            std::fs::read_to_string(m)
                .unwrap()
                .lines()
                .any(|l| l.trim() == "[state]" || l.starts_with("[state."))
        })
        .collect();
    assert!(examples.len() >= 2, "{examples:?}");
    for manifest in &examples {
        let (code, json, _) = run(manifest, 2_000, &["--encoding", "state"]);
        assert_eq!(code, Some(0), "{manifest}: {json}");
        assert_eq!(json["violations"].as_u64(), Some(0), "{manifest}: {json}");
        // A program keeping supervisors' memory (`[state] memory`, the cell) is shown a held round's
        // sensor changes one per scan under its `hold` input, so its memory misses none: no stall, and
        // the marked state reached.
        assert_eq!(json["stalls"].as_u64(), Some(0), "{manifest}: {json}");
        assert!(json["marked_visits"].as_u64() > Some(0), "{manifest}: {json}");
        let scan = &json["scan"];
        let (scans, max, bound) = (
            scan["scans"].as_u64().unwrap(),
            scan["max_statements"].as_u64().unwrap(),
            scan["bound_per_scan"].as_u64().unwrap(),
        );
        assert!(scans > 0 && max > 0 && max <= bound, "{manifest}: {scan}");
        assert!(json["commands"].as_u64().unwrap() > 0, "{manifest}: {json}");
        eprintln!("{manifest} (state): {} events, {scan}, coverage {}", json["events"], json["coverage"]);
    }
}

// See: issue 36 (done when: the factory and the cell closed loop through `--target plc`, 0 violations
// and full coverage).
#[test]
fn the_factory_and_the_cell_run_clean_with_full_coverage_and_their_scans() {
    for (manifest, events) in [("examples/factory/factory.toml", 3_000), ("examples/cell/cell.toml", 20_000)]
    {
        for encoding in ["int", "bits"] {
            let what = format!("{manifest} {encoding}");
            let (code, json, _) = run(&repo(manifest), events, &["--encoding", encoding]);
            assert_eq!(code, Some(0), "{what}: {json}");
            assert_eq!((json["schema"].as_u64(), json["violations"].as_u64()), (Some(3), Some(0)), "{what}");
            assert!(json["full_coverage_at"].is_u64(), "{what}: {json}");
            assert_eq!(json["uncovered"].as_array().map(Vec::len), Some(0), "{what}: {json}");
            for line in json["coverage"].as_array().unwrap() {
                assert_eq!(line["taken"], line["reachable"], "{what}: {line}");
            }
            let link = ["lost", "stalls", "reboots", "resyncs", "garbled", "overflows"];
            for key in link {
                assert_eq!(json[key].as_u64(), Some(0), "{what}: {key}: {json}");
            }
            assert_eq!(json["firmware"]["events_in"], json["uncontrollable"], "{what}");
            assert_eq!(json["firmware"]["commands_out"], json["commands"], "{what}");
            let scan = &json["scan"];
            let (scans, max, bound) = (
                scan["scans"].as_u64().unwrap(),
                scan["max_statements"].as_u64().unwrap(),
                scan["bound_per_scan"].as_u64().unwrap(),
            );
            assert!(scans >= json["uncontrollable"].as_u64().unwrap(), "{what}: one edge per scan: {scan}");
            assert!(0 < max && max <= bound, "{what}: {scan}");
            assert_eq!(scan["cycle_ms"].as_u64(), Some(10), "{what}");
            // The PLC's own clock: scans of 10 ms.
            assert!((json["seconds"].as_f64().unwrap() - scans as f64 * 0.01).abs() < 1e-6, "{what}");
            eprintln!("{what}: {} events, {scan}", json["events"]);
        }
    }
}

// See: issue 36 (the run is a function of its seed: the same seed, the same bytes — the scan count
// and the PLC clock included).
#[test]
fn the_same_seed_gives_the_same_json() {
    let manifest = repo("examples/factory/factory.toml");
    let (_, first, bytes) = run(&manifest, 1_000, &["--seed", "7"]);
    let (_, _, again) = run(&manifest, 1_000, &["--seed", "7"]);
    assert_eq!(String::from_utf8_lossy(&bytes), String::from_utf8_lossy(&again));
    let (_, other, _) = run(&manifest, 1_000, &["--seed", "8"]);
    assert_ne!(first["trace_sha256"], other["trace_sha256"], "another seed, another trace");
}

#[test]
fn a_firmware_option_is_refused_with_exit_2() {
    for extra in [["--layout", "ranked"], ["--sampling", "timer"]] {
        let mut args = vec!["run", "examples/factory/factory.toml", "--target", "plc"];
        args.extend(extra);
        let factory = repo("examples/factory/factory.toml");
        args[1] = &factory;
        let out = codegen(&args);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
        assert!(String::from_utf8_lossy(&out.stderr).contains("go with"), "{extra:?}");
    }
}

// See: issue 36 (`run --target plc` for the hybrid form: both controllers scanned against the plant
// net's own token game, 0 violations, coverage reported, the same seed giving the same bytes).
#[test]
fn both_hybrid_controllers_run_clean_against_their_net_and_the_same_seed_gives_the_same_json() {
    let manifest = repo("examples/hybrid/hybrid.toml");
    for supervisors in ["reduced", "full"] {
        let what = format!("hybrid {supervisors}");
        let (code, json, bytes) = run(&manifest, 400, &["--supervisors", supervisors, "--seed", "3"]);
        assert_eq!(code, Some(0), "{what}: {json}");
        assert_eq!(json["violations"].as_u64(), Some(0), "{what}: {json}");
        assert_eq!(json["target"].as_str(), Some("plc"), "{what}");
        assert!(json["events"].as_u64().unwrap() >= 400, "{what}: {json}");
        for key in ["stalls", "resyncs", "desyncs", "lost"] {
            assert_eq!(json[key].as_u64(), Some(0), "{what}: {key}: {json}");
        }
        // The line comes home again and again; M1's on-delay makes the run seconds of PLC time.
        assert!(json["marked_visits"].as_u64().unwrap() >= 20, "{what}: {json}");
        let coverage = json["coverage"].as_array().unwrap();
        assert_eq!(coverage.len(), 1, "{what}: judged against SUPER: {json}");
        let (taken, reachable) = (coverage[0]["taken"].as_u64().unwrap(), coverage[0]["reachable"].as_u64());
        assert!(taken > 0 && Some(taken) <= reachable, "{what}: {json}");
        let scan = &json["scan"];
        let (scans, max, bound) = (
            scan["scans"].as_u64().unwrap(),
            scan["max_statements"].as_u64().unwrap(),
            scan["bound_per_scan"].as_u64().unwrap(),
        );
        assert!(0 < max && max <= bound, "{what}: {scan}");
        assert!((json["seconds"].as_f64().unwrap() - scans as f64 * 0.01).abs() < 1e-6, "{what}");
        eprintln!("{what}: {} events, {scan}, coverage {}", json["events"], json["coverage"]);
        if supervisors == "reduced" {
            let (_, _, again) = run(&manifest, 400, &["--supervisors", supervisors, "--seed", "3"]);
            assert_eq!(String::from_utf8_lossy(&bytes), String::from_utf8_lossy(&again), "{what}");
        }
    }
}

/// The reduced hybrid controller's text with `from` replaced by `to` (once), run for `events` events.
fn hybrid_mutant(from: &str, to: &str, events: u64) -> codegen::monitor::Report {
    use codegen::plc::hybrid::closed_loop::{run, Program};
    let project = codegen::project::Project::load(Path::new(&repo("examples/hybrid/hybrid.toml"))).unwrap();
    let out = project.plc(&codegen::plc::Form::Hybrid).unwrap().into_hybrid().unwrap();
    let text = &out.files.iter().find(|(n, _)| n == "line_hybrid.st").unwrap().1;
    assert_eq!(text.matches(from).count(), 1, "{from}");
    let text = text.replacen(from, to, 1);
    let program = Program { text: &text, bound_per_scan: 1_000, cycle_ms: 10 };
    let options = codegen::closed_loop::Options::for_events(events);
    let hybrid = project.hybrid.as_ref().unwrap();
    run(program, &hybrid.plant, &hybrid.net_set().unwrap(), "line", &options, &mut |_| {}).unwrap()
}

// See: issue 36 (a broken hybrid program is caught: the monitor and the plant net judge what it does).
#[test]
fn a_hybrid_program_with_a_mutated_rung_is_caught() {
    // M1's rung without its inhibitor contact: M1 starts into a full buffer, which SUPER disables.
    let report = hybrid_mutant("P_p1 AND NOT A_2 AND part1", "P_p1 AND part1", 400);
    assert!(report.violations > 0, "{report:?}");
    assert!(report.findings.iter().any(|f| f.contains("disabled by")), "{:?}", report.findings);
    // M1's finishing rung without its timer: f1 before its 1.5 s, which the plant net refuses.
    let report = hybrid_mutant("P_p2 AND T_t2.Q", "P_p2", 40);
    assert!(report.violations > 0, "{report:?}");
    assert!(report.findings.iter().any(|f| f.contains("of its 1500 ms delay")), "{:?}", report.findings);
    // M2's motor never on: the plant sees it off while M2 works (and never reports M2 done).
    let report = hybrid_mutant("mot2 := P_p4;", "mot2 := FALSE;", 400);
    assert!(report.findings.iter().any(|f| f.contains("actuator mot2 is off")), "{:?}", report.findings);
    // M1's motor always on: wrong from the first scan, so the run ends at its first violation rather
    // than restarting into the same one for ever.
    let report = hybrid_mutant("mot1 := P_p2;", "mot1 := TRUE;", 400);
    assert_eq!((report.violations, report.events), (1, 0), "{report:?}");
}

/// The cylinder's event-based program with `from` replaced by `to` (every occurrence), run closed loop
/// with its timers for `events` events.
fn cylinder_mutant(from: &str, to: &str, events: u64) -> codegen::monitor::Report {
    use codegen::plc::{Avalanche, Encoding, Form};
    let project =
        codegen::project::Project::load(Path::new(&repo("examples/cylinder/cylinder.toml"))).unwrap();
    let form = Form::Event { encoding: Encoding::Int, avalanche: Avalanche::Auto, policy: None };
    let out = project.plc(&form).unwrap().into_event().unwrap();
    let text = &out.files[0].1;
    assert!(text.contains(from), "{from}");
    let text = text.replace(from, to);
    let mut options = codegen::closed_loop::Options::for_events(events);
    options.timers = project.timers.clone();
    options.plant.answer_delay_us = vec![("extend".into(), (1_000_000, 3_000_000))];
    codegen::plc::closed_loop::run(&text, &out.report, &project.set, "cylinder", &options, &mut |_| {})
        .unwrap()
}

// See: issue 37 (the monitor judges the timed events: a program whose timer is wrong is caught).
#[test]
fn a_cylinder_program_with_a_wrong_timer_is_caught() {
    // As written: every timeout on time, both paths run — the alarm after a late end switch too (the
    // switch after the timeout, before the alarm: the deadline round's split), so coverage is full.
    let report = cylinder_mutant("T#2000ms", "T#2000ms", 200);
    let timeouts = report.timeouts.as_ref().unwrap();
    assert_eq!((report.violations, timeouts.early, timeouts.missing), (0, 0, 0), "{report:?}");
    assert!(timeouts.on_time > 0, "{report:?}");
    assert!(report.full_coverage(), "{:?}", report.coverage);
    // The TON's delay doubled: the timeout does not come by its deadline and slack.
    let report = cylinder_mutant("T#2000ms", "T#4000ms", 200);
    let timeouts = report.timeouts.unwrap();
    assert!(timeouts.missing > 0 && report.violations >= timeouts.missing, "{report:?}");
    assert!(report.findings.iter().any(|f| f.contains("timeout_missing")), "{:?}", report.findings);
    // Halved: it comes before its deadline.
    let report = cylinder_mutant("T#2000ms", "T#1000ms", 200);
    let timeouts = report.timeouts.unwrap();
    assert!(timeouts.early > 0, "{report:?}");
    assert!(report.findings.iter().any(|f| f.contains("timeout_early")), "{:?}", report.findings);
    // Never raised: the timer's running flag never set.
    let report = cylinder_mutant("run_T_ext := TRUE;", "run_T_ext := FALSE;", 200);
    assert!(report.timeouts.unwrap().missing > 0, "{report:?}");
}

/// The EFA buffer's state-based program with `from` replaced by `to` (every occurrence), run closed
/// loop for `events` events.
fn buffer_state_mutant(from: &str, to: &str, events: u64) -> codegen::monitor::Report {
    use codegen::plc::state_based::{closed_loop, Engine, StateOptions};
    use codegen::plc::Form;
    let project =
        codegen::project::Project::load(Path::new(&repo("examples/efa/buffer-state.toml"))).unwrap();
    let form = Form::State { options: StateOptions::default(), engine: Engine::Explicit };
    let mut out = project.plc(&form).unwrap().into_state().unwrap();
    let text = &mut out.files[0].1;
    assert!(text.contains(from), "{from}");
    *text = text.replace(from, to);
    let options = codegen::closed_loop::Options::for_events(events);
    closed_loop::run(&out, &project.set, "efa_buffer_state", &options, &mut |_| {}).unwrap()
}

// See: issue 37 (the state-based program over a module with variables: the count an INT, the guards
// contacts on the rungs, run closed loop with 0 violations and the marked state visited; a wrong guard
// is caught by the monitor).
#[test]
fn the_efa_buffer_state_based_runs_clean_and_a_wrong_guard_is_caught() {
    let (code, json, _) = run(&repo("examples/efa/buffer-state.toml"), 500, &["--encoding", "state"]);
    assert_eq!(code, Some(0), "{json}");
    assert_eq!(json["violations"].as_u64(), Some(0), "{json}");
    assert!(json["marked_visits"].as_u64() > Some(0), "{json}");
    assert!(json["commands"].as_u64() > Some(100), "{json}");
    // As written, under the test's own driver: clean.
    let report = buffer_state_mutant("n_2 <= 1", "n_2 <= 1", 300);
    assert_eq!(report.violations, 0, "{report:?}");
    // start1's guard loosened to the count's whole range: M1 fills the full buffer, which the
    // supervisor forbids.
    let report = buffer_state_mutant("n_2 <= 1", "n_2 <= 2", 300);
    assert!(report.violations > 0, "{report:?}");
}

// See: issue 36 (the station under its own local-queue policy moves).
#[test]
fn the_station_under_its_local_queue_gets_past_the_fixed_rounds_first_cycle() {
    // The [plc] policy is `local-queue`: a fixed round over the plants. Modelled as a uniform choice,
    // the steering held the plant back for target commands the round never takes where it stands, and
    // the closed loop went round one cycle of actuator toggles with 71 transitions taken, whatever the
    // length of the run. Mirroring the round's cursors, the steering takes more within 100 events.
    let (code, json, _) = run(&repo("examples/station/station.toml"), 100, &[]);
    assert_eq!(code, Some(0), "{json}");
    assert_eq!(json["violations"], 0, "{json}");
    let taken: u64 = json["coverage"].as_array().unwrap().iter().map(|c| c["taken"].as_u64().unwrap()).sum();
    assert!(taken > 100, "{taken} transitions taken: {json}");
}

// See: issue 37 (timers run in the event-based program only: the other forms refuse them, named).
#[test]
fn timers_with_a_form_that_has_none_are_refused() {
    let cylinder = repo("examples/cylinder/cylinder.toml");
    let dir = std::env::temp_dir().join(format!("cli_run_plc_timers_{}", std::process::id()));
    let dir = dir.to_str().unwrap();
    for args in [
        &["plc", &cylinder, "--encoding", "state", "-o", dir][..],
        &["run", &cylinder, "--target", "plc", "--encoding", "state", "--events", "10"][..],
    ] {
        let out = codegen(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains("cylinder.toml: [[timers]] run in the event-based program only"), "{err}");
        assert!(err.contains("the state-based program has no timeout event"), "{err}");
    }
    assert!(!Path::new(dir).exists(), "refused before anything is written");
}

/// The factory's program behind the wrapper, its counted scans' statement counts noted, driven by a
/// host that sends `chunks` one write at a time: after a chunk ending in STEP, STATUS or RESET it reads
/// until that many answers (SYNC, STATUS, READY) came. Returns the frames it read from the first RESET's
/// READY on (before it the program runs from power-up, as long as the machine's timing lets it) and the
/// statements of each scan the figures count, in order.
fn factory_wrapper(chunks: &[Vec<u8>]) -> (Vec<codegen::link::protocol::Frame>, Vec<u64>) {
    use codegen::link::protocol::{Decoder, Frame, EXIT, READY, RESET, STATUS, STEP};
    use codegen::link::ByteLink;
    use codegen::plc::closed_loop::{net_driver, spawn_plc};
    use codegen::plc::{Avalanche, Encoding, Form};
    use std::sync::{Arc, Mutex};
    use std::time::Duration;

    let project = codegen::project::Project::load(Path::new(&repo("examples/factory/factory.toml"))).unwrap();
    let form = Form::Event { encoding: Encoding::Int, avalanche: Avalanche::Auto, policy: None };
    let out = project.plc(&form).unwrap().into_event().unwrap();
    let driver = net_driver(&out.files[0].1, &out.report, &project.set, None, 1).unwrap();
    let statements = Arc::new(Mutex::new(Vec::new()));
    let (mut host, target) = codegen::link::memory::pair();
    let (on_scan, on_reset) = (Arc::clone(&statements), Arc::clone(&statements));
    let noted = Watched {
        driver,
        on_scan: move |scan: &Scan| on_scan.lock().unwrap().extend(scan.statements),
        on_reset: move |_: &Driver| on_reset.lock().unwrap().clear(),
    };
    let plc = spawn_plc(noted, target);
    let (mut decoder, mut frames, mut buf) = (Decoder::default(), Vec::new(), [0u8; 64]);
    let mut read_until = |host: &mut codegen::link::memory::MemoryLink, answers: usize| {
        let mut seen = 0;
        while seen < answers {
            let n = host.recv(&mut buf, Duration::from_secs(30)).unwrap();
            assert!(n > 0, "the wrapper answers: {frames:?}");
            for frame in buf[..n].iter().filter_map(|&b| decoder.push(b)) {
                seen += usize::from(matches!(frame, Frame::Sync | Frame::Status(_) | Frame::Ready));
                frames.push(frame);
            }
        }
    };
    read_until(&mut host, 1);
    for chunk in chunks {
        host.send(chunk).unwrap();
        read_until(&mut host, chunk.iter().filter(|&&b| [STEP, STATUS, RESET, READY].contains(&b)).count());
    }
    host.send(&[EXIT]).unwrap();
    plc.join().unwrap().unwrap();
    let statements = statements.lock().unwrap().clone();
    let reset = frames.iter().rposition(|&f| f == Frame::Ready).unwrap();
    (frames.split_off(reset), statements)
}

// The flaky `the_same_seed_gives_the_same_json` (once under load: `scan.max_statements` 80 for 81): the
// wrapper answered a step's SYNC with a command's pulse still running, and the scans it ran down in
// before the host's next events came were as many as the machine's timing gave — so an edge's scan
// counted the pulse's countdown or not. Two hosts, one sending the next step at once (in the same write
// as the STEP before it, the extreme of a fast host), the other letting the wrapper run scans first
// (three writes it takes one per scan, then STATUS), must see the same frames and the same scans.
#[test]
fn a_steps_answer_finds_the_program_at_rest_however_soon_the_host_goes_on() {
    use codegen::link::protocol::{HOLD, RESET, STATUS, STEP};
    let finish1 = {
        let project =
            codegen::project::Project::load(Path::new(&repo("examples/factory/factory.toml"))).unwrap();
        project.set.events().id("finish1").unwrap().as_u32() as u8
    };
    let start = vec![vec![HOLD, STATUS], vec![RESET]];
    let tail = vec![vec![HOLD], vec![HOLD], vec![HOLD], vec![STATUS]];
    let mut hasty = start.clone();
    hasty.push(vec![STEP, finish1, STEP, STEP]);
    hasty.extend(tail.clone());
    let mut patient = start;
    for step in [vec![STEP], vec![finish1, STEP], vec![STEP]] {
        patient.push(step);
        patient.extend(tail.clone());
    }
    let (fast, fast_scans) = factory_wrapper(&hasty);
    let (slow, slow_scans) = factory_wrapper(&patient);
    let commands = |frames: &[codegen::link::protocol::Frame]| -> Vec<codegen::link::protocol::Frame> {
        frames.iter().filter(|f| matches!(f, codegen::link::protocol::Frame::Command(_))).copied().collect()
    };
    assert_eq!(commands(&fast).len(), 3, "start1; start2 after finish1; start1: {fast:?}");
    assert_eq!(commands(&fast), commands(&slow), "{fast:?}\n{slow:?}");
    assert_eq!(fast_scans, slow_scans, "the counted scans' statements");
    assert_eq!(fast.last(), slow.last(), "the same counters");
}
