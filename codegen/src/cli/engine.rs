//! `codegen synth --engine`: which engine synthesises (explicit states, BDDs, or chosen by size), and
//! the report of a symbolic supervisor too large to list as an automaton.

use std::io::Write;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;

use codegen::model::Automaton;
use codegen::symbolic::{self, Check, Options, Order, SymbolicSupervisor, AUTO_EXPLICIT_STATES};
use codegen::synth::{self, Config, Supervisor, SynthError};
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
    /// Explicit while the product (monolithic, or the supervisors' product of the conflict check) stays
    /// below a million states, symbolic beyond.
    Auto,
}

/// The variable order `--bdd-order` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BddOrder {
    /// Components sharing events placed together (Cuthill–McKee on the event graph).
    EventGraph,
    /// Plants then specifications, as given.
    Given,
}

impl BddOrder {
    /// The symbolic engine's options with this order.
    pub fn options(self) -> Options {
        let order = match self {
            BddOrder::EventGraph => Order::EventGraph,
            BddOrder::Given => Order::Given,
        };
        Options { order, ..Options::default() }
    }
}

/// The monolithic supervisor as the engine that ran gives it.
pub enum Monolithic {
    /// From the explicit engine.
    Explicit(Supervisor),
    /// From the symbolic engine (listed as an automaton when small enough).
    Symbolic(SymbolicSupervisor),
}

impl Engine {
    /// Monolithic synthesis on this engine. `auto` runs the explicit engine until its product passes
    /// [`AUTO_EXPLICIT_STATES`], then the symbolic one (with `options`). Says on stderr which ran.
    pub fn monolithic(
        self,
        plants: &[Automaton],
        specs: &[Automaton],
        cfg: &Config,
        options: &Options,
    ) -> Result<Monolithic, Error> {
        let explicit = match self {
            Engine::Symbolic => false,
            Engine::Explicit => true,
            Engine::Auto => {
                let capped = Config { state_limit: cfg.state_limit.min(AUTO_EXPLICIT_STATES), ..cfg.clone() };
                match synth::monolithic(plants, specs, &capped) {
                    Err(SynthError::StateLimit { .. }) if cfg.state_limit > AUTO_EXPLICIT_STATES => {
                        eprintln!("engine: the explicit product passed {AUTO_EXPLICIT_STATES} states");
                        false
                    }
                    r => {
                        say("monolithic synthesis", false);
                        return Ok(Monolithic::Explicit(r?));
                    }
                }
            }
        };
        say("monolithic synthesis", !explicit);
        Ok(if explicit {
            Monolithic::Explicit(synth::monolithic(plants, specs, cfg)?)
        } else {
            let r = symbolic::monolithic(plants, specs, cfg, options)?;
            if r.states == BigUint::ZERO {
                // No supervisor exists: the explicit engine says so with a shortest uncontrollable trace,
                // when the product is small enough for it to build.
                let capped = Config { state_limit: cfg.state_limit.min(AUTO_EXPLICIT_STATES), ..cfg.clone() };
                return match synth::monolithic(plants, specs, &capped) {
                    Err(verdict @ SynthError::NoSupervisor(_)) => Err(verdict.into()),
                    _ => Err(format!(
                        "no supervisor exists for {}: the symbolic engine found no state of the supervised \
                         plant that is controllable and nonblocking (the product is too large for the \
                         explicit engine to give a shortest trace)",
                        r.name
                    )
                    .into()),
                };
            }
            eprintln!(
                "engine: the supervisor's BDD has {} nodes, the largest BDD {} nodes",
                r.nodes, r.peak_nodes
            );
            Monolithic::Symbolic(r)
        })
    }

    /// For modular synthesis: the symbolic conflict check, if this engine uses one (`auto`: only on
    /// supervisor products the explicit check stopped at [`AUTO_EXPLICIT_STATES`]).
    pub fn conflict_check(self, options: Options) -> Option<Arc<Check>> {
        let explicit_states = if self == Engine::Auto { AUTO_EXPLICIT_STATES } else { 0 };
        (self != Engine::Explicit)
            .then(|| Arc::new(Check { options, explicit_states, ran: Default::default() }))
    }
}

/// Says on stderr which engine ran.
fn say(what: &str, symbolic: bool) {
    eprintln!("engine: {what} ran {}", if symbolic { "symbolic (BDD)" } else { "explicit" });
}

/// Says on stderr which engine the conflict check ran on; true for the symbolic one.
pub fn say_conflict_check(check: Option<&Arc<Check>>) -> bool {
    let symbolic = check.is_some_and(|c| c.ran.load(Ordering::Relaxed));
    say("the conflict check", symbolic);
    symbolic
}

/// A count as JSON: a number while it fits in 64 bits, else its decimal string.
pub fn count(n: &BigUint) -> serde_json::Value {
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
