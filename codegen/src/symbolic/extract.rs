//! The explicit automaton of a symbolic supervisor, when it is small enough to list: a breadth-first
//! walk of the product from the initial tuple, each step computed on the components and kept when the
//! BDD holds its target — so pack, emit and plc run on the symbolic engine's result as on the explicit
//! one's.

use biodivine_lib_bdd::Bdd;

use super::encoding::Space;
use crate::formats::hash::FastMap;
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
    let n = dfas.len();
    let alphabet: Vec<u32> = space.events.iter().map(|e| e.event).collect();
    let mut builder = DfaBuilder::new(alphabet);
    // The tuples in order of discovery, flat (n per state), and the number of each.
    let mut tuples: Vec<u32> = Vec::new();
    let mut index: FastMap<Box<[u32]>, u32> = FastMap::default();
    let start: Option<Vec<u32>> = dfas.iter().map(|d| d.initial()).collect();
    if let Some(start) = start.filter(|t| set.eval_in(&space.valuation(t))) {
        index.insert(start.clone().into_boxed_slice(), 0);
        tuples.extend(start);
    }
    let mut here = vec![0u32; n];
    let mut at = 0;
    while at * n < tuples.len() {
        here.copy_from_slice(&tuples[at * n..(at + 1) * n]);
        let mut valuation = space.valuation(&here);
        let mut next = here.clone();
        builder.start_state(dfas.iter().zip(&here).all(|(d, &s)| d.is_marked(s)));
        for e in &space.events {
            let moved =
                e.parts.iter().all(|&(c, _)| dfas[c].step(here[c], e.event).map(|t| next[c] = t).is_some());
            if moved {
                e.parts.iter().for_each(|&(c, _)| space.set_state(&mut valuation, c, next[c]));
                if set.eval_in(&valuation) {
                    let id = match index.get(&next[..]) {
                        Some(&id) => id,
                        None => {
                            let id = (tuples.len() / n) as u32;
                            index.insert(next.clone().into_boxed_slice(), id);
                            tuples.extend_from_slice(&next);
                            id
                        }
                    };
                    builder.push(e.event, id);
                }
            }
            for &(c, _) in &e.parts {
                next[c] = here[c];
                space.set_state(&mut valuation, c, here[c]);
            }
        }
        at += 1;
    }
    let dfa = builder.finish(Some(0));
    dfa.to_automaton(name, Kind::Supervisor, table, |q| {
        name_of_tuple(sources, |c| tuples[q as usize * n + c])
    })
}
