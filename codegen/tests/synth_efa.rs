//! Supremica modules with variables (EFA): the published kyllercg buffer unfolds to the counter it
//! models, and an EFA specification synthesises, with either engine, the supervisor its plain twin
//! gives; the contract (`synth MODULE --monolithic -o DIR --format wmod`, then `convert` to a
//! libFAUDES `.gen`) as written; our modules of the Huck-KIT collaboration cell's two scenarios, whose
//! specification reads the plants' variables, synthesise the supervisors Supremica published.

use std::collections::{BTreeSet, HashMap, VecDeque};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use codegen::formats::{read_path, wmod};
use codegen::model::{Automaton, Kind};
use codegen::synth::language::equal;
use codegen::synth::minimize;

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// The counter `put`/`get` over 0..=max, marked at 0.
fn counter(max: usize) -> Automaton {
    let mut a = Automaton::new("counter", Kind::Plant);
    let states: Vec<_> = (0..=max).map(|k| a.add_state(format!("c{k}"), k == 0).unwrap()).collect();
    let (get, put) = (a.add_event("get", true).unwrap(), a.add_event("put", true).unwrap());
    for k in 0..max {
        a.add_transition(states[k], put, states[k + 1]);
        a.add_transition(states[k + 1], get, states[k]);
    }
    a.initial = Some(states[0]);
    a
}

/// The kyllercg module with only the component called `keep`.
fn only(text: &str, keep: &str, drop: &str) -> Automaton {
    let open = format!("<SimpleComponent Kind=\"PLANT\" Name=\"{drop}\">");
    let start = text.find(&open).unwrap();
    let end = start + text[start..].find("</SimpleComponent>").unwrap() + "</SimpleComponent>".len();
    let text = format!("{}{}", &text[..start], &text[end..]);
    let mut a = wmod::read(Path::new("kyllercg_buffer.wmod"), &text).unwrap();
    assert_eq!(a.len(), 1);
    assert_eq!(a[0].name, keep);
    a.remove(0)
}

#[test]
fn kyllercg_buffer_and_buffer_min_are_the_same_counter_0_to_3() {
    let file = repo("codegen/tests/data/efa/kyllercg_buffer.wmod");
    let both = read_path(&file).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(both.len(), 1, "the two components share item_qty: one product");
    assert_eq!((both[0].name.as_str(), both[0].kind), ("Buffer_Min||Buffer", Kind::Plant));
    assert_eq!((both[0].states.len(), both[0].transitions.len(), both[0].marked_count()), (6, 10, 1));
    let bytes = std::fs::read(&file).unwrap();
    let text: String = bytes.iter().map(|&b| char::from(b)).collect(); // windows-1252 comment only
    let buffer = only(&text, "Buffer", "Buffer_Min");
    let buffer_min = only(&text, "Buffer_Min", "Buffer");
    assert_eq!(buffer_min.states.len(), 4);
    for a in [&both[0], &buffer, &buffer_min] {
        assert_eq!(equal(a, &counter(3)).unwrap(), None, "{}", a.name);
    }
}

