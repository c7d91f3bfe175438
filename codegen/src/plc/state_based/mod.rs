//! State-based programs (state feedback control, docs/design.md §10; Côté, St-Denis & Kerjean): the
//! program tracks no event — each scan it reads the plant's state from its signals and, per
//! controllable event σ, evaluates F_σ over them; where F_σ holds, σ's command writes its outputs. The
//! feedback itself is [`crate::feedback`]'s; this module writes it as a program.
//!
//! # Overview
//!
//! * [`rungs`] — F_σ factored into a rung (shared literals in series, products in parallel,
//!   SET/RESET coils).
//! * [`memory`] — where memory is kept, the supervisors' states tracked from events in ST, and a
//!   module's variables and guards over them ([`crate::plc::guards`]): a guarded event's rung is F_σ in
//!   series with its guard's `BOOL`.
//! * [`program`] — the ST `PROGRAM` written by the project's ST writer ([`crate::scan::st`]), the Ladder
//!   Diagram body ([`crate::scan::ld`]) beside it in the PLCopen XML, and the choice of one command per
//!   scan ([`program::OnePerScan`]).
//! * [`report`] — the figures of the program and its feedback, and f as a table.
//!
//! [`validate`] is the translation validation: for every reachable state x and every valuation of the
//! signals that reads as x, each rung conducts exactly when f_σ(x) = 1.

pub mod closed_loop;
pub mod memory;
pub mod program;
pub mod report;
pub mod rungs;

use std::path::Path;

use crate::config::{ScanPolicy, Signals};
use crate::feedback::memory::Layout;
use crate::feedback::{self, guards, product_size, FeedbackError, Sfbc, Vector};
use crate::model::EventId;
use crate::pack::PackSet;
use crate::provenance::Provenance;
use crate::scan::files::{File, Header, Source};
use crate::scan::names::sanitize;
use crate::scan::{Graphic, Program as ScanProgram};
use crate::symbolic::{self, Guards};
use crate::synth::Config;

use super::{about, PlcError, PlcOptions};

pub use memory::Tracking;
pub use program::OnePerScan;
pub use report::{GuardsReport, Report, SymbolicReport};
pub use rungs::EventRung;

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

impl StateOptions {
    /// The command-line words of these options after `--encoding state`, for the engine `engine`
    /// (`--memory --exact --choice first`; `--exact --engine symbolic --choice first`).
    pub fn words(&self, engine: &Engine) -> Vec<String> {
        let symbolic = matches!(engine, Engine::Symbolic { .. });
        let mut out = vec![String::from("--encoding state")];
        if self.memory && !symbolic {
            out.push("--memory".into());
        }
        if self.exact {
            out.push("--exact".into());
        }
        if symbolic {
            out.push("--engine symbolic".into());
        }
        if let Some(p) = self.choice {
            out.push(format!("--choice {}", p.name()));
        }
        out
    }
}

/// Where a state-based program's feedback comes from.
#[derive(Clone, Default)]
pub enum Engine {
    /// The explicit closed loop of the project's supervisor set, listed state by state.
    #[default]
    Explicit,
    /// Guards read off the BDDs of the monolithic supervisor of the project's plants and
    /// specifications: for plants whose closed loop is too large to list.
    Symbolic {
        /// Limits and progress of the synthesis on BDDs.
        cfg: Config,
        /// The symbolic engine's settings.
        options: symbolic::Options,
    },
}

/// A state-based program from the explicit closed loop: its files, report and what they came from.
#[derive(Clone, Debug)]
pub struct Output {
    /// `(file name, contents)`: `<name>.st`, `<name>_config.st`, `<name>.xml`.
    pub files: Vec<File>,
    /// The program the files are written from, for a vendor's printer.
    pub sources: Vec<Source>,
    /// The figures and the table of f.
    pub report: Report,
    /// One rung per controllable event, in order.
    pub rungs: Vec<EventRung>,
    /// The state vectors bound to the set.
    pub vector: Vector,
    /// The feedback.
    pub sfbc: Sfbc,
    /// The kept supervisors' memory (empty when the plant state decides).
    pub memory: Tracking,
    /// The choice of one command per scan, when the program makes one.
    pub one: Option<OnePerScan>,
}

impl Output {
    /// The program's Boolean variables: the signals, then the memory bits.
    pub fn names(&self) -> Vec<String> {
        variable_names(&self.vector, &self.memory)
    }
}

