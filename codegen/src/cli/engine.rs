//! `codegen synth --engine`: which engine synthesises (explicit states, BDDs, or chosen by size), and
//! the report of a symbolic supervisor too large to list as an automaton.

use std::io::Write;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;

use codegen::model::Automaton;
use codegen::symbolic::{self, Check, SymbolicSupervisor};
use num_bigint::BigUint;
use serde_json::json;

use super::Error;

/// The engine `--engine` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Engine {
    /// Explicit states (products built state by state).
    Explicit,
    /// Binary decision diagrams.
    Symbolic,
    /// Symbolic when the product of the automata's state counts reaches 2^24, explicit below.
    Auto,
}

impl Engine {
    /// For monolithic synthesis: whether the symbolic engine runs on `automata`.
    pub fn symbolic_for(self, automata: &[Automaton]) -> bool {
        match self {
            Engine::Explicit => false,
            Engine::Symbolic => true,
            Engine::Auto => symbolic::prefers_symbolic(automata),
        }
    }

    /// For modular synthesis: the symbolic conflict check, if this engine uses one (`auto`: only on
    /// supervisor products from 2^24 states).
    pub fn conflict_check(self) -> Option<Arc<Check>> {
        (self != Engine::Explicit).then(|| Arc::new(Check { auto: self == Engine::Auto, ..Check::default() }))
    }
}

/// Says on stderr which engine ran.
pub fn say(what: &str, symbolic: bool) {
    eprintln!("engine: {what} ran {}", if symbolic { "symbolic (BDD)" } else { "explicit" });
}

/// Says on stderr which engine the conflict check ran on; true for the symbolic one.
pub fn say_conflict_check(check: Option<&Arc<Check>>) -> bool {
    let symbolic = check.is_some_and(|c| c.ran.load(Ordering::Relaxed));
    say("the conflict check", symbolic);
    symbolic
}

/// A count as JSON: a number while it fits in 64 bits, else its decimal string.
fn count(n: &BigUint) -> serde_json::Value {
    u64::try_from(n).map_or_else(|_| json!(n.to_string()), |v| json!(v))
}

/// Prints a symbolic supervisor that was not listed (more states than the explicit limit): its exact
/// counts as a table or as the `--json` of `codegen synth` (schema `schema`), with `explicit: false`.
pub fn report_counts(name: &str, s: &SymbolicSupervisor, json: bool, schema: u32) -> Result<ExitCode, Error> {
    let mut out = std::io::stdout().lock();
    if json {
        let value = json!({
            "schema": schema,
            "name": name,
            "engine": "symbolic",
            "supervisors": [{
                "name": s.name,
                "specs": s.specs,
                "plants": s.plants,
                "states": count(&s.states),
                "transitions": count(&s.transitions),
                "explicit": false,
                "bdd_nodes": s.nodes,
            }],
            "nonconflicting": true,
            "merged": [],
            "total_states": count(&s.states),
            "total_transitions": count(&s.transitions),
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&value)?)?;
    } else {
        writeln!(out, "supervisor  states  transitions  BDD nodes")?;
        writeln!(out, "{}  {}  {}  {}", s.name, s.states, s.transitions, s.nodes)?;
        writeln!(out, "(more than {} states: counts only, no automaton)", symbolic::EXPLICIT_LIMIT)?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}
