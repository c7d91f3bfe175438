//! State-based programs (state feedback control, docs/design.md §10; Côté, St-Denis & Kerjean): the program
//! tracks no event — each scan it reads the plant's state from its signals and, per controllable event
//! σ, evaluates F_σ over them; where F_σ holds, σ's command writes its outputs.
//!
//! # Overview
//!
//! * [`vector`] — the manifest's `[state]` section bound to the set's plants and checked against them.
//! * [`sfbc`] — f from the reachable closed loop plants ‖ supervisors; where the supervisors' memory
//!   decides, the plant states with two traces, or the supervisors kept as memory.
//! * [`guards`] — the rungs from guards read off the symbolic engine's BDDs (`--engine symbolic`), for
//!   plants whose closed loop is too large to list.
//! * [`minimise`] — F_σ as a prime, irredundant sum of products (BDDs), don't-cares only where no
//!   reachable state's signals are.
//! * [`program`] — the rungs (shared literals in series, products in parallel, SET/RESET coils), the ST
//!   `PROGRAM` written by the project's ST writer ([`crate::plc::st`]) and the Ladder Diagram body
//!   ([`crate::plc::ld`]) beside it in the PLCopen XML ([`crate::plc::xml`]).
//!
//! The same rungs are the tables of the state-based firmware (`[runtime] mode = "state"`), written by
//! [`crate::emit::state`].
//! * [`report`] — |f|, rungs, literals and products per rung, instruction-list instructions and stack
//!   depth ([`crate::plc::ld`]'s cost model), scan time, and the table of f as in the paper's Table 1.
//!
//! [`validate`] is the translation validation: for every reachable state x and every valuation of the
//! signals that reads as x, each rung conducts exactly when f_σ(x) = 1.

pub mod guards;
pub mod memory;
pub mod minimise;
pub mod program;
pub mod report;
pub mod sfbc;
pub mod vector;

use crate::config::{Cube, ScanPolicy, Signals, SignalsError};
use crate::pack::PackSet;
use crate::plc::names::sanitize;
use crate::plc::{comment, header, ld, xml, PlcOptions};
use crate::provenance::Provenance;
use crate::synth::{Reachable, SynthError};

pub use program::{EventRung, OnePerScan};
pub use report::Report;
pub use sfbc::Sfbc;
pub use vector::Vector;

