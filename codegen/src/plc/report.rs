//! What a generated program costs and how it meets each scan-cycle problem: its variables, statements
//! (counted on the syntax tree that is printed), a static bound on the statements one scan executes,
//! the AEEM memory bits, the method per avalanche event, and where the simultaneity check says the fixed
//! order of simultaneous inputs matters.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::model::{EventId, EventTable};
use crate::pack::PackSet;
use crate::problems::{run as check, Problem};
use crate::synth::{product, Config};

use super::guards::Guards;
use super::io::Source;
use super::program::SEED_STRUCTURE;
use super::{PlcError, PlcOptions, Program};
use crate::scan::ir::VarClass;

/// The report (`codegen plc --json`, schema 1).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Report {
    /// Schema version.
    pub schema: u32,
    /// Name of the set.
    pub name: String,
    /// `int` or `bits`.
    pub encoding: &'static str,
    /// The `--avalanche` option.
    pub avalanche_option: &'static str,
    /// Choice policy.
    pub policy: &'static str,
    /// Guard's initial value.
    pub guard: bool,
    /// The task's interval.
    pub cycle_ms: u32,
    /// Files written, by name.
    pub files: Vec<String>,
    /// Variable counts and the I/O map.
    pub variables: Variables,
    /// Statement counts.
    pub statements: Statements,
    /// Most statements one scan executes (function block and program).
    pub bound_per_scan: u64,
    /// The AEEM memory bits.
    pub memory_bits: Vec<String>,
    /// Per automaton and avalanche event, the method.
    pub avalanche: Vec<AvalancheEntry>,
    /// Simultaneous inputs.
    pub simultaneity: Simultaneity,
    /// Choice sites with a cursor (local queue).
    pub choice_sites: usize,
    /// The modules' variables the program keeps and the guards over them (`efa_variables`, `guards`).
    #[serde(flatten)]
    pub guards: GuardsReport,
}

/// The modules' variables a program keeps as integers and each controllable event's guard over them:
/// what both program forms report (empty without variables).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct GuardsReport {
    /// The modules' variables the program keeps as integers (absent without any).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub efa_variables: Vec<String>,
    /// Per controllable event a supervisor holds, its guard over the variables, or `null` where the
    /// supervisors' states are kept (absent without variables).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub guards: Vec<GuardEntry>,
}

impl GuardsReport {
    /// What `g` keeps and decides, events named from `events`, in event id order.
    pub fn new(g: &Guards, events: &EventTable) -> GuardsReport {
        if g.variables.is_empty() {
            return GuardsReport::default();
        }
        let mut guards: Vec<(EventId, Option<String>)> = g
            .guards
            .iter()
            .map(|(e, x)| (*e, Some(x.text(&g.variables))))
            .chain(g.kept.iter().map(|&e| (e, None)))
            .collect();
        guards.sort_by_key(|(e, _)| *e);
        GuardsReport {
            efa_variables: g.variables.iter().map(|v| v.declared.name.clone()).collect(),
            guards: guards
                .into_iter()
                .map(|(e, guard)| GuardEntry { event: events.name(e).to_owned(), guard })
                .collect(),
        }
    }

    /// The report's lines: the variables, then each event's guard.
    pub fn text(&self) -> String {
        let mut out = String::new();
        if !self.efa_variables.is_empty() {
            out += &format!(
                "variables of the modules: {} (INT, updated by their events' actions)\n",
                self.efa_variables.join(", ")
            );
        }
        for g in &self.guards {
            match &g.guard {
                Some(guard) => out += &format!("guard: {} when {guard}\n", g.event),
                None => {
                    out += &format!(
                        "guard: {} over the supervisors' states (not a function of the variables)\n",
                        g.event
                    )
                }
            }
        }
        out
    }
}

/// A controllable event's condition in its rung.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct GuardEntry {
    /// The event.
    pub event: String,
    /// The supervisors' guard over the variables, `None` where their states are tested instead.
    pub guard: Option<String>,
}

/// Variables of the function block.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Variables {
    /// `VAR_INPUT` entries.
    pub inputs: usize,
    /// `VAR_OUTPUT` entries.
    pub outputs: usize,
    /// `VAR` entries (arrays count once).
    pub locals: usize,
    /// Where every uncontrollable event comes from and what every mapped controllable event drives.
    pub io: Vec<IoEntry>,
}

/// One event's place in the I/O map.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct IoEntry {
    /// The event.
    pub event: String,
    /// `input` (an uncontrollable event's source), `output`, or `timer` (a `[[timers]]` timeout, which
    /// the program raises itself).
    pub direction: &'static str,
    /// Program variable (`EVENTS.<member>` for internal events; for a timer, its `TON` instance's
    /// `<instance>.Q`, a local of the function block).
    pub variable: String,
    /// `rising`, `falling`, `both` (inputs, timers) or `set`, `clear`, `pulse` (outputs).
    pub kind: &'static str,
    /// Pulse length in scans (0 otherwise).
    pub scans: u16,
}

/// Statement counts.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Statements {
    /// Top-level statements of the function block per section kind.
    pub sections: BTreeMap<&'static str, usize>,
    /// All top-level statements of the function block.
    pub function_block: usize,
    /// Top-level statements of the program.
    pub program: usize,
    /// The seed documents' structure: initialisation, AEEM set, transitions, AEEM reset.
    pub seed_structure: usize,
}

/// One avalanche event in one automaton.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct AvalancheEntry {
    /// Automaton.
    pub automaton: String,
    /// Event.
    pub event: String,
    /// `order`, `aeem`, `none` or `case`.
    pub method: &'static str,
}

