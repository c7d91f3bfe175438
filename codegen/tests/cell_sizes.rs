//! Golden sizes: the manufacturing cell read through `read_path` gives the paper's published figures.

use std::path::{Path, PathBuf};

use codegen::formats::read_path;

fn cell(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/cell").join(rel)
}

/// (states, transitions, events, controllable, marked) of the one automaton in `rel`.
fn sizes(rel: &str) -> (usize, usize, usize, usize, usize) {
    let automata = read_path(&cell(rel)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(automata.len(), 1);
    let a = &automata[0];
    (a.states.len(), a.transitions.len(), a.events.len(), a.controllable_count(), a.marked_count())
}

#[test]
fn published_supervisors_have_the_published_sizes() {
    for (file, states, transitions) in [
        ("published/S1.xmd", 4, 10),
        ("published/S2_6.xmd", 121, 360),
        ("published/S3.xmd", 33, 112),
        ("published/S4.xmd", 33, 112),
        ("published/S5.xmd", 30, 74),
        ("published/S7.xmd", 12, 29),
    ] {
        let (s, t, ..) = sizes(file);
        assert_eq!((s, t), (states, transitions), "{file}");
    }
}

#[test]
fn plants_and_specs_read_with_their_flags() {
    // G1: conveyor, two states, both events controllable, initial state marked.
    assert_eq!(sizes("plants/G1.xmd"), (2, 2, 2, 2, 1));
    assert_eq!(sizes("specs/E5.xmd").0, 4);
    assert_eq!(sizes("specs/E5.xmd").1, 14);
}

#[test]
fn the_plants_have_23_events_13_controllable() {
    let mut events = std::collections::BTreeMap::new();
    for g in ["G1", "G2", "G3", "G4"] {
        let a = read_path(&cell(&format!("plants/{g}.xmd"))).unwrap().remove(0);
        assert_eq!(a.name, g);
        for e in a.events {
            events.insert(e.name, e.controllable);
        }
    }
    assert_eq!(events.len(), 23);
    assert_eq!(events.values().filter(|&&c| c).count(), 13);
}
