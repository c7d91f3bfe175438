//! What a state-based program costs and what its feedback is: |f|, rungs, literals and products per
//! rung, instruction-list instructions and stack depth (the cost model of [`crate::scan::ld`]), the scan
//! time at the `[plc] instruction_ns` per instruction, the event-based program's figures for the same
//! set, and f as a table of plant states (component → state, with the kept supervisors' states where
//! memory is kept) and the events inhibited there — the paper's Table 1. docs/state-based.md defines
//! every figure.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use num_bigint::BigUint;
use serde::Serialize;

use super::EventRung;
use crate::feedback::{Sfbc, Vector};
use crate::pack::PackSet;
pub use crate::plc::report::GuardsReport;
use crate::symbolic::Guards;

/// One rung's figures.
#[derive(Clone, Debug, Serialize)]
pub struct RungFigures {
    /// The controllable event.
    pub event: String,
    /// Products of F_σ.
    pub products: usize,
    /// Literals of F_σ as a sum of products.
    pub literals: usize,
    /// Contacts of the factored rung.
    pub contacts: usize,
    /// Instruction-list instructions, coils included.
    pub il_instructions: usize,
    /// Logic stack depth.
    pub stack_depth: usize,
    /// The rung's condition as ST.
    pub formula: String,
}

/// One state of f's domain where f inhibits something.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Component → its state.
    pub state: BTreeMap<String, String>,
    /// Kept supervisor → its state, where memory is kept.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub memory: BTreeMap<String, String>,
    /// The physically possible controllable events f disables, in event order.
    pub disabled: Vec<String>,
}

/// The memory a program keeps.
#[derive(Clone, Debug, Serialize)]
pub struct MemoryFigures {
    /// The kept supervisors.
    pub kept: Vec<String>,
    /// Bits their states take (⌈log2 states⌉ each): the program's memory `BOOL`s, beside an `INT`
    /// per kept supervisor.
    pub bits: u32,
    /// (plant state, event) pairs where memory decides.
    pub conflicts: usize,
    /// f's domain: the reachable (plant state, kept supervisors' states) pairs.
    pub domain_states: usize,
}

/// The event-based program's figures for the same set (the `int` encoding).
#[derive(Clone, Debug, Serialize)]
pub struct EventBased {
    /// Top-level statements of the function block and the program.
    pub statements: usize,
    /// Static bound on statements per scan.
    pub bound_per_scan: u64,
}

/// The figures.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// States of the free plant G (reachable product of the plants).
    pub plant_states: usize,
    /// Its transitions.
    pub plant_transitions: usize,
    /// Reachable states of plants ‖ supervisors.
    pub closed_loop_states: usize,
    /// Reachable plant states under supervision: the closed loop's states projected on the plants.
    pub reachable_plant_states: usize,
    /// |f|: the states of f's domain (reachable plant states, or (plant state, memory) pairs where
    /// memory is kept) where f disables a physically possible controllable event.
    pub entries: usize,
    /// Rungs: one per controllable event.
    pub rungs: usize,
    /// Signals read or written.
    pub signals: usize,
    /// Per rung.
    pub per_rung: Vec<RungFigures>,
    /// Instruction-list instructions of the whole program.
    pub il_instructions: usize,
    /// Deepest logic stack of any rung.
    pub stack_depth: usize,
    /// Time per instruction, in nanoseconds.
    pub instruction_ns: u32,
    /// Scan time: instructions × time per instruction, in microseconds.
    pub scan_us: f64,
    /// The task's cycle (`[plc] cycle_ms`), in milliseconds: a scan longer than it is a finding.
    pub cycle_ms: u32,
    /// The supervisors kept as memory, when the plant state does not decide.
    pub memory: Option<MemoryFigures>,
    /// The policy choosing one command per scan (`[state] choice`), when the program fires one.
    pub choice: Option<&'static str>,
    /// The event-based program's figures, when computed.
    pub event_based: Option<EventBased>,
    /// f as a table.
    pub table: Vec<Row>,
    /// The modules' variables the program keeps and the guards over them (`efa_variables`, `guards`).
    #[serde(flatten)]
    pub guards: GuardsReport,
}

impl Report {
    /// Whether the scan estimate (`scan_us`) is longer than the task's cycle (`cycle_ms`): a finding,
    /// since the PLC could not run the program every cycle.
    pub fn scan_too_long(&self) -> bool {
        self.scan_us > f64::from(self.cycle_ms) * 1000.0
    }

