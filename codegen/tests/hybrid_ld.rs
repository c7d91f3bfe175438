//! The hybrid example's two controllers run closed loop: their rungs scanned as a PLC runs Ladder
//! Diagram (top to bottom, coils as they are reached, `TON` on the scan clock) against a virtual plant
//! of the line's devices, judged against the net's reachability graph and the specification. And the
//! project's hybrid stages: a net the program cannot keep in bits, a transition without an event, a
//! ready supervisor, and the coupled net checked against plant ‖ supervisor.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use codegen::model::{Automaton, StateId};
use codegen::plc::hybrid::{coupled, Output, Side};
use codegen::plc::{Form, PlcError, Written};
use codegen::project::Project;
use codegen::scan::ld::{CoilKind, Element, Rung};
use codegen::synth::{language, product, Config};

const CYCLE_MS: u64 = 10;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/hybrid")
}

/// The example's manifest text with every path absolute, so that a changed copy can stand anywhere.
fn manifest_text() -> String {
    let r = root().display().to_string();
    std::fs::read_to_string(root().join("hybrid.toml"))
        .unwrap()
        .replace("\"specs/buffer.gen\"", &format!("\"{r}/specs/buffer.gen\""))
        .replace("\"line.pnml\"", &format!("\"{r}/line.pnml\""))
}

/// `text` as a manifest in a scratch directory of its own.
fn scratch(tag: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hybrid_ld").join(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("hybrid.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The hybrid controllers of `project`, or the error's message.
fn hybrid(project: &Project) -> Result<Output, String> {
    match project.plc(&Form::Hybrid).map_err(|e| e.to_string())? {
        Written::Hybrid(out) => Ok(out),
        _ => unreachable!("a hybrid manifest writes a hybrid controller"),
    }
}

fn example() -> (Project, Output, Automaton) {
    let project = Project::load(&root().join("hybrid.toml")).unwrap();
    let out = hybrid(&project).unwrap();
    let spec = codegen::formats::read_path(&root().join("specs/buffer.gen")).unwrap().remove(0);
    (project, out, spec)
}

/// The state after `e` from `s` (an automaton without `e` stays), or None when it refuses `e`.
fn step(a: &Automaton, s: StateId, e: &str) -> Option<StateId> {
    let Some(id) = a.event_id(e) else { return Some(s) };
    a.transitions.iter().find(|t| t.source == s && t.event == id).map(|t| t.target)
}

/// A PLC scanning a controller's rungs.
struct Scan<'a> {
    rungs: &'a [Rung],
    vars: BTreeMap<String, bool>,
    /// Per timer, the scan time its input turned on.
    started: BTreeMap<String, Option<u64>>,
    now: u64,
}

impl Scan<'_> {
    fn get(&self, v: &str) -> bool {
        match v.strip_suffix(".Q") {
            Some(timer) => self.timer_done(timer),
            None => self.vars.get(v).copied().unwrap_or(false),
        }
    }

    fn timer_done(&self, timer: &str) -> bool {
        matches!(self.started.get(timer), Some(Some(t0)) if self.now - t0 >= self.preset(timer))
    }

    fn preset(&self, timer: &str) -> u64 {
        self.rungs
            .iter()
            .flat_map(|r| &r.coils)
            .find_map(|c| match c.kind {
                CoilKind::OnDelay(ms) if c.variable == timer => Some(u64::from(ms)),
                _ => None,
            })
            .unwrap()
    }

    fn scan(&mut self) {
        for r in self.rungs {
            let on = r.condition.conducts(&|v| self.get(v));
            for c in &r.coils {
                match c.kind {
                    CoilKind::Set if on => {
                        self.vars.insert(c.variable.clone(), true);
                    }
                    CoilKind::Reset if on => {
                        self.vars.insert(c.variable.clone(), false);
                    }
                    CoilKind::Out => {
                        self.vars.insert(c.variable.clone(), on);
                    }
                    CoilKind::OnDelay(_) => {
                        let t0 = self.started.entry(c.variable.clone()).or_insert(None);
                        *t0 = if on { Some(t0.unwrap_or(self.now)) } else { None };
                    }
                    _ => {}
                }
            }
        }
        self.now += CYCLE_MS;
    }
}

