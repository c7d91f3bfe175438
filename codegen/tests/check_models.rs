//! The implementation checks on the reference models, read from their files.

use std::path::Path;

use codegen::formats::read_path;
use codegen::problems::{run, Problem};

fn read(rel: &str) -> codegen::model::Automaton {
    read_path(&Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap_or_else(|e| panic!("{e}")).remove(0)
}

#[test]
fn seed_avalanche_events_are_1_2_3() {
    let found = run(&read("tests/data/TEST.ADS"), &[Problem::Avalanche]);
    let events: Vec<_> = found.iter().map(|f| f.events.join(",")).collect();
    assert_eq!(events, ["1", "2", "3"]);
}

#[test]
fn livelock_example_has_choice_problems_at_states_1_and_3() {
    let found = run(&read("../examples/livelock/livelock.xmd"), &Problem::ALL);
    let choice: Vec<_> = found
        .iter()
        .filter(|f| f.problem == Problem::Choice)
        .map(|f| (f.state.as_str(), f.trace.len()))
        .collect();
    assert_eq!(choice, [("1", 0), ("3", 1)]);
    assert!(found
        .iter()
        .all(|f| f.problem != Problem::Simultaneity && f.problem != Problem::InexactSynchronisation));
}
