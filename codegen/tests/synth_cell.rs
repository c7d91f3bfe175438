//! Golden tests: the manufacturing cell's local modular supervisors come out as published (state and
//! transition counts of the paper, language-equal to the published files), E2 and E6 are found conflicting
//! and merged, and the monolithic supervisor has the published size.

use std::path::{Path, PathBuf};

use codegen::formats::read_path;
use codegen::model::Automaton;
use codegen::synth::{self, language, Config};

fn cell(dir: &str, name: &str) -> Automaton {
    let path: PathBuf =
        [env!("CARGO_MANIFEST_DIR"), "..", "examples", "cell", dir, &format!("{name}.xmd")].iter().collect();
    read_path(Path::new(&path)).unwrap().remove(0)
}

fn plants() -> Vec<Automaton> {
    ["G1", "G2", "G3", "G4"].iter().map(|n| cell("plants", n)).collect()
}

fn specs() -> Vec<Automaton> {
    ["E1", "E2", "E3", "E4", "E5", "E6", "E7"].iter().map(|n| cell("specs", n)).collect()
}

#[test]
fn local_modular_supervisors_are_the_published_ones() {
    let r = synth::local_modular(&plants(), &specs(), &Config::default()).unwrap();
    assert!(r.nonconflicting);
    assert_eq!(r.merged, [["E2", "E6"]]);
    let sizes: Vec<(&str, usize, usize)> = r
        .supervisors
        .iter()
        .map(|s| (s.automaton.name.as_str(), s.automaton.states.len(), s.automaton.transitions.len()))
        .collect();
    assert_eq!(
        sizes,
        [("S1", 4, 10), ("S2_6", 121, 360), ("S3", 33, 112), ("S4", 33, 112), ("S5", 30, 74), ("S7", 12, 29)]
    );
    assert_eq!((r.total_states(), r.total_transitions()), (233, 697));
    for s in &r.supervisors {
        let published = cell("published", &s.automaton.name);
        assert_eq!(language::equal(&s.automaton, &published).unwrap(), None, "{}", s.automaton.name);
    }
}

#[test]
fn reduced_supervisors_keep_the_closed_loop() {
    let cfg = Config::default();
    let plants = plants();
    let r = synth::local_modular(&plants, &specs(), &cfg).unwrap();
    for s in &r.supervisors {
        let local: Vec<Automaton> = plants.iter().filter(|p| s.plants.contains(&p.name)).cloned().collect();
        let reduced = synth::reduce(&local, &s.automaton, &cfg).unwrap();
        assert!(reduced.states.len() < s.automaton.states.len(), "{}", s.automaton.name);
        let closed = |sup: &Automaton| {
            let mut parts = local.clone();
            parts.push(sup.clone());
            synth::product(&parts, &cfg).unwrap()
        };
        assert_eq!(
            language::equal(&closed(&reduced), &closed(&s.automaton)).unwrap(),
            None,
            "{}",
            s.automaton.name
        );
    }
}

#[test]
fn monolithic_supervisor_has_the_published_size() {
    let s = synth::monolithic(&plants(), &specs(), &Config::default()).unwrap();
    assert_eq!((s.automaton.states.len(), s.automaton.transitions.len()), (3420, 11808));
}