    /// The figures of `rungs` for `f` over `set`; `g` is the free plant's size, `ns` the time per
    /// instruction.
    pub fn new(
        set: &PackSet,
        vector: &Vector,
        f: &Sfbc,
        rungs: &[EventRung],
        g: (usize, usize),
        ns: u32,
        event_based: Option<(usize, u64)>,
    ) -> Report {
        let per_rung: Vec<RungFigures> = rungs
            .iter()
            .map(|r| {
                let il = r.rung.il();
                RungFigures {
                    event: r.event.clone(),
                    products: r.cubes.len(),
                    literals: r.cubes.iter().map(|c| c.len()).sum(),
                    contacts: r.rung.condition.contacts(),
                    il_instructions: il.instructions,
                    stack_depth: il.stack_depth,
                    formula: r.rung.condition.st().text(),
                }
            })
            .collect();
        let il: usize = per_rung.iter().map(|r| r.il_instructions).sum();
        Report {
            plant_states: g.0,
            plant_transitions: g.1,
            closed_loop_states: f.closed_states,
            reachable_plant_states: f.plant_states,
            entries: f.size(),
            rungs: rungs.len(),
            signals: vector.signals.signals.len(),
            stack_depth: per_rung.iter().map(|r| r.stack_depth).max().unwrap_or(0),
            il_instructions: il,
            instruction_ns: ns,
            scan_us: il as f64 * f64::from(ns) / 1000.0,
            cycle_ms: 10,
            choice: None,
            per_rung,
            event_based: event_based
                .map(|(statements, bound_per_scan)| EventBased { statements, bound_per_scan }),
            table: table(set, f),
            guards: GuardsReport::default(),
            memory: f.memory.as_ref().map(|m| MemoryFigures {
                kept: m.kept.iter().map(|&k| set.members()[k].name().to_owned()).collect(),
                bits: m.bits,
                conflicts: f.conflicts.len(),
                domain_states: f.entries.len(),
            }),
        }
    }

    /// The report as text.
    pub fn text(&self) -> String {
        let mut out = String::new();
        let domain = self
            .memory
            .as_ref()
            .map_or(String::new(), |m| format!(", {} with the kept supervisors' states", m.domain_states));
        let _ = writeln!(
            out,
            "state-based program: G {} states / {} transitions; closed loop {} states over {} plant states{domain}; |f| = {}",
            self.plant_states, self.plant_transitions, self.closed_loop_states, self.reachable_plant_states, self.entries
        );
        let _ = writeln!(
            out,
            "{} rungs over {} signals: {} IL instructions, stack depth {}, scan {:.1} us at {} ns per instruction",
            self.rungs, self.signals, self.il_instructions, self.stack_depth, self.scan_us, self.instruction_ns
        );
        if self.scan_too_long() {
            let _ = writeln!(
                out,
                "finding: the scan ({:.1} ms) is longer than the task's cycle ({} ms, [plc] cycle_ms): the PLC \
                 cannot run the program every cycle; raise cycle_ms, or set instruction_ns to the PLC's own \
                 figure if it is faster",
                self.scan_us / 1000.0,
                self.cycle_ms
            );
        }
        if let Some(policy) = self.choice {
            let _ = writeln!(
                out,
                "one command per scan, chosen by {policy} among the rungs that conduct (the choice section is not in the IL count)"
            );
        }
        if let Some(m) = &self.memory {
            let _ = writeln!(
                out,
                "memory decides at {} (plant state, event) pairs: kept {} ({} bits: as many BOOLs in the program, beside an INT per supervisor)",
                m.conflicts,
                m.kept.join(", "),
                m.bits
            );
        }
        if let Some(e) = &self.event_based {
            let _ = writeln!(
                out,
                "event-based program (int) for the same set: {} statements, at most {} per scan",
                e.statements, e.bound_per_scan
            );
        }
        out += &self.guards.text();
        for r in &self.per_rung {
            let _ = writeln!(
                out,
                "  {:<10} {} products, {} literals, {} contacts, {} IL, depth {}: {}",
                r.event, r.products, r.literals, r.contacts, r.il_instructions, r.stack_depth, r.formula
            );
        }
        let _ = writeln!(out, "f ({} entries):", self.table.len());
        for row in &self.table {
            let state: Vec<String> = row.state.iter().map(|(c, s)| format!("{c}={s}")).collect();
            let memory: Vec<String> = row.memory.iter().map(|(c, s)| format!(" {c}={s}")).collect();
            let memory = if memory.is_empty() { String::new() } else { format!(" |{}", memory.concat()) };
            let _ = writeln!(out, "  {}{memory} -> {}", state.join(" "), row.disabled.join(" "));
        }
        out
    }
}

