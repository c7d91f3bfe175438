//! The event-based program's ladder (`--encoding bits --avalanche aeem`) of the seed `TEST.ADS`,
//! against the hybrid paper's Fig. 13 (Uzam & Gelen 2013, §2.4.4): 20 rungs — the initialisation, a
//! set rung per memory bit, the 13 transitions, a reset rung per bit — each bit reset by the
//! transition rungs of its event; the rungs scanned as a PLC runs Ladder Diagram take exactly the
//! model's transition; the ST sections are the rungs' statements; the XML carries them as `<LD>`.

use std::collections::BTreeSet;
use std::path::Path;

use codegen::model::Automaton;
use codegen::pack::PackSet;
use codegen::plc::{generate, Avalanche, Encoding, Output, PlcOptions};
use codegen::provenance::Provenance;
use codegen::scan::ld::{CoilKind, Element, Rung};
use codegen::scan::Stmt;

/// The paper's transition rungs that reset each memory bit (events 1, 2, 3 are its a, b, c).
const PAPER: [(&str, &[usize]); 3] = [("1", &[5, 8, 12, 15]), ("2", &[6, 7, 17]), ("3", &[9, 11])];

fn model() -> Automaton {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/TEST.ADS");
    codegen::formats::read_path(&path).unwrap().remove(0)
}

/// The seed's program: every event an input edge (the paper reads every event from a signal), or
/// the file's controllability (odd labels controllable).
fn program(all_inputs: bool, avalanche: Avalanche) -> Output {
    let mut a = model();
    if all_inputs {
        for e in &mut a.events {
            e.controllable = false;
        }
    }
    let set = PackSet::new(vec![a], vec![]).unwrap();
    let opts =
        PlcOptions { name: "test".into(), encoding: Encoding::Bits, avalanche, ..PlcOptions::default() };
    generate(&set, &opts, &Provenance::default()).unwrap()
}

/// The variables a rung's contacts read, left to right.
fn contacts(e: &Element) -> Vec<&str> {
    match e {
        Element::Contact { variable, .. } => vec![variable.as_str()],
        Element::Series(es) | Element::Parallel(es) => es.iter().flat_map(contacts).collect(),
    }
}

fn drives(r: &Rung, variable: &str, kind: CoilKind) -> bool {
    r.coils.iter().any(|c| c.variable == variable && c.kind == kind)
}

/// Per event (by name), its memory bit: the variable set by the rung reading the event's flag.
fn bits(out: &Output) -> Vec<(String, String)> {
    out.program
        .rungs
        .iter()
        .filter(|r| r.coils.len() == 1 && r.coils[0].kind == CoilKind::Set)
        .map(|r| {
            let flag = contacts(&r.condition)[0];
            (flag.trim_start_matches("ev_").to_owned(), r.coils[0].variable.clone())
        })
        .collect()
}

/// 1-based numbers of the rungs after the first (the initialisation) with contacts that reset `bit`:
/// the transitions that use it.
fn resets(rungs: &[Rung], bit: &str) -> Vec<usize> {
    let used = |r: &Rung| r.condition.contacts() > 0 && drives(r, bit, CoilKind::Reset);
    (2..=rungs.len()).filter(|&n| used(&rungs[n - 1])).collect()
}

/// Scans `rungs` once as a PLC runs Ladder Diagram: top to bottom, each rung's condition on the
/// variables as they are, then its coils.
fn scan(rungs: &[Rung], vars: &mut BTreeSet<String>) {
    for r in rungs {
        if r.condition.conducts(&|v: &str| vars.contains(v)) {
            for c in &r.coils {
                match c.kind {
                    CoilKind::Set => vars.insert(c.variable.clone()),
                    CoilKind::Reset => vars.remove(&c.variable),
                    k => panic!("no {k:?} coil in the seed's ladder"),
                };
            }
        }
    }
}

/// From state `s`, event `label` for one scan of the rungs after the first: the state bits left on.
fn step(rungs: &[Rung], s: usize, label: &str) -> Vec<usize> {
    let mut vars: BTreeSet<String> = [format!("X_TEST_{s}"), format!("ev_{label}")].into();
    scan(&rungs[1..], &mut vars);
    assert!(!vars.iter().any(|v| v.starts_with("m_")), "every memory bit clear at the end: {vars:?}");
    (0..5).filter(|q| vars.contains(&format!("X_TEST_{q}"))).collect()
}