/// What one run saw.
#[derive(Debug, PartialEq, Eq)]
struct Run {
    /// (scan, event) of every firing.
    trace: Vec<(u64, String)>,
    violations: usize,
    /// Returns to the marked state of plant and specification (a finished production cycle).
    cycles: usize,
}

/// `scans` scans of `side`'s controller against the line's devices: a part arrives at M1 at random
/// (`part1`), M2's sensor (`done2`) answers 1 to 4 scans after its motor started; every firing is checked
/// against the plant (the net's reachability graph), the specification and the supervisor, whose state
/// must be where the auto-net's token is.
fn run(project: &Project, side: &Side, spec: &Automaton, seed: u64, scans: u64) -> Run {
    let plant = &project.hybrid.as_ref().unwrap().plant;
    let (net, graph) = (&plant.net.net, &plant.graph);
    let c = &side.controller;
    let mut plc = Scan { rungs: &c.rungs, vars: BTreeMap::new(), started: BTreeMap::new(), now: 0 };
    let places: Vec<String> = net.places.iter().map(|p| format!("P_{}", p.id)).collect();
    let states: Vec<&String> = c.bools.iter().filter(|(v, _)| v.starts_with("A_")).map(|(v, _)| v).collect();
    let mut rng = seed;
    let mut next = move || {
        rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (rng >> 33) as u32
    };
    let (mut g, mut e, mut x) =
        (graph.initial.unwrap(), spec.initial.unwrap(), side.supervisor.initial.unwrap());
    let mut busy2 = 0;
    let mut result = Run { trace: Vec::new(), violations: 0, cycles: 0 };
    plc.scan(); // the first scan sets the initial marking
    for scan in 1..scans {
        plc.vars.insert("part1".into(), next() % 3 == 0);
        busy2 = if plc.get("mot2") { busy2 + 1 } else { 0 };
        let answer = 1 + u64::from(next() % 4);
        plc.vars.insert("done2".into(), busy2 >= answer);
        let before: Vec<u32> = places.iter().map(|p| u32::from(plc.get(p))).collect();
        plc.scan();
        let after: Vec<u32> = places.iter().map(|p| u32::from(plc.get(p))).collect();
        if before != after {
            let fired: Vec<usize> = (0..net.transitions.len())
                .filter(|&t| {
                    net.state_enabled(t, &before) && net.fire(t, &before).as_deref() == Some(&after[..])
                })
                .collect();
            let [t] = fired[..] else {
                result.violations += 1;
                continue;
            };
            let event = &plant.labels.events[t];
            result.trace.push((scan, event.clone()));
            match (step(graph, g, event), step(spec, e, event), step(&side.supervisor, x, event)) {
                (Some(g2), Some(e2), Some(x2)) => (g, e, x) = (g2, e2, x2),
                _ => result.violations += 1,
            }
            if graph.states[g.index()].marked && spec.states[e.index()].marked {
                result.cycles += 1;
            }
        }
        let tokens: Vec<usize> = (0..states.len()).filter(|&k| plc.get(states[k])).collect();
        if tokens != [x.index()] {
            result.violations += 1;
        }
    }
    result
}

#[test]
fn both_controllers_run_the_line_safely_again_and_again_and_alike() {
    let (project, out, spec) = example();
    for seed in [1, 2, 3] {
        let reduced = run(&project, &out.reduced, &spec, seed, 20_000);
        assert_eq!(reduced.violations, 0, "seed {seed}: {reduced:?}");
        assert!(reduced.cycles >= 20, "seed {seed}: {} cycles", reduced.cycles);
        // The full supervisor's controller makes the same moves on the same sensor readings.
        let full = run(&project, &out.full, &spec, seed, 20_000);
        assert_eq!(full, reduced, "seed {seed}");
        // M1's work, a delay of 1.5 s, lasts at least that long: every f1 150 scans after its s1 or more.
        let mut started = None;
        for (scan, e) in &reduced.trace {
            match e.as_str() {
                "s1" => started = Some(*scan),
                "f1" => assert!(scan - started.take().unwrap() >= 150, "seed {seed}: f1 at {scan}"),
                _ => {}
            }
        }
    }
    // And the closed loops' languages are equal as automata.
    let graph = &project.hybrid.as_ref().unwrap().plant.graph;
    let closed = |s: &Automaton| product(&[graph.clone(), s.clone()], &Config::default()).unwrap();
    assert!(language::equal(&closed(&out.full.supervisor), &closed(&out.reduced.supervisor))
        .unwrap()
        .is_none());
}