/// Why a state-based program cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    /// The manifest has no `[state]` section.
    #[error("--encoding state needs the manifest's [state] section (the plant's state vectors)")]
    Missing,
    /// The section is malformed.
    #[error(transparent)]
    Signals(#[from] SignalsError),
    /// The section does not fit the set's plants.
    #[error("{key}: {message}")]
    Vector {
        /// The key it is about.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// The closed loop could not be explored.
    #[error("closed loop: {0}")]
    Synth(#[from] SynthError),
    /// The program breaks a rule of the strict IEC writer (a bug here, not in the input).
    #[error("internal error, please report: the program is not strict IEC 61131-3: {0}")]
    Strict(#[from] crate::plc::strict::Violation),
    /// The supervisors' memory decides somewhere and memory is not allowed.
    #[error("{0}")]
    Memory(String),
}

/// What the command line adds to the manifest's `[state]` keys (each ORed with its key).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StateOptions {
    /// Keep supervisors' states where the plant state does not decide (`--memory`).
    pub memory: bool,
    /// F_σ without don't-cares (`--exact`).
    pub exact: bool,
    /// One command per scan, chosen by this policy (`--choice`).
    pub choice: Option<ScanPolicy>,
}

/// The program's files, report and rungs.
#[derive(Clone, Debug)]
pub struct Output {
    /// `(file name, contents)`: `<name>.st`, `<name>_config.st`, `<name>.xml`.
    pub files: Vec<(String, String)>,
    /// The figures and the table of f.
    pub report: Report,
    /// One rung per controllable event, in order.
    pub rungs: Vec<EventRung>,
    /// The state vectors bound to the set.
    pub vector: Vector,
    /// The feedback.
    pub sfbc: Sfbc,
    /// The kept supervisors' memory (empty when the plant state decides).
    pub memory: memory::Memory,
    /// The choice of one command per scan, when the program makes one.
    pub one: Option<OnePerScan>,
}

impl Output {
    /// The program's Boolean variables: the signals, then the memory bits.
    pub fn names(&self) -> Vec<String> {
        variable_names(&self.vector, &self.memory)
    }
}

fn variable_names(vector: &Vector, memory: &memory::Memory) -> Vec<String> {
    vector.signals.signals.iter().map(|s| s.name.clone()).chain(memory.names.iter().cloned()).collect()
}

/// The cube of entry `e`: its plant state's formula and its kept supervisors' memory bits.
fn entry_cube(vector: &Vector, f: &Sfbc, memory: &memory::Memory, e: &sfbc::Entry) -> Cube {
    let x = vector.cube(&e.state[..f.plants]);
    let m = memory.cube(&e.state[f.plants..]);
    Cube { mask: x.mask | m.mask, value: x.value | m.value }
}

/// The feedback of `set` under `signals`' state vectors, and the state vectors bound to it.
pub fn analyse(set: &PackSet, signals: Signals, memory: bool) -> Result<(Vector, Sfbc), StateError> {
    let vector = Vector::bind(set, signals)?;
    let f = Sfbc::compute(set, memory || vector.signals.memory)?;
    Ok((vector, f))
}

/// The rungs of `f`: per controllable event, F_σ minimised between its ON set and the valuations no
/// reachable state produces (none with `exact`).
pub fn rungs(
    set: &PackSet,
    vector: &Vector,
    f: &Sfbc,
    memory: &memory::Memory,
    exact: bool,
) -> Vec<EventRung> {
    let names = variable_names(vector, memory);
    let u = minimise::Universe::new(names.len());
    let cubes: Vec<Cube> = f.entries.iter().map(|e| entry_cube(vector, f, memory, e)).collect();
    let reachable = u.union(&cubes);
    let dc = if exact { u.union(&[]) } else { reachable.not() };
    f.controllable
        .iter()
        .enumerate()
        .map(|(i, &e)| {
            let on: Vec<Cube> =
                f.entries.iter().zip(&cubes).filter(|(en, _)| en.allowed[i]).map(|(_, &c)| c).collect();
            let cover = u.minimise(&u.union(&on), &dc);
            let command = vector.commands[e.index()].map_or(Cube::default(), |(_, c)| c);
            let extra = memory.after.get(&e.as_u32()).cloned().unwrap_or_default();
            program::rung(&names, set.events().name(e), cover, command, extra)
        })
        .collect()
}

/// Translation validation: for every entry of `f` (a reachable plant state x, with the kept supervisors'
/// states when memory is kept) and every valuation of the program's variables that reads as it, rung σ
/// conducts iff f_σ(x) = 1. Returns the valuations checked, or the first disagreement.
pub fn validate(out: &Output, rungs: &[EventRung]) -> Result<usize, String> {
    let (vector, f) = (&out.vector, &out.sfbc);
    let names = out.names();
    let all = if names.len() == 64 { u64::MAX } else { (1u64 << names.len()) - 1 };
    let mut checked = 0;
    for e in &f.entries {
        let x = entry_cube(vector, f, &out.memory, e);
        let free = all & !x.mask;
        let mut sub = free;
        loop {
            let v = x.value | sub;
            let closed = |var: &str| names.iter().position(|n| *n == var).is_some_and(|i| v >> i & 1 == 1);
            for (k, r) in rungs.iter().enumerate() {
                if r.rung.condition.conducts(&closed) != e.allowed[k] {
                    return Err(format!(
                        "rung {} at plant state {:?} (signals {v:#b}): conducts {}, f says {}",
                        r.event, e.state, !e.allowed[k], e.allowed[k]
                    ));
                }
            }
            checked += 1;
            if sub == 0 {
                break;
            }
            sub = (sub - 1) & free;
        }
    }
    Ok(checked)
}

/// States and transitions of the reachable product of `dfas` (the free plant G, or the specification E).
pub fn product_size(dfas: &[&crate::model::Dfa]) -> Result<(usize, usize), SynthError> {
    let r = Reachable::explore(dfas, sfbc::STATE_LIMIT)?;
    Ok((r.dfa().state_count(), r.dfa().transition_count()))
}

/// Writes the state-based program of `set` with `opts` and the state vectors `signals`; `choices` allow
/// supervisor memory (as `[state] memory`), keep F_σ free of don't-cares (as `[state] exact`) and fire
/// one command per scan by a choice policy (as `[state] choice`). `event_based` is the event-based program's report for
/// the same set, for the comparison figures.
pub fn generate(
    set: &PackSet,
    signals: Signals,
    opts: &PlcOptions,
    choices: StateOptions,
    provenance: &Provenance,
    event_based: Option<&crate::plc::Report>,
) -> Result<Output, StateError> {
    let exact = choices.exact || signals.exact;
    let policy = choices.choice.or(signals.choice);
    let (vector, f) = analyse(set, signals, choices.memory)?;
    if !f.conflicts.is_empty() && f.memory.is_none() {
        return Err(StateError::Memory(report::conflicts_text(set, &f)));
    }
    let signal_names = variable_names(&vector, &memory::Memory::default());
    let memory = match &f.memory {
        Some(m) => memory::Memory::new(set, &vector, &m.kept, &signal_names)?,
        None => memory::Memory::default(),
    };
    let rungs = self::rungs(set, &vector, &f, &memory, exact);
    let one =
        policy.map(|policy| OnePerScan::new(policy, opts.seed, &vector, f.controllable.iter().copied()));
    let files = program_files(set, &vector, &rungs, &memory, one.as_ref(), opts, exact, provenance)?;
    let ns = opts.spec.instruction_ns.unwrap_or(1000);
    let plants: Vec<_> = set.members()[..f.plants].iter().map(|m| &m.dfa).collect();
    let g = product_size(&plants)?;
    let mut report = Report::new(set, &vector, &f, &rungs, g, ns, event_based);
    report.choice = policy.map(ScanPolicy::name);
    Ok(Output { files, report, rungs, vector, sfbc: f, memory, one })
}

/// The program's files from its rungs: `<name>.st` (the `PROGRAM`), `<name>_config.st` and
/// `<name>.xml` (PLCopen XML with the Ladder Diagram body when no memory is kept and no choice is
/// made), each with the header; `one` makes the scan fire one chosen rung.
#[allow(clippy::too_many_arguments)]
pub fn program_files(
    set: &PackSet,
    vector: &Vector,
    rungs: &[EventRung],
    memory: &memory::Memory,
    one: Option<&OnePerScan>,
    opts: &PlcOptions,
    exact: bool,
    provenance: &Provenance,
) -> Result<Vec<(String, String)>, StateError> {
    let base = sanitize(&opts.name);
    let pou = program::pou(&vector.signals, &base, rungs, memory, one)?;
    crate::plc::strict::check(&[], &[&pou])?;
    let ns = opts.spec.instruction_ns.unwrap_or(1000);
    let options = format!(
        "Options: encoding=state memory={} exact={exact} choice={} cycle_ms={} instruction_ns={ns}",
        !memory.kept.is_empty(),
        one.map_or("none", |o| o.policy.name()),
        opts.cycle_ms
    );
    let header: Vec<String> = header(set, opts, provenance)
        .into_iter()
        .map(|l| if l.starts_with("Options:") { options.clone() } else { l })
        .collect();
    let st = format!("{}\n{}", comment(&header), pou.text());
    let config = format!("{}\n{}", comment(&header), xml::configuration_text(&base, opts.cycle_ms));
    // The Ladder Diagram body holds the rungs alone: a program with memory tracks it, and one with a
    // choice policy chooses among its rungs, in ST only.
    let ladder: Vec<ld::Rung> = rungs.iter().map(|r| r.rung.clone()).collect();
    let bodies = if memory.kept.is_empty() && one.is_none() { vec![ld::body(&ladder)] } else { Vec::new() };
    let xml = xml::document(None, &[(&pou, &bodies)], &base, opts.cycle_ms, &header);
    Ok(vec![(format!("{base}.st"), st), (format!("{base}_config.st"), config), (format!("{base}.xml"), xml)])
}