// See: issue 36 (TEST.ADS's ladder as Fig. 13).
#[test]
fn the_seeds_ladder_has_fig_13s_twenty_rungs_and_its_bits_reset_per_source_state_block() {
    let out = program(true, Avalanche::Aeem);
    let rungs = &out.program.rungs;
    assert_eq!(rungs.len(), 20);
    // Rung 1: the initial state set, the others and every bit reset, on the first scan or reset.
    assert_eq!(contacts(&rungs[0].condition), ["ready", "reset"]);
    assert!(drives(&rungs[0], "X_TEST_0", CoilKind::Set));
    assert!((1..5).all(|s| drives(&rungs[0], &format!("X_TEST_{s}"), CoilKind::Reset)));
    // Rungs 2, 3, 4 set M1, M2, M3 on events 1, 2, 3 (a, b, c); rungs 18, 19, 20 clear them.
    let bits = bits(&out);
    let events: Vec<&str> = bits.iter().map(|(e, _)| e.as_str()).collect();
    assert_eq!(events, ["1", "2", "3"]);
    assert_eq!(bits.iter().map(|(_, b)| b.clone()).collect::<Vec<_>>(), out.program.memory_bits);
    for (i, (_, bit)) in bits.iter().enumerate() {
        let end = &rungs[17 + i];
        assert!(end.condition.contacts() == 0 && drives(end, bit, CoilKind::Reset), "rung {}", 18 + i);
    }
    // Rungs 5..17: one per transition.
    assert_eq!(rungs[4..17].iter().filter(|r| contacts(&r.condition)[0].starts_with("X_TEST_")).count(), 13);

    // Where each bit is reset: ours, and the paper's.
    let ours: Vec<Vec<usize>> = bits.iter().map(|(_, b)| resets(rungs, b)).collect();
    assert_eq!(ours, [vec![5, 7, 11, 13], vec![6, 8, 16], vec![9, 12]]);
    // The mapping: both ladders group the transitions by source state, ascending, so each state's
    // rungs are the same block of numbers (state 0: 5-6, 1: 7-10, 2: 11-12, 3: 13-15, 4: 16-17) and
    // in each block the same bits are reset; within a block ours go by event, the paper's by target
    // state (3 -6-> 2 before 3 -1-> 2), so the numbers inside a block may differ.
    let a = model();
    let mut first = 5;
    for s in 0..5 {
        let n = a.transitions.iter().filter(|t| t.source.index() == s).count();
        let block = first..first + n;
        let of = format!("X_TEST_{s}");
        let ours_here: Vec<usize> =
            (5..=17).filter(|&k| contacts(&rungs[k - 1].condition)[0] == of).collect();
        assert_eq!(ours_here, block.clone().collect::<Vec<_>>(), "state {s}'s block");
        for ((event, paper), (_, bit)) in PAPER.iter().zip(&bits) {
            let mine = ours[bits.iter().position(|(_, b)| b == bit).unwrap()]
                .iter()
                .filter(|k| block.contains(k))
                .count();
            let theirs = paper.iter().filter(|k| block.contains(k)).count();
            assert_eq!(mine, theirs, "event {event} in state {s}'s block");
        }
        first += n;
    }
    assert_eq!(first, 18);
}

// See: issue 36 (the ladder is the program the ST runs).
#[test]
fn the_ladders_rungs_are_the_st_sections_and_take_one_step_per_event() {
    let out = program(true, Avalanche::Aeem);
    let rungs = &out.program.rungs;
    // The ST of the seed structure after the initialisation is the rungs' statements, in order.
    let st: Vec<Stmt> = out
        .program
        .fb
        .sections
        .iter()
        .filter(|s| ["aeem-set", "transitions", "aeem-reset"].contains(&s.label))
        .flat_map(|s| s.stmts.clone())
        .collect();
    let from_rungs: Vec<Stmt> = rungs[1..].iter().flat_map(Rung::statements).collect();
    assert_eq!(st, from_rungs);
    // Every event from every state takes exactly the model's transition (or none), in one scan.
    let a = model();
    for s in 0..5 {
        for e in &a.events {
            let want = a
                .transitions
                .iter()
                .find(|t| t.source.index() == s && a.events[t.event.index()].name == e.name)
                .map_or(s, |t| t.target.index());
            assert_eq!(step(rungs, s, &e.name), [want], "state {s}, event {}", e.name);
        }
    }
    // Without the transition rungs' resets (AEEM's second step) one edge of event 1 runs on from state 0
    // to 1, 2, 3 and back to 2 in the same scan: the avalanche the bits remove.
    let bare: Vec<Rung> = rungs
        .iter()
        .map(|r| {
            let mut r = r.clone();
            if r.condition.contacts() > 0 {
                r.coils.retain(|c| !c.variable.starts_with("m_") || c.kind == CoilKind::Set);
            }
            r
        })
        .collect();
    assert_eq!(step(&bare, 0, "1"), [2]);
    assert_eq!(step(rungs, 0, "1"), [1]);
}

// See: issue 36 (the `<LD>` body is written for this form only).
#[test]
fn the_xml_carries_the_ladder_for_bits_with_aeem_only() {
    let xml = |out: &Output| out.files.iter().find(|(n, _)| n.ends_with(".xml")).unwrap().1.clone();
    let aeem = xml(&program(true, Avalanche::Aeem));
    let fb =
        &aeem[aeem.find("<pou name=\"test_sct\"").unwrap()..aeem.find("<pou name=\"test_main\"").unwrap()];
    assert!(fb.contains("<body><ST>") && fb.contains("<body><LD>"), "ST and LD bodies");
    assert_eq!(fb.matches("<leftPowerRail").count(), 20);
    let reset_coils: usize = program(true, Avalanche::Aeem)
        .program
        .rungs
        .iter()
        .map(|r| r.coils.iter().filter(|c| c.kind == CoilKind::Reset).count())
        .sum();
    assert_eq!(fb.matches("storage=\"reset\"").count(), reset_coils);
    for other in [Avalanche::Auto, Avalanche::None] {
        assert!(!xml(&program(true, other)).contains("<LD>"), "{}", other.name());
    }
    // With the file's controllability the block applies the uncontrollable events (2, 4, 6) before its
    // choice and the controllable ones (1, 3, 5) after it: still 20 rungs, in two passes.
    let out = program(false, Avalanche::Aeem);
    let rungs = &out.program.rungs;
    assert_eq!(rungs.len(), 20);
    let bits = bits(&out);
    let events: Vec<&str> = bits.iter().map(|(e, _)| e.as_str()).collect();
    assert_eq!(events, ["2", "1", "3"]);
    let ours: Vec<Vec<usize>> = bits.iter().map(|(_, b)| resets(rungs, b)).collect();
    assert_eq!(ours, [vec![3, 4, 7], vec![11, 12, 15, 17], vec![13, 16]]);
}
