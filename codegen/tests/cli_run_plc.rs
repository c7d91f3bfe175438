//! `codegen run --target plc` as a binary: the PLC program of every example with a `[plc]` section
//! scanned closed loop by the interpreter, exit 0 with `"violations": 0` and a marked visit in the JSON;
//! the factory and the cell with full coverage and their scan figures; the same seed giving the same
//! bytes; exit 2 for the firmware's options. (Exit 1 on a violation: `tests/plc.rs` runs a broken program through the same
//! `plc::closed_loop::run` the command calls, and the exit status is the QEMU run's `finish`.)

use std::path::Path;
use std::process::{Command, Output};

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
    run(program, &hybrid.plant, &project.set, "line", &options, &mut |_| {}).unwrap()
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