#[test]
fn a_controller_without_its_inhibitor_arcs_overflows_the_buffer() {
    // The judge can fail: drop the inhibitor contacts (the auto-net's places in the plant's rungs).
    let (project, out, spec) = example();
    let mut side = out.reduced.clone();
    for r in &mut side.controller.rungs {
        if let Element::Series(es) = &mut r.condition {
            es.retain(
                |e| !matches!(e, Element::Contact { variable, negated: true } if variable.starts_with("A_")),
            );
        }
    }
    assert!(run(&project, &side, &spec, 1, 20_000).violations > 0);
}

#[test]
fn the_coupled_net_is_checked_against_plant_and_supervisor() {
    let (project, out, _) = example();
    let h = project.hybrid.as_ref().unwrap();
    let check = |side: &Side, inhibitors: &[(usize, usize)]| -> Result<(), Box<PlcError>> {
        Ok(coupled::check(
            &h.plant.net.net,
            &h.plant.labels,
            &h.plant.graph,
            &out.full.supervisor,
            &side.supervisor,
            inhibitors,
            &Config::default(),
        )?)
    };
    for side in [&out.reduced, &out.full] {
        check(side, &side.controller.inhibitors).unwrap();
        // The coupled net is a net: its reachability graph is the closed loop, one marking per state.
        let (net, labels) = coupled::coupled(
            &h.plant.net.net,
            &h.plant.labels,
            &side.supervisor,
            &side.controller.inhibitors,
        );
        let graph = codegen::net::reachability::reachability(&net, &labels, "closed", 1000).unwrap();
        let closed = product(&[h.plant.graph.clone(), side.supervisor.clone()], &Config::default()).unwrap();
        assert_eq!(graph.states.len(), closed.states.len(), "{}", side.supervisor.name);
    }
    // Without one of its inhibitor arcs the reduced controller lets the buffer overflow: refused.
    let fewer = &out.reduced.controller.inhibitors[1..];
    let err = check(&out.reduced, fewer).unwrap_err();
    assert!(matches!(*err, PlcError::Coupling { .. }), "{err}");
    assert!(err.to_string().contains("differs from plant ‖ supervisor after"), "{err}");
}

#[test]
fn the_example_gives_the_table_4_comparison() {
    let (_, out, _) = example();
    let (r, f) = (out.report.reduced, out.report.full);
    assert_eq!(out.report.plant, (4, 8));
    assert_eq!((r.supervisor_states, f.supervisor_states), (3, 10));
    // Fewer places, transitions, arcs, bits and bytes with the reduced supervisor; one timer each.
    assert!(r.places < f.places && r.transitions < f.transitions && r.inhibitor_arcs < f.inhibitor_arcs);
    assert!(r.memory_bits < f.memory_bits && r.program_bytes < f.program_bytes);
    assert_eq!((r.timers, f.timers), (1, 1));
    // The buffer's two events chain in the reduced supervisor (0 -f1-> 1 -f1-> 2): AEEM on them.
    assert_eq!(out.report.aeem_reduced, ["f1", "s2"]);
    let condat: Vec<(&str, Vec<&str>)> =
        out.report.condat.iter().map(|(k, v)| (k.as_str(), v.iter().map(String::as_str).collect())).collect();
    assert_eq!(condat, [("(p1.p3,empty)", vec!["s2"]), ("(p1.p3,full)", vec!["s1"])]);
    let names: Vec<&str> = out.files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "line_hybrid.st",
            "line_hybrid_config.st",
            "line_hybrid.xml",
            "line_hybrid_full.st",
            "line_hybrid_full_config.st",
            "line_hybrid_full.xml"
        ]
    );
    let xml = &out.files[2].1;
    assert!(xml.contains("<body><LD>") && xml.contains("typeName=\"TON\" instanceName=\"T_t2\""));
    // Every file names every input with its hash: the manifest, the net and the specification.
    for (name, text) in &out.files {
        for input in ["hybrid.toml", "line.pnml", "specs/buffer.gen"] {
            assert!(text.lines().any(|l| l.len() > 66 && l.ends_with(input)), "{name} lacks {input}");
        }
    }
}