/// A state-based program written from guards.
#[derive(Clone, Debug)]
pub struct SymbolicOutput {
    /// `(file name, contents)`, as [`Output::files`].
    pub files: Vec<File>,
    /// The program the files are written from, for a vendor's printer.
    pub sources: Vec<Source>,
    /// The figures.
    pub report: SymbolicReport,
    /// One rung per controllable event, in event id order.
    pub rungs: Vec<EventRung>,
    /// The state vectors bound to the set.
    pub vector: Vector,
}

fn variable_names(vector: &Vector, memory: &Tracking) -> Vec<String> {
    vector.signals.signals.iter().map(|s| s.name.clone()).chain(memory.names.iter().cloned()).collect()
}

/// The error `source` of the state feedback, in `file`.
fn in_file(file: &Path) -> impl Fn(FeedbackError) -> PlcError + '_ {
    move |source| PlcError::Feedback { file: file.to_path_buf(), source: Box::new(source) }
}

/// Translation validation: for every entry of `f` (a reachable plant state x, with the kept supervisors'
/// states when memory is kept) and every valuation of the program's variables that reads as it, rung σ
/// conducts iff f_σ(x) = 1 (a guard over a module's variables taken as holding). Returns the valuations checked, or the first disagreement.
pub fn validate(out: &Output, rungs: &[EventRung]) -> Result<usize, String> {
    let (vector, f) = (&out.vector, &out.sfbc);
    let names = out.names();
    let guards: Vec<&str> = out.memory.guards.iter().map(|(_, g)| g.as_str()).collect();
    let all = if names.len() == 64 { u64::MAX } else { (1u64 << names.len()) - 1 };
    let mut checked = 0;
    for e in &f.entries {
        let x = feedback::entry_cube(vector, f, &out.memory.layout, e);
        let free = all & !x.mask;
        let mut sub = free;
        loop {
            let v = x.value | sub;
            // A guard's contact is closed: the guards are checked against the closed loop on their own
            // (`crate::plc::guards`); f_σ is then the rest of the rung.
            let closed = |var: &str| {
                guards.contains(&var) || names.iter().position(|n| *n == var).is_some_and(|i| v >> i & 1 == 1)
            };
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

/// Writes the state-based program of `set` with `opts` and the state vectors `signals`; `choices` allow
/// supervisor memory (as `[state] memory`), keep F_σ free of don't-cares (as `[state] exact`) and fire
/// one command per scan by a choice policy (as `[state] choice`). `event_based` is the event-based
/// program's size for the same set (statements, bound per scan), for the comparison figures. Errors of
/// the feedback name `file`.
pub fn generate(
    set: &PackSet,
    signals: Signals,
    opts: &PlcOptions,
    choices: StateOptions,
    provenance: &Provenance,
    event_based: Option<(usize, u64)>,
    file: &Path,
) -> Result<Output, PlcError> {
    let exact = choices.exact || signals.exact;
    let policy = choices.choice.or(signals.choice);
    // The events whose guard over the modules' variables decides them (the event-based program's
    // analysis): F_σ is their physical possibility, the guard a further contact.
    let guards = crate::plc::guards::extract(set, &opts.efa);
    let decided: Vec<EventId> = guards.guards.iter().map(|(e, _)| *e).collect();
    let (vector, f) = feedback::analyse(set, signals, choices.memory, &decided).map_err(in_file(file))?;
    if !f.conflicts.is_empty() && f.memory.is_none() {
        return Err(in_file(file)(FeedbackError::Memory(report::conflicts_text(set, &f))));
    }
    let signal_names = variable_names(&vector, &Tracking::default());
    let layout = match &f.memory {
        Some(m) => Layout::new(set, &m.kept, signal_names.len()).map_err(in_file(file))?,
        None => Layout::default(),
    };
    let memory = if f.memory.is_some() || !guards.variables.is_empty() {
        Tracking::new(set, &vector, &layout, &signal_names, &guards).map_err(in_file(file))?
    } else {
        Tracking::default()
    };
    let names = variable_names(&vector, &memory);
    let rungs: Vec<EventRung> = feedback::rules(&vector, &f, &layout, exact)
        .iter()
        .map(|r| {
            let extra = memory.after.get(&r.event.as_u32()).cloned().unwrap_or_default();
            rungs::rung(set, &names, r, memory.guard(r.event), extra)
        })
        .collect();
    let one =
        policy.map(|policy| OnePerScan::new(policy, opts.seed, &vector, f.controllable.iter().copied()));
    let source = program_source(set, &vector, &rungs, &memory, one.as_ref(), opts, exact, provenance, file)?;
    let files = source.files()?;
    let ns = opts.spec.instruction_ns.unwrap_or(1000);
    let plants: Vec<_> = set.members()[..f.plants].iter().map(|m| &m.dfa).collect();
    let g = product_size(&plants).map_err(|e| in_file(file)(e.into()))?;
    let mut report = Report::new(set, &vector, &f, &rungs, g, ns, event_based);
    report.guards = GuardsReport::new(&guards, set.events());
    report.choice = policy.map(ScanPolicy::name);
    report.cycle_ms = opts.cycle_ms;
    Ok(Output { files, sources: vec![source], report, rungs, vector, sfbc: f, memory, one })
}

/// Writes the state-based program of `set`'s plants under `signals`' state vectors from `guards` (as
/// [`generate`] does from the explicit closed loop; `choices.exact` keeps F_σ free of don't-cares, and
/// `choices.choice`, else `[state] choice`, fires one command per scan chosen by that policy;
/// `choices.memory` is not read: a program from guards keeps no memory). Errors of the feedback name
/// `file`.
pub fn from_guards(
    set: &PackSet,
    signals: Signals,
    guards: &Guards,
    opts: &PlcOptions,
    choices: StateOptions,
    provenance: &Provenance,
    file: &Path,
) -> Result<SymbolicOutput, PlcError> {
    let exact = choices.exact || signals.exact;
    let policy = choices.choice.or(signals.choice);
    let vector = Vector::bind(set, signals).map_err(in_file(file))?;
    let names = variable_names(&vector, &Tracking::default());
    let rules = guards::rules(set, &vector, guards, exact).map_err(in_file(file))?;
    let rungs: Vec<EventRung> = rules.iter().map(|r| rungs::rung(set, &names, r, None, Vec::new())).collect();
    let one = policy.map(|policy| OnePerScan::new(policy, opts.seed, &vector, rules.iter().map(|r| r.event)));
    let source = program_source(
        set,
        &vector,
        &rungs,
        &Tracking::default(),
        one.as_ref(),
        opts,
        exact,
        provenance,
        file,
    )?;
    let files = source.files()?;
    let report = SymbolicReport::new(guards, &rungs);
    Ok(SymbolicOutput { files, sources: vec![source], report, rungs, vector })
}

/// The program from its rungs with its header, whose files are `<name>.st` (the `PROGRAM`),
/// `<name>_config.st` and `<name>.xml` (PLCopen XML with the Ladder Diagram body when no memory is kept
/// and no choice is made); `one` makes the scan fire one chosen rung.
#[allow(clippy::too_many_arguments)]
fn program_source(
    set: &PackSet,
    vector: &Vector,
    rungs: &[EventRung],
    memory: &Tracking,
    one: Option<&OnePerScan>,
    opts: &PlcOptions,
    exact: bool,
    provenance: &Provenance,
    file: &Path,
) -> Result<Source, PlcError> {
    let base = sanitize(&opts.name);
    let pou = program::pou(&vector.signals, &base, rungs, memory, one).map_err(in_file(file))?;
    let ns = opts.spec.instruction_ns.unwrap_or(1000);
    let header = Header {
        about: vec![about(set, &opts.name)],
        provenance: provenance.clone(),
        options: vec![
            ("encoding", "state".into()),
            ("memory", (!memory.layout.kept.is_empty()).to_string()),
            ("exact", exact.to_string()),
            ("choice", one.map_or("none", |o| o.policy.name()).into()),
            ("cycle_ms", opts.cycle_ms.to_string()),
            ("instruction_ns", ns.to_string()),
        ],
        notes: Vec::new(),
    };
    // The Ladder Diagram body holds the rungs alone: a program with memory (supervisors' states, or a
    // module's variables and guards) tracks it in ST after each rung (ladder for a vendor whose rungs
    // call ST), and one with a choice policy chooses among its rungs, in ST only.
    let ladder = || rungs.iter().map(|r| r.rung.clone()).collect();
    let graphic = match (memory.vars.is_empty(), one) {
        (true, None) => Graphic::Ladder(ladder()),
        (false, None) => Graphic::LadderCallingSt(rungs.iter().map(|r| program::held(&r.rung)).collect()),
        (_, Some(_)) => Graphic::Text,
    };
    let program =
        ScanProgram { base, types: Vec::new(), pous: vec![(pou, graphic)], cycle_ms: opts.cycle_ms };
    Ok(Source { program, header })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::efa::unfold;
    use crate::manifest::Manifest;
    use crate::model::{Automaton, Kind};
    use crate::scan::ld::Element;
    use crate::synth::monolithic;

    /// The variables of the contacts of `e`, left to right.
    fn contacts(e: &Element, out: &mut Vec<String>) {
        match e {
            Element::Contact { variable, .. } => out.push(variable.clone()),
            Element::Series(es) | Element::Parallel(es) => es.iter().for_each(|x| contacts(x, out)),
        }
    }

    // See: issue 37 (the state-based program over a module with variables: the guard, not the
    // supervisor's state, decides an event where the E/D analysis says it alone does).
    #[test]
    fn the_buffers_state_based_rungs_test_its_count_not_the_supervisors_state() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/efa/buffer-state.toml");
        let manifest = Manifest::load(&file).unwrap();
        let efa = manifest.read_efa().unwrap();
        let unfolded = unfold(&file, &efa[0]).unwrap();
        let of = |kind| unfolded.iter().filter(|a| a.kind == kind).cloned().collect::<Vec<Automaton>>();
        let sup = monolithic(&of(Kind::Plant), &of(Kind::Spec), &Config::default()).unwrap();
        let set = PackSet::new(of(Kind::Plant), vec![sup.automaton]).unwrap();
        let signals = || manifest.state.as_ref().unwrap().check().unwrap();
        let opts = PlcOptions { name: "efa_buffer_state".into(), efa, ..PlcOptions::default() };
        let program = |opts: &PlcOptions| {
            generate(&set, signals(), opts, StateOptions::default(), &Provenance::default(), None, &file)
        };
        let out = program(&opts).unwrap();
        // No supervisor's state is kept: the count is the only memory.
        assert!(out.memory.layout.kept.is_empty() && out.memory.states.is_empty());
        assert_eq!(out.memory.variables, ["n_2"]);
        let text = &out.files[0].1;
        for (event, machine, guard) in [("start1", "m1", "n_2 <= 1"), ("start2", "m2", "n_2 >= 1")] {
            let rung = out.rungs.iter().find(|r| r.event == event).unwrap();
            let mut seen = Vec::new();
            contacts(&rung.rung.condition, &mut seen);
            // The machine's idle state (its signals) and the guard: nothing of the supervisor.
            let want = [format!("{machine}_done"), format!("{machine}_run"), format!("g_{event}")];
            assert_eq!(seen, want, "{event}");
            assert!(text.contains(&format!("g_{event} := {guard};")), "{event}: {text}");
        }
        // The stops' guards are TRUE: their rungs have no guard contact.
        let stop = out.rungs.iter().find(|r| r.event == "stop1").unwrap();
        assert_eq!(stop.rung.condition.contacts(), 2);
        assert!(validate(&out, &out.rungs).unwrap() > 0);
        let guards: Vec<(&str, Option<&str>)> =
            out.report.guards.guards.iter().map(|g| (g.event.as_str(), g.guard.as_deref())).collect();
        assert_eq!(
            guards,
            [
                ("start1", Some("n <= 1")),
                ("stop1", Some("TRUE")),
                ("start2", Some("n >= 1")),
                ("stop2", Some("TRUE"))
            ]
        );
        // Without a choice policy the rungs are ladder that call the variables' updates in ST (the
        // XML's body is then the ST one: an LD body of the rungs alone would leave the updates out).
        let fire_all = || Signals { choice: None, ..signals() };
        let all =
            generate(&set, fire_all(), &opts, StateOptions::default(), &Provenance::default(), None, &file);
        let graphic = &all.unwrap().sources[0].program.pous[0].1;
        assert!(matches!(graphic, crate::scan::Graphic::LadderCallingSt(_)), "{graphic:?}");
        // Without the module's variables the plant state does not decide start1 and start2: the
        // supervisor's memory would have to be kept.
        let plain = PlcOptions { efa: Vec::new(), ..opts };
        let err = program(&plain).unwrap_err().to_string();
        assert!(err.contains("start1") && err.contains("start2"), "{err}");
    }
}