/// How simultaneous inputs are handled and where their order matters.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Simultaneity {
    /// The rule.
    pub applied: &'static str,
    /// Pairs of uncontrollable events whose two orders differ somewhere in the closed loop.
    pub order_matters: Vec<[String; 2]>,
    /// Closed-loop states where they do.
    pub findings: usize,
}

impl Report {
    /// The report of `program`, written as `files` for `set` with `opts`.
    pub fn new(
        set: &PackSet,
        opts: &PlcOptions,
        program: &Program,
        files: &[(String, String)],
    ) -> Result<Report, PlcError> {
        let events = set.events();
        let count = |class| program.fb.vars.iter().filter(|(c, _)| *c == class).map(|(_, v)| v.len()).sum();
        let mut io = Vec::new();
        for (&e, source) in &program.io.sources {
            let (variable, kind) = match source {
                Source::Input { variable, edge, .. } => (variable.clone(), edge.name()),
                Source::Member(m) => (format!("EVENTS.{m}"), "rising"),
            };
            io.push(IoEntry {
                event: events.name(e).to_owned(),
                direction: "input",
                variable,
                kind,
                scans: 0,
            });
        }
        for (e, ton) in &program.timers {
            io.push(IoEntry {
                event: events.name(*e).to_owned(),
                direction: "timer",
                variable: format!("{ton}.Q"),
                kind: "rising",
                scans: 0,
            });
        }
        for o in &program.io.outputs {
            for &(e, action, scans) in &o.actions {
                io.push(IoEntry {
                    event: events.name(e).to_owned(),
                    direction: "output",
                    variable: o.variable.clone(),
                    kind: action.name(),
                    scans,
                });
            }
        }
        let sections: BTreeMap<&'static str, usize> = program.fb.statements().into_iter().collect();
        let seed_structure = SEED_STRUCTURE.iter().map(|k| sections.get(k).copied().unwrap_or(0)).sum();
        let statements = Statements {
            function_block: sections.values().sum(),
            program: program.main.statements().iter().map(|(_, n)| n).sum(),
            sections,
            seed_structure,
        };
        Ok(Report {
            schema: 1,
            name: opts.name.clone(),
            encoding: opts.encoding.name(),
            avalanche_option: opts.avalanche.name(),
            policy: opts.policy.name(),
            guard: opts.guard,
            cycle_ms: opts.cycle_ms,
            files: files.iter().map(|(n, _)| n.clone()).collect(),
            variables: Variables {
                inputs: count(VarClass::Input),
                outputs: count(VarClass::Output),
                locals: count(VarClass::Local),
                io,
            },
            statements,
            bound_per_scan: program.fb.bound() + program.main.bound(),
            memory_bits: program.memory_bits.clone(),
            avalanche: program
                .avalanche
                .iter()
                .map(|(a, e, m)| AvalancheEntry {
                    automaton: a.clone(),
                    event: events.name(*e).to_owned(),
                    method: m.name(),
                })
                .collect(),
            simultaneity: simultaneity(set)?,
            choice_sites: program.sites,
            guards: GuardsReport::new(&program.guards, events),
        })
    }

    /// The report as text, one fact per line.
    pub fn text(&self) -> String {
        let mut out = format!(
            "{}: encoding {}, avalanche {}, policy {}, guard {}, task every {} ms\n",
            self.name, self.encoding, self.avalanche_option, self.policy, self.guard, self.cycle_ms
        );
        out += &format!(
            "variables: {} inputs, {} outputs, {} locals\n",
            self.variables.inputs, self.variables.outputs, self.variables.locals
        );
        let sections: Vec<String> =
            self.statements.sections.iter().map(|(k, n)| format!("{k} {n}")).collect();
        out += &format!(
            "statements: function block {} ({}), program {}; seed structure {}\n",
            self.statements.function_block,
            sections.join(", "),
            self.statements.program,
            self.statements.seed_structure
        );
        out += &format!("statements executed per scan: at most {}\n", self.bound_per_scan);
        out += &format!("memory bits: {}\n", self.memory_bits.len());
        if self.avalanche.is_empty() {
            out += "avalanche: no event chains in any automaton\n";
        }
        for a in &self.avalanche {
            out += &format!("avalanche: {} in {}: {}\n", a.event, a.automaton, a.method);
        }
        out += &self.guards.text();
        out += &format!("simultaneity: {}", self.simultaneity.applied);
        if self.simultaneity.order_matters.is_empty() {
            out += "; the order never matters\n";
        } else {
            let pairs: Vec<String> =
                self.simultaneity.order_matters.iter().map(|[a, b]| format!("{a}/{b}")).collect();
            out += &format!(
                "; the order matters for {} ({} closed-loop states)\n",
                pairs.join(", "),
                self.simultaneity.findings
            );
        }
        out
    }
}

/// The simultaneity check on the closed loop (plants ‖ supervisors).
fn simultaneity(set: &PackSet) -> Result<Simultaneity, PlcError> {
    let automata: Vec<_> = set.members().iter().map(|m| m.automaton.clone()).collect();
    let closed = match automata.as_slice() {
        [one] => one.clone(),
        many => product(many, &Config::default()).map_err(PlcError::Simultaneity)?,
    };
    let found = check(&closed, &[Problem::Simultaneity]);
    let mut pairs: Vec<[String; 2]> =
        found.iter().map(|f| [f.events[0].clone(), f.events[1].clone()]).collect();
    pairs.sort();
    pairs.dedup();
    Ok(Simultaneity {
        applied: "edges latched, one applied per scan in event id order",
        order_matters: pairs,
        findings: found.len(),
    })
}