fn synth(module: &Path, engine: &str, dir: &Path) -> Automaton {
    let _ = std::fs::remove_dir_all(dir);
    let out = codegen(&[
        "synth",
        module.to_str().unwrap(),
        "--monolithic",
        "--engine",
        engine,
        "-o",
        dir.to_str().unwrap(),
        "--format",
        "wmod",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // The module is named after the manifest's `name`, or the module's file.
    let mut written: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(written.len(), 1, "{written:?}");
    let written = written.remove(0);
    let mut sups: Vec<Automaton> = read_path(&written)
        .unwrap_or_else(|e| panic!("{e}"))
        .into_iter()
        .filter(|a| a.kind == Kind::Supervisor)
        .collect();
    assert_eq!(sups.len(), 1);
    // The contract as written: `convert` turns the module into a libFAUDES generator, its supervisor.
    let gen = dir.join("supervisor.gen");
    let out = codegen(&["convert", written.to_str().unwrap(), gen.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains(&format!("wrote the supervisor '{}'", sups[0].name))
    );
    let back = read_path(&gen).unwrap_or_else(|e| panic!("{e}")).remove(0);
    assert_eq!(equal(&back, &sups[0]).unwrap(), None);
    // --component picks another automaton of the module: a plant.
    let plant = read_path(&written).unwrap().into_iter().find(|a| a.kind == Kind::Plant).unwrap();
    let out =
        codegen(&["convert", written.to_str().unwrap(), gen.to_str().unwrap(), "--component", &plant.name]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(equal(&read_path(&gen).unwrap().remove(0), &plant).unwrap(), None);
    // A module without a supervisor gives no answer of its own: the refusal names the way.
    if module.extension().is_some_and(|e| e == "wmod") {
        let unfolded = dir.join("unfolded.wmod");
        let out = codegen(&["convert", module.to_str().unwrap(), unfolded.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let out = codegen(&["convert", unfolded.to_str().unwrap(), gen.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains("pick one with --component NAME"));
    }
    sups.remove(0)
}

#[test]
fn an_efa_spec_synthesises_its_plain_twins_supervisor_with_both_engines() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("synth_efa");
    let plain = synth(&repo("codegen/tests/data/efa/buffer_plain.wmod"), "explicit", &tmp.join("plain"));
    assert_eq!((plain.states.len(), plain.transitions.len()), (10, 16));
    for engine in ["explicit", "symbolic"] {
        let efa = synth(&repo("examples/efa/buffer.wmod"), engine, &tmp.join(engine));
        assert_eq!(equal(&efa, &plain).unwrap(), None, "{engine}");
    }
}

/// The natural projection of `a` onto the events not in `hidden`, by subset construction: marked
/// where a merged state is.
fn project(a: &Automaton, hidden: &[&str]) -> Automaton {
    let silent = |e: usize| hidden.contains(&a.events[e].name.as_str());
    let closure = |set: BTreeSet<usize>| {
        let mut set = set;
        let mut todo: Vec<usize> = set.iter().copied().collect();
        while let Some(s) = todo.pop() {
            for t in a.transitions.iter().filter(|t| t.source.index() == s && silent(t.event.index())) {
                if set.insert(t.target.index()) {
                    todo.push(t.target.index());
                }
            }
        }
        set
    };
    let mut p = Automaton::new(format!("P({})", a.name), a.kind);
    let kept: Vec<usize> = (0..a.events.len()).filter(|&e| !silent(e)).collect();
    let ids: Vec<_> = kept
        .iter()
        .map(|&e| p.add_event(a.events[e].name.clone(), a.events[e].controllable).unwrap())
        .collect();
    let mut seen: HashMap<BTreeSet<usize>, _> = HashMap::new();
    let start = closure(BTreeSet::from([a.initial.unwrap().index()]));
    let mut queue = VecDeque::from([start.clone()]);
    let add = |p: &mut Automaton, set: &BTreeSet<usize>| {
        p.add_state(format!("{set:?}"), set.iter().any(|&s| a.states[s].marked)).unwrap()
    };
    let first = add(&mut p, &start);
    p.initial = Some(first);
    seen.insert(start, first);
    while let Some(set) = queue.pop_front() {
        let source = seen[&set];
        for (&e, &id) in kept.iter().zip(&ids) {
            let next: BTreeSet<usize> = a
                .transitions
                .iter()
                .filter(|t| t.event.index() == e && set.contains(&t.source.index()))
                .map(|t| t.target.index())
                .collect();
            if next.is_empty() {
                continue;
            }
            let next = closure(next);
            let target = match seen.get(&next) {
                Some(&t) => t,
                None => {
                    let t = add(&mut p, &next);
                    seen.insert(next.clone(), t);
                    queue.push_back(next);
                    t
                }
            };
            p.add_transition(source, id, target);
        }
    }
    p
}

fn figures(a: &Automaton) -> (usize, usize, usize) {
    (a.states.len(), a.transitions.len(), a.marked_count())
}

/// Supremica's supervisors for the cell (`models/supremica/XML/supervisor_scenario_{A,B}.xml` in
/// Huck-KIT/supremica-coppeliasim-hrc): A is `min(detm(sup(…)//{robot events}))`, 23 states, 45
/// transitions, 8 marked; B is `sup(…)//{robot_safety_stop}` (the hidden event renamed `tau`), 90
/// states, 182 transitions, 45 marked. Their languages equal ours exactly (libFAUDES'
/// `LanguageEquality`, marked and closed, run against the published files, docs/formats.md); the
/// repository has no licence, so its files stay out of this one and the test holds their figures.
#[test]
fn the_collaboration_cells_two_scenarios_synthesise_the_supervisors_supremica_published() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("synth_efa_hrc");
    let a = synth(&repo("examples/efa/hrc/scenario_a.toml"), "explicit", &tmp.join("a"));
    assert_eq!(figures(&a), (117, 264, 58));
    let robot = ["robot_move_to_housing", "robot_insert_gearwheel", "robot_move_back"];
    let published = minimize(&project(&a, &robot)).unwrap();
    assert_eq!(figures(&published), (23, 45, 8));
    for engine in ["explicit", "symbolic"] {
        let b = synth(&repo("examples/efa/hrc/scenario_b.toml"), engine, &tmp.join(engine));
        assert_eq!(figures(&b), (90, 182, 45), "{engine}");
    }
}

/// `codegen run MODULE --target TARGET --events N --json`: its exit status and JSON report.
fn run(module: &Path, target: &str, events: u64) -> (Option<i32>, serde_json::Value) {
    let events = events.to_string();
    let out = codegen(&["run", module.to_str().unwrap(), "--target", target, "--events", &events, "--json"]);
    let json = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{target}: {e}: {}", String::from_utf8_lossy(&out.stderr)));
    (out.status.code(), json)
}

/// The EFA buffer example runs closed loop as users run any module: its firmware under QEMU and its PLC
/// program scanned against the virtual plant, 0 violations and every transition of the supervisor
/// taken. The program is written from the unfolded supervisor (no guards over the variable yet).
#[test]
fn the_efa_example_runs_closed_loop_under_qemu_and_as_a_plc_program() {
    let module = repo("examples/efa/buffer.wmod");
    for target in ["qemu", "plc"] {
        let (code, json) = run(&module, target, 300);
        assert_eq!(code, Some(0), "{target}: {json}");
        assert_eq!(json["target"].as_str(), Some(target), "{json}");
        assert_eq!(json["violations"].as_u64(), Some(0), "{target}: {json}");
        assert!(json["events"].as_u64().unwrap() >= 300, "{target}: {json}");
        assert!(json["full_coverage_at"].as_u64().is_some(), "{target}: {json}");
    }
}
