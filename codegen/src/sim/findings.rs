//! `check`'s findings ([`crate::problems`]) where they occur: each finding's shortest trace replayed on
//! its scope's automata gives the local state of each, so the page can mark the state on every graph.

use crate::model::{Automaton, Composition, EventTable};
use crate::problems::{run as check, scopes, Problem};
use crate::synth::{product, Config};

/// Products larger than this are not checked here (the page says so): `codegen check` has the limits.
const STATE_LIMIT: usize = 200_000;
/// Most findings kept per scope: the nearest first, as `check` orders them.
const PER_SCOPE: usize = 50;

/// One finding of `check`, located.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Located {
    /// The problem's name (`avalanche`, `choice`, …).
    pub problem: String,
    /// The scope checked: `closed loop`, or a supervisor with its local plant.
    pub scope: String,
    /// The events involved.
    pub events: Vec<String>,
    /// What goes wrong.
    pub detail: String,
    /// Where: `(automaton, local state)` for every automaton of the scope.
    pub at: Vec<(String, String)>,
}

/// Runs every check on the closed loop and on each supervisor with its local plant, and locates the
/// findings; an error (a product over the limit) as text for the page.
pub fn locate(
    plants: &[Automaton],
    supervisors: &[Automaton],
    table: &EventTable,
) -> Result<Vec<Located>, String> {
    let cfg = Config { state_limit: STATE_LIMIT, ..Config::default() };
    let mut out = Vec::new();
    for scope in scopes(plants, supervisors) {
        let members: Vec<Automaton> = scope.members.iter().map(|a| (*a).clone()).collect();
        let automaton = match members.as_slice() {
            [one] => one.clone(),
            many => product(many, &cfg).map_err(|e| format!("{}: {e}", scope.name))?,
        };
        let replay = Composition::new(&scope.members, table).map_err(|e| e.to_string())?;
        for finding in check(&automaton, &Problem::ALL).into_iter().take(PER_SCOPE) {
            let mut state = replay.initial();
            let walked =
                finding.trace.iter().all(|name| table.id(name).is_some_and(|e| replay.step(&mut state, e)));
            let at = if walked {
                (0..replay.len())
                    .map(|i| (replay.name(i).to_owned(), replay.state_name(i, state[i]).to_owned()))
                    .collect()
            } else {
                Vec::new()
            };
            out.push(Located {
                problem: finding.problem.name().to_owned(),
                scope: scope.name.clone(),
                events: finding.events,
                detail: finding.detail,
                at,
            });
        }
    }
    Ok(out)
}