#[test]
fn a_net_with_two_tokens_in_p1_is_refused_naming_p1() {
    let dir = scratch("two-tokens", "");
    let pnml = dir.with_file_name("line.pnml");
    let net = std::fs::read_to_string(root().join("line.pnml")).unwrap().replacen(
        "<initialMarking><text>1</text></initialMarking></place>",
        "<initialMarking><text>2</text></initialMarking></place>",
        1,
    );
    std::fs::write(&pnml, net).unwrap();
    let text = manifest_text().replace(
        &format!("\"{}/line.pnml\"", root().display()),
        &format!("{:?}", pnml.display().to_string()),
    );
    let project = Project::load(&scratch("two-tokens", &text)).unwrap();
    let err = hybrid(&project).unwrap_err();
    assert_eq!(
        err,
        "place 'p1' holds 2 tokens in the initial marking: a PLC program keeps a place in one BOOL, so only safe nets are written"
    );
}

#[test]
fn a_transition_without_an_event_is_named_with_its_line() {
    let text = manifest_text().replace("t4 = \"f2\"\n", "");
    let err = Project::load(&scratch("no-event", &text)).unwrap_err().to_string();
    assert!(err.ends_with("hybrid.toml:10: transition 't4' has no event in [hybrid.events]"), "{err}");
    let text = manifest_text().replace("t4 = \"f2\"", "t9 = \"f2\"");
    let err = Project::load(&scratch("no-transition", &text)).unwrap_err().to_string();
    assert!(err.ends_with("hybrid.toml:32: hybrid.events.t9: the net has no such transition"), "{err}");
}

/// The example's manifest with `supervisors = [file]` in place of its specifications.
fn with_supervisor(sup: &Automaton, name: &str) -> PathBuf {
    let path = scratch(name, "");
    let file = path.with_file_name(name);
    codegen::formats::write_path(&file, std::slice::from_ref(sup)).unwrap();
    let spec = format!("specs = [\"{}/specs/buffer.gen\"]", root().display());
    let text = manifest_text().replace(&spec, &format!("supervisors = [{:?}]", file.display().to_string()));
    scratch(name, &text)
}

/// A file's lines without its header (which names its inputs).
fn body(text: &str) -> &str {
    text.split_once("*)\n").or_else(|| text.split_once("-->\n")).map_or(text, |(_, b)| b)
}

#[test]
fn a_ready_supervisor_gives_the_synthesised_ones_controllers_and_a_wrong_one_is_refused() {
    let (_, out, _) = example();
    let given = Project::load(&with_supervisor(&out.full.supervisor, "super.gen")).unwrap();
    let again = hybrid(&given).unwrap();
    assert_eq!(again.report.text(), out.report.text());
    for ((n, a), (m, b)) in again.files.iter().zip(&out.files) {
        assert_eq!((n, body(a)), (m, body(b)));
    }

    // Without the transitions of one uncontrollable event the supervisor refuses what the net does.
    let mut wrong = out.full.supervisor.clone();
    let f2 = wrong.event_id("f2").unwrap();
    wrong.transitions.retain(|t| t.event != f2);
    let err = Project::load(&with_supervisor(&wrong, "wrong.gen")).unwrap_err().to_string();
    assert!(err.contains("wrong.gen: supervisor 'wrong': not controllable") && err.contains("'f2'"), "{err}");

    // Specifications and a supervisor together: which one is meant is not guessed.
    let given = with_supervisor(&out.full.supervisor, "both.gen").with_file_name("both.gen");
    let both = manifest_text().replace(
        "name = \"line\"",
        &format!("name = \"line\"\nsupervisors = [{:?}]", given.display().to_string()),
    );
    let err = Project::load(&scratch("both", &both)).unwrap_err();
    assert!(err.to_string().contains("1 specification file(s) and 1 supervisor file(s) given"), "{err}");
}
