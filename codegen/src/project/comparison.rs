//! The paper's columns for the other two architectures of the same problem: modular and monolithic.

use crate::model::Automaton;
use crate::pack::paper::Columns;
use crate::pack::report::Comparison;
use crate::synth::{modular, monolithic, Config};

/// Synthesises the modular (one supervisor per specification against the whole plant, conflicting ones
/// merged) and monolithic supervisors of `plants` and `specs` and counts them over `events` events. A
/// synthesis that fails (e.g. on `cfg`'s state limit) is kept as a missing row with its error.
pub fn modular_and_monolithic(
    plants: &[Automaton],
    specs: &[Automaton],
    events: usize,
    cfg: &Config,
) -> Vec<Comparison> {
    let modular = modular(plants, specs, cfg)
        .map(|r| Columns::of(r.supervisors.iter().map(|s| &s.automaton), events))
        .map_err(|e| e.to_string());
    let monolithic = monolithic(plants, specs, cfg)
        .map(|s| Columns::of([&s.automaton], events))
        .map_err(|e| e.to_string());
    vec![
        Comparison { approach: "modular".to_owned(), columns: modular },
        Comparison { approach: "monolithic".to_owned(), columns: monolithic },
    ]
}
