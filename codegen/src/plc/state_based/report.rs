//! What a state-based program costs and what its feedback is: |f|, rungs, literals and products per
//! rung, instruction-list instructions and stack depth (the cost model of [`crate::plc::ld`]), the scan
//! time at the `[plc] instruction_ns` per instruction, the event-based program's figures for the same
//! set, and f as a table of plant states (component → state) and the events inhibited there — the
//! paper's Table 1.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use super::{EventRung, Sfbc, Vector};
use crate::pack::PackSet;

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

/// One plant state where f inhibits something.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Component → its state.
    pub state: BTreeMap<String, String>,
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
    /// Reachable plant states under supervision (the domain of f).
    pub reachable_plant_states: usize,
    /// |f|: reachable plant states where f disables a physically possible controllable event.
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
}

impl Report {
    /// The figures of `rungs` for `f` over `set`; `g` is the free plant's size, `ns` the time per
    /// instruction.
    pub fn new(
        set: &PackSet,
        vector: &Vector,
        f: &Sfbc,
        rungs: &[EventRung],
        g: (usize, usize),
        ns: u32,
        event_based: Option<&crate::plc::Report>,
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
            reachable_plant_states: f.entries.len(),
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
            event_based: event_based.map(|r| EventBased {
                statements: r.statements.function_block + r.statements.program,
                bound_per_scan: r.bound_per_scan,
            }),
            table: table(set, f),
            memory: f.memory.as_ref().map(|m| MemoryFigures {
                kept: m.kept.iter().map(|&k| set.members()[k].name().to_owned()).collect(),
                bits: m.bits,
                conflicts: f.conflicts.len(),
            }),
        }
    }

    /// The report as text.
    pub fn text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "state-based program: G {} states / {} transitions; closed loop {} states over {} plant states; |f| = {}",
            self.plant_states, self.plant_transitions, self.closed_loop_states, self.reachable_plant_states, self.entries
        );
        let _ = writeln!(
            out,
            "{} rungs over {} signals: {} IL instructions, stack depth {}, scan {:.1} us at {} ns per instruction",
            self.rungs, self.signals, self.il_instructions, self.stack_depth, self.scan_us, self.instruction_ns
        );
        if self.scan_us > f64::from(self.cycle_ms) * 1000.0 {
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
            let _ = writeln!(out, "  {} -> {}", state.join(" "), row.disabled.join(" "));
        }
        out
    }
}

/// f as rows, in the order of the plant states.
fn table(set: &PackSet, f: &Sfbc) -> Vec<Row> {
    let members = set.members();
    f.entries
        .iter()
        .filter(|e| e.inhibits())
        .map(|e| Row {
            state: e.state[..f.plants]
                .iter()
                .enumerate()
                .map(|(p, &s)| {
                    let a = &members[p].automaton;
                    (a.name.clone(), a.states[s as usize].name.clone())
                })
                .collect(),
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
