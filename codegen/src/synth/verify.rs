//! Verifying a supervisor: the controllability and nonblocking checks, each with a shortest
//! counterexample trace.

use crate::model::{Automaton, EventId, EventTable};

use super::product::{tuple_name, Exploration, Options};
use super::reverse::Reverse;
use super::trim::coaccessible_mask;
use super::{Config, Inputs, SynthError};
use crate::model::Dfa;

/// The supervisor disables an uncontrollable event the plant can generate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Uncontrollable {
    /// Shortest string of the closed loop leading to the offending state.
    pub trace: Vec<String>,
    /// The closed-loop state: the tuple of plant states and the supervisor state.
    pub state: String,
    /// The uncontrollable event the plant enables and the supervisor refuses.
    pub event: String,
}

/// A reachable state of a product from which no marked state can be reached.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Blocking {
    /// Shortest string leading to the blocking state.
    pub trace: Vec<String>,
    /// The product state: the tuple of component states.
    pub state: String,
}

fn names(table: &EventTable, events: &[u32]) -> Vec<String> {
    events.iter().map(|&e| table.name(EventId::from_u32(e)).to_owned()).collect()
}

/// Checks that `supervisor` is controllable with respect to the plant `‖ plants`: in every reachable
/// state of plant ‖ supervisor, each uncontrollable event the plant enables is enabled by the supervisor
/// too (or is outside its alphabet). Returns the first violation in breadth-first order.
pub fn controllability(
    plants: &[Automaton],
    supervisor: &Automaton,
    cfg: &Config,
) -> Result<Option<Uncontrollable>, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(std::iter::once(supervisor)))?;
    let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
    let x = Exploration::run(
        &dfas,
        &inputs.controllable,
        Options { plants: plants.len(), parents: true },
        cfg,
        "closed loop",
    )?;
    let sources: Vec<&Automaton> = plants.iter().chain(std::iter::once(supervisor)).collect();
    Ok(x.bad.first().map(|&(s, e)| Uncontrollable {
        trace: names(&inputs.table, &x.trace(s)),
        state: tuple_name(&x, &sources, s),
        event: inputs.table.name(EventId::from_u32(e)).to_owned(),
    }))
}

/// The first (breadth-first) reachable state of the product of `dfas` that cannot reach a marked state.
pub(crate) fn first_blocking(
    dfas: &[&Dfa],
    inputs: &Inputs,
    cfg: &Config,
    what: &str,
) -> Result<(Exploration, Option<u32>), SynthError> {
    let x = Exploration::run(
        dfas,
        &inputs.controllable,
        Options { plants: dfas.len(), parents: true },
        cfg,
        what,
    )?;
    let d = &x.dfa;
    let co = coaccessible_mask(d, &Reverse::new(d), &vec![true; d.state_count()]);
    let first = co.iter().position(|&c| !c).map(|s| s as u32);
    Ok((x, first))
}

/// Checks that the product of `automata` is nonblocking (every reachable state can reach a marked
/// state). For a set of supervisors this is the conflict check: they are nonconflicting exactly when it
/// passes. Returns the first blocking state in breadth-first order.
pub fn nonblocking(automata: &[Automaton], cfg: &Config) -> Result<Option<Blocking>, SynthError> {
    let inputs = Inputs::new(automata.iter())?;
    let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
    let (x, first) = first_blocking(&dfas, &inputs, cfg, "product")?;
    let sources: Vec<&Automaton> = automata.iter().collect();
    Ok(first
        .map(|s| Blocking { trace: names(&inputs.table, &x.trace(s)), state: tuple_name(&x, &sources, s) }))
}
