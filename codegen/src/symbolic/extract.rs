//! The explicit automaton of a symbolic supervisor, when it is small enough to list: a breadth-first
//! walk of the product from the initial tuple, each step computed on the components and kept when the
//! BDD holds its target — so pack, emit and plc run on the symbolic engine's result as on the explicit
//! one's.

use std::collections::HashMap;

use biodivine_lib_bdd::Bdd;

use super::encoding::Space;
use crate::model::{Automaton, Dfa, DfaBuilder, EventTable, Kind};
use crate::synth::name_of_tuple;

/// The automaton of the states of `set` (reachable from the initial tuple within it) of the product of
/// `sources` (`dfas` are their conversions over `table`), named `name`; states are named by the tuple of
/// component state names, as the explicit engine names them.
pub(crate) fn to_automaton(
    space: &Space,
    set: &Bdd,
    dfas: &[&Dfa],
    sources: &[&Automaton],
    table: &EventTable,
    name: &str,
) -> Automaton {
    let alphabet: Vec<u32> = space.events.iter().map(|e| e.event).collect();
    let mut builder = DfaBuilder::new(alphabet);
    let mut tuples: Vec<Vec<u32>> = Vec::new();
    let mut index: HashMap<Vec<u32>, u32> = HashMap::new();
    let start: Option<Vec<u32>> = dfas.iter().map(|d| d.initial()).collect();
    if let Some(start) = start.filter(|t| space.contains(set, t)) {
        index.insert(start.clone(), 0);
        tuples.push(start);
    }
    let mut at = 0;
    while at < tuples.len() {
        let here = tuples[at].clone();
        builder.start_state(dfas.iter().zip(&here).all(|(d, &s)| d.is_marked(s)));
        for e in &space.events {
            let mut next = here.clone();
            let moved = e.parts.iter().all(|&(c, _)| dfas[c].step(here[c], e.event).map(|t| next[c] = t).is_some());
            if !moved || !space.contains(set, &next) {
                continue;
            }
            let id = *index.entry(next.clone()).or_insert_with(|| {
                tuples.push(next);
                (tuples.len() - 1) as u32
            });
            builder.push(e.event, id);
        }
        at += 1;
    }
    let dfa = builder.finish(Some(0));
    dfa.to_automaton(name, Kind::Supervisor, table, |q| name_of_tuple(sources, |c| tuples[q as usize][c]))
}
