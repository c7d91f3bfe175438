//! The hybrid example's two controllers run closed loop: their rungs scanned as a PLC runs Ladder
//! Diagram (top to bottom, coils as they are reached, `TON` on the scan clock) against a virtual plant
//! of the line's devices, judged against the net's reachability graph and the specification.

use std::collections::BTreeMap;
use std::path::Path;

use super::*;
use crate::model::StateId;
use crate::synth::{language, product};

const CYCLE_MS: u64 = 10;

fn example() -> (Manifest, Output, Automaton) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/hybrid");
    let manifest = Manifest::load(&root.join("hybrid.toml")).unwrap();
    let out = generate(&manifest, &Config::default(), CYCLE_MS as u32).unwrap();
    let spec = crate::formats::read_path(&root.join("specs/buffer.gen")).unwrap().remove(0);
    (manifest, out, spec)
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
fn run(out: &Output, side: &Side, spec: &Automaton, seed: u64, scans: u64) -> Run {
    let c = &side.controller;
    let mut plc = Scan { rungs: &c.rungs, vars: BTreeMap::new(), started: BTreeMap::new(), now: 0 };
    let places: Vec<String> = out.net.net.places.iter().map(|p| format!("P_{}", p.id)).collect();
    let states: Vec<&String> = c.bools.iter().filter(|(v, _)| v.starts_with("A_")).map(|(v, _)| v).collect();
    let mut rng = seed;
    let mut next = move || {
        rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (rng >> 33) as u32
    };
    let (mut g, mut e, mut x) =
        (out.plant.initial.unwrap(), spec.initial.unwrap(), side.supervisor.initial.unwrap());
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
            let fired: Vec<usize> = (0..out.net.net.transitions.len())
                .filter(|&t| {
                    out.net.net.state_enabled(t, &before)
                        && out.net.net.fire(t, &before).as_deref() == Some(&after[..])
                })
                .collect();
            let [t] = fired[..] else {
                result.violations += 1;
                continue;
            };
            let event = &out.events[t];
            result.trace.push((scan, event.clone()));
            match (step(&out.plant, g, event), step(spec, e, event), step(&side.supervisor, x, event)) {
                (Some(g2), Some(e2), Some(x2)) => (g, e, x) = (g2, e2, x2),
                _ => result.violations += 1,
            }
            if out.plant.states[g.index()].marked && spec.states[e.index()].marked {
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
    let (_, out, spec) = example();
    for seed in [1, 2, 3] {
        let reduced = run(&out, &out.reduced, &spec, seed, 20_000);
        assert_eq!(reduced.violations, 0, "seed {seed}: {reduced:?}");
        assert!(reduced.cycles >= 20, "seed {seed}: {} cycles", reduced.cycles);
        // The full supervisor's controller makes the same moves on the same sensor readings.
        let full = run(&out, &out.full, &spec, seed, 20_000);
        assert_eq!(full, reduced, "seed {seed}");
    }
    // And the closed loops' languages are equal as automata.
    let closed = |s: &Automaton| product(&[out.plant.clone(), s.clone()], &Config::default()).unwrap();
    assert!(language::equal(&closed(&out.full.supervisor), &closed(&out.reduced.supervisor))
        .unwrap()
        .is_none());
}

#[test]
fn a_controller_without_its_inhibitor_arcs_overflows_the_buffer() {
    // The judge can fail: drop the inhibitor contacts (the auto-net's places in the plant's rungs).
    let (_, out, spec) = example();
    let mut side = out.reduced.clone();
    for r in &mut side.controller.rungs {
        if let Element::Series(es) = &mut r.condition {
            es.retain(
                |e| !matches!(e, Element::Contact { variable, negated: true } if variable.starts_with("A_")),
            );
        }
    }
    assert!(run(&out, &side, &spec, 1, 20_000).violations > 0);
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
    let xml = &out.files.iter().find(|(n, _)| n == "line_hybrid.xml").unwrap().1;
    assert!(xml.contains("<body><LD>") && xml.contains("typeName=\"TON\" instanceName=\"T_t2\""));
}

#[test]
fn a_transition_without_an_event_is_named_with_its_line() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/hybrid");
    let text = std::fs::read_to_string(root.join("hybrid.toml")).unwrap().replace("t4 = \"f2\"\n", "");
    let m = Manifest::parse(&root.join("hybrid.toml"), &text).unwrap();
    let err = generate(&m, &Config::default(), 10).unwrap_err().to_string();
    assert!(err.ends_with("hybrid.toml:10: transition 't4' has no event in [hybrid.events]"), "{err}");
    let text =
        std::fs::read_to_string(root.join("hybrid.toml")).unwrap().replace("t4 = \"f2\"", "t9 = \"f2\"");
    let m = Manifest::parse(&root.join("hybrid.toml"), &text).unwrap();
    let err = generate(&m, &Config::default(), 10).unwrap_err().to_string();
    assert!(err.ends_with("hybrid.toml:32: hybrid.events.t9: the net has no such transition"), "{err}");
}

/// The example's manifest with `supervisors = [file]` in place of its specifications.
fn with_supervisor(m: &Manifest, sup: &Automaton, name: &str) -> Manifest {
    let dir = std::env::temp_dir().join(format!("hybrid-given-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    crate::formats::write_path(&file, std::slice::from_ref(sup)).unwrap();
    let text = std::fs::read_to_string(&m.file).unwrap().replace(
        "specs = [\"specs/buffer.gen\"]",
        &format!("supervisors = [{:?}]", file.display().to_string()),
    );
    Manifest::parse(&m.file, &text).unwrap()
}

#[test]
fn a_ready_supervisor_gives_the_synthesised_ones_controllers_and_a_wrong_one_is_refused() {
    let (m, out, _) = example();
    let given = with_supervisor(&m, &out.full.supervisor, "super.gen");
    let again = generate(&given, &Config::default(), CYCLE_MS as u32).unwrap();
    assert_eq!(again.report.text(), out.report.text());
    assert_eq!(again.files, out.files);

    // Without the transitions of one uncontrollable event the supervisor refuses what the net does.
    let mut wrong = out.full.supervisor.clone();
    let f2 = wrong.event_id("f2").unwrap();
    wrong.transitions.retain(|t| t.event != f2);
    let err = generate(&with_supervisor(&m, &wrong, "wrong.gen"), &Config::default(), 10).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("wrong.gen: supervisor 'wrong': not controllable") && text.contains("'f2'"),
        "{text}"
    );

    // Specifications and a supervisor together: which one is meant is not guessed.
    let both = std::fs::read_to_string(&m.file)
        .unwrap()
        .replace("name = \"line\"", "name = \"line\"\nsupervisors = [\"x.gen\"]");
    let err = generate(&Manifest::parse(&m.file, &both).unwrap(), &Config::default(), 10).unwrap_err();
    assert!(err.to_string().contains("1 specification file(s) and 1 supervisor file(s) given"), "{err}");
}
