//! Sequences drawn as Petri nets and verified under the synthesised interlocks (docs/design.md §11; Mušič &
//! Matko 2005).
//!
//! | part | module |
//! |---|---|
//! | the place/transition net (weighted and inhibitor arcs, initial marking) | [`model`] |
//! | the PNML reader | [`pnml`] |
//! | transition conditions Y(t) | [`condition`] |
//! | the interpretation (Y, Z, D) bound to the plant's signals | [`interpretation`](mod@interpretation) |
//! | the IO-reachability graph | [`io_graph`] |
//! | the reachability graph of an event-labelled net, as a plant automaton | [`reachability`] |
//! | what a hybrid controller's controllable transitions wait for, as plant automata | [`arrivals`] |
//! | the safe-net check a PLC program needs, with a firing sequence to a second token | [`safety`] |
//! | Definition 2's verdict, the trace and the diagnosis | [`verdict`] |
//! | the graph in Graphviz | [`dot`] |
//!
//! [`verify`] runs them in order: the net of a manifest's `[net]` section, under the admissible
//! behaviour (plants ‖ supervisors) of the same manifest.

pub mod arrivals;
pub mod condition;
pub mod dot;
mod error;
pub mod interpretation;
pub mod io_graph;
pub mod model;
pub mod pnml;
pub mod reachability;
pub mod safety;
pub mod verdict;

#[cfg(test)]
mod tests;

use std::path::Path;

use serde::Serialize;

pub use error::NetError;
pub use interpretation::Interpretation;
pub use io_graph::{IoGraph, Limits};
pub use model::Net;
pub use pnml::{check_pnml, read_pnml, read_pnml_bytes};
pub use verdict::Verdict;

use crate::config::NetSpec;
use crate::model::{Automaton, Composition, EventTable};
use crate::synth::{Inputs, Reachable};

/// A net verified under supervision: what was built and the verdict.
#[derive(Debug)]
pub struct Verification {
    /// The net with its interpretation.
    pub net: Interpretation,
    /// The events of the admissible behaviour.
    pub table: EventTable,
    /// The admissible behaviour, stepped.
    pub plant: Composition,
    /// Size of the admissible behaviour's reachable product.
    pub admissible: Size,
    /// The IO-reachability graph.
    pub graph: IoGraph,
    /// Definition 2's verdict.
    pub verdict: Verdict,
}

/// States and transitions of an automaton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Size {
    /// States.
    pub states: usize,
    /// Transitions.
    pub transitions: usize,
}

/// What `codegen verify --json` prints.
#[derive(Serialize)]
pub struct Report<'a> {
    /// The verdict, nodes, edges and, for a blocking net, trace, marking and refused actions.
    #[serde(flatten)]
    pub verdict: &'a Verdict,
    /// The admissible behaviour's size.
    pub admissible: Size,
}

/// Reads the net of `spec` (a `[net]` section of the manifest `file`), binds its interpretation to the
/// events of `automata` (plants and supervisors: the admissible behaviour) and judges its IO-reachability
/// graph.
pub fn verify(
    spec: &NetSpec,
    file: &Path,
    automata: &[&Automaton],
    limits: Limits,
) -> Result<Verification, NetError> {
    let (net, inputs) = load(spec, file, automata)?;
    let reachable = Reachable::explore(&inputs.dfas.iter().collect::<Vec<_>>(), limits.state_limit)?;
    let admissible =
        Size { states: reachable.dfa().state_count(), transitions: reachable.dfa().transition_count() };
    let plant = Composition::new(automata, &inputs.table)?;
    let graph = IoGraph::build(&net, &plant, limits)?;
    let verdict = Verdict::judge(&graph, &net, &plant, &inputs.table);
    Ok(Verification { net, table: inputs.table, plant, admissible, graph, verdict })
}

/// Reads the net of `spec` (a `[net]` section of the manifest `file`) and binds its interpretation to the
/// events of `automata` (the plants and supervisors whose signals it reads and sets).
pub fn interpretation(
    spec: &NetSpec,
    file: &Path,
    automata: &[&Automaton],
) -> Result<Interpretation, NetError> {
    Ok(load(spec, file, automata)?.0)
}

fn load(spec: &NetSpec, file: &Path, automata: &[&Automaton]) -> Result<(Interpretation, Inputs), NetError> {
    let pnml = file.parent().unwrap_or(Path::new("")).join(spec.pnml.get_ref());
    let net = read_pnml(&pnml)?;
    let inputs = Inputs::new(automata.iter().copied())?;
    let net = Interpretation::bind(spec, file, net, &inputs.table)?;
    Ok((net, inputs))
}