/// f as rows, in the order of its domain's states.
fn table(set: &PackSet, f: &Sfbc) -> Vec<Row> {
    let members = set.members();
    let name = |m: usize, s: u32| {
        let a = &members[m].automaton;
        (a.name.clone(), a.states[s as usize].name.clone())
    };
    let kept = f.memory.as_ref().map_or(&[][..], |m| m.kept.as_slice());
    f.entries
        .iter()
        .filter(|e| e.inhibits())
        .map(|e| Row {
            state: e.state[..f.plants].iter().enumerate().map(|(p, &s)| name(p, s)).collect(),
            memory: kept.iter().zip(&e.state[f.plants..]).map(|(&k, &s)| name(k, s)).collect(),
            disabled: f
                .controllable
                .iter()
                .enumerate()
                .filter(|&(i, _)| e.possible[i] && !e.allowed[i])
                .map(|(_, &ev)| set.events().name(ev).to_owned())
                .collect(),
        })
        .collect()
}

/// The plant states where the supervisors' memory decides, each with a trace to a closed-loop state
/// enabling the event and one disabling it.
pub fn conflicts_text(set: &PackSet, f: &Sfbc) -> String {
    let names = |t: &[crate::model::EventId]| -> String {
        if t.is_empty() {
            "(initial state)".into()
        } else {
            t.iter().map(|&e| set.events().name(e)).collect::<Vec<_>>().join(" ")
        }
    };
    let mut out = format!(
        "the supervisors' memory decides at {} (plant state, event) pairs: no state feedback exists; allow memory with --memory or [state] memory = true",
        f.conflicts.len()
    );
    for c in &f.conflicts {
        let state: Vec<String> = c
            .state
            .iter()
            .enumerate()
            .map(|(p, &s)| {
                let a = &set.members()[p].automaton;
                format!("{}={}", a.name, a.states[s as usize].name)
            })
            .collect();
        let _ = write!(
            out,
            "\n  {} {}: enabled after {}; disabled after {}",
            state.join(" "),
            set.events().name(c.event),
            names(&c.enabled_after),
            names(&c.disabled_after)
        );
    }
    out
}

/// One rung's figures in a program written from guards.
#[derive(Clone, Debug, Serialize)]
pub struct SymbolicRung {
    /// The controllable event.
    pub event: String,
    /// Products of F_σ.
    pub products: usize,
    /// Literals of F_σ as a sum of products.
    pub literals: usize,
    /// Nodes of the guard's BDD (over the state variables).
    pub bdd_nodes: usize,
}

/// The figures of a state-based program written from guards (`--engine symbolic`).
#[derive(Clone, Debug)]
pub struct SymbolicReport {
    /// Reachable plant states under the monolithic supervisor, exact.
    pub reachable_plant_states: BigUint,
    /// Per rung.
    pub rungs: Vec<SymbolicRung>,
}

impl SymbolicReport {
    /// The figures of `rungs` written from `guards`.
    pub fn new(guards: &Guards, rungs: &[EventRung]) -> SymbolicReport {
        let rungs = rungs
            .iter()
            .map(|r| SymbolicRung {
                event: r.event.clone(),
                products: r.cubes.len(),
                literals: r.cubes.iter().map(|c| c.len()).sum(),
                bdd_nodes: guards.guards.iter().find(|g| g.event == r.event).map_or(0, |g| g.allowed.size()),
            })
            .collect();
        SymbolicReport { reachable_plant_states: guards.count(&guards.reachable), rungs }
    }

    /// The report as text.
    pub fn text(&self) -> String {
        let mut out = format!(
            "reachable plant states: {}\nrung  products  literals  guard BDD nodes\n",
            self.reachable_plant_states
        );
        for r in &self.rungs {
            let _ = writeln!(out, "{}  {}  {}  {}", r.event, r.products, r.literals, r.bdd_nodes);
        }
        out
    }
}

impl Serialize for SymbolicReport {
    /// `reachable_plant_states` (a number while it fits in 64 bits, else its decimal string) and `rungs`.
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct as _;
        let mut s = serializer.serialize_struct("SymbolicReport", 2)?;
        match u64::try_from(&self.reachable_plant_states) {
            Ok(n) => s.serialize_field("reachable_plant_states", &n)?,
            Err(_) => {
                s.serialize_field("reachable_plant_states", &self.reachable_plant_states.to_string())?
            }
        }
        s.serialize_field("rungs", &self.rungs)?;
        s.end()
    }
}
