//! The PLC back end: IEC 61131-3 programs from the same supervisor set the firmware runs, with the
//! scan-cycle problems solved in the code and reported. Four forms, one program IR ([`crate::scan`]):
//!
//! * **event-based** ([`generate`], `--encoding int|bits`) — a `FUNCTION_BLOCK` with plants,
//!   supervisors and interface that tracks every automaton's state from the events, and a `PROGRAM`
//!   instantiating it: [`program`] builds it, over the I/O map of [`io`], the avalanche plan of
//!   [`avalanche`] and the choice policies of [`choice`]; [`report`] measures it;
//! * **with a sequence** ([`generate_with_sequence`]) — a sequence net beside those interlocks in one
//!   program ([`sequence`]);
//! * **state-based** ([`state_based`], `--encoding state`) — no state tracked, one rung per
//!   controllable event over the plant's signals, from the state feedback of [`crate::feedback`];
//! * **hybrid** ([`hybrid`]) — an automation net as the plant, coupled to its reduced supervisor by
//!   inhibitor arcs, in Ladder Diagram and ST (Uzam & Gelen 2013).
//!
//! The sequence and the hybrid controller are both written by the one lowering of a net,
//! [`token_passing`]. Every form's files come from [`crate::scan::files`]; every error is a
//! [`PlcError`]. [`Form`] names a form with its options and [`Written`] is what any form writes: the
//! project's single entry, `Project::plc`, takes the one and returns the other. [`closed_loop`] runs the
//! event-based program's text under the interpreter against the virtual plant (`codegen run --target
//! plc`).
//!
//! Event-based encodings: `int` — one integer state per automaton and a `CASE` per event, where no
//! event can chain (a `CASE` takes one branch); `bits` — one `BOOL` per state and one statement per
//! transition, the ladder form, where avalanche events need elimination; with `--avalanche aeem` (the
//! seed documents' method) the XML carries those rungs as Ladder Diagram ([`Program::rungs`]). Output
//! is deterministic: the same set and options give the same bytes (the XML's creation time is fixed).

pub mod avalanche;
pub mod choice;
pub mod closed_loop;
mod error;
pub mod guards;
pub mod hybrid;
pub mod io;
pub mod net_drive;
pub mod program;
pub mod report;
pub mod sequence;
pub mod state_based;
pub mod token_passing;

use crate::config::{OnFault, RuntimeConfig};
use crate::net::Interpretation;
use crate::pack::PackSet;
use crate::provenance::Provenance;
use crate::scan::files::{File, Header, Source};
use crate::scan::names::stem;
use crate::scan::{Graphic, Program as ScanProgram};

pub use crate::config::{PlcSpec, ScanPolicy};
pub use avalanche::{Avalanche, Method};
pub use error::PlcError;
pub use program::Program;
pub use report::Report;

/// The state encoding (`--encoding`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Encoding {
    /// One integer per automaton, a `CASE` per event.
    #[default]
    Int,
    /// One `BOOL` per state, one statement per transition (ladder form).
    Bits,
}

impl Encoding {
    /// The option's name.
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Int => "int",
            Encoding::Bits => "bits",
        }
    }
}

/// A PLC program's form and the options that shape it: what `codegen plc` is asked for.
#[derive(Clone)]
pub enum Form {
    /// The event-based program (with the manifest's sequence net beside it when it has one).
    Event {
        /// The state encoding.
        encoding: Encoding,
        /// Avalanche elimination (bits encoding).
        avalanche: Avalanche,
        /// The choice policy, else the manifest's.
        policy: Option<ScanPolicy>,
    },
    /// The state-based program.
    State {
        /// Memory, don't-cares and one command per scan.
        options: state_based::StateOptions,
        /// Where f comes from.
        engine: state_based::Engine,
    },
    /// The hybrid controller of a manifest with a `[hybrid]` section.
    Hybrid,
}

/// What a form writes: its files and its report, with what the form built on the way.
#[derive(Clone, Debug)]
pub enum Written {
    /// An event-based program.
    Event(Output),
    /// A state-based program from the explicit closed loop.
    State(state_based::Output),
    /// A state-based program from guards off the symbolic engine's BDDs.
    Symbolic(state_based::SymbolicOutput),
    /// The two hybrid controllers.
    Hybrid(hybrid::Output),
}

impl Written {
    /// The event-based program, if that is what was written.
    pub fn into_event(self) -> Option<Output> {
        if let Written::Event(o) = self {
            Some(o)
        } else {
            None
        }
    }

    /// The state-based program from the explicit closed loop, if that is what was written.
    pub fn into_state(self) -> Option<state_based::Output> {
        if let Written::State(o) = self {
            Some(o)
        } else {
            None
        }
    }

    /// The state-based program from guards, if that is what was written.
    pub fn into_symbolic(self) -> Option<state_based::SymbolicOutput> {
        if let Written::Symbolic(o) = self {
            Some(o)
        } else {
            None
        }
    }

    /// The hybrid controllers, if that is what was written.
    pub fn into_hybrid(self) -> Option<hybrid::Output> {
        if let Written::Hybrid(o) = self {
            Some(o)
        } else {
            None
        }
    }

    /// Whether the report holds a finding (a state-based scan estimate longer than the task's cycle):
    /// the files are written, and the command exits 1 as a check that failed.
    pub fn has_finding(&self) -> bool {
        matches!(self, Written::State(o) if o.report.scan_too_long())
    }

    /// The files written: `(file name, contents)`.
    pub fn files(&self) -> &[File] {
        match self {
            Written::Event(o) => &o.files,
            Written::State(o) => &o.files,
            Written::Symbolic(o) => &o.files,
            Written::Hybrid(o) => &o.files,
        }
    }

    /// The programs the files are written from, with their headers, in the files' order: what a
    /// vendor's printer ([`crate::scan::vendor`]) prints.
    pub fn sources(&self) -> &[Source] {
        match self {
            Written::Event(o) => &o.sources,
            Written::State(o) => &o.sources,
            Written::Symbolic(o) => &o.sources,
            Written::Hybrid(o) => &o.sources,
        }
    }

    /// The report as text, one fact per line.
    pub fn text(&self) -> String {
        match self {
            Written::Event(o) => o.report.text(),
            Written::State(o) => o.report.text(),
            Written::Symbolic(o) => o.report.text(),
            Written::Hybrid(o) => o.report.text(),
        }
    }

    /// The report as JSON (schema 1) for the set `name`: the event-based report itself, or the form's
    /// report under its key (`sfbc`, `hybrid`) beside the encoding and the files.
    pub fn json(&self, name: &str) -> serde_json::Value {
        let files: Vec<&str> = self.files().iter().map(|(n, _)| n.as_str()).collect();
        match self {
            Written::Event(o) => serde_json::json!(o.report),
            Written::State(o) => serde_json::json!({
                "schema": 1,
                "name": name,
                "encoding": "state",
                "files": files,
                "sfbc": o.report,
            }),
            Written::Symbolic(o) => {
                let mut v = serde_json::json!({
                    "schema": 1,
                    "name": name,
                    "encoding": "state",
                    "engine": "symbolic",
                    "files": files,
                });
                if let (Some(map), serde_json::Value::Object(report)) =
                    (v.as_object_mut(), serde_json::json!(o.report))
                {
                    map.extend(report);
                }
                v
            }
            Written::Hybrid(o) => serde_json::json!({
                "schema": 1,
                "name": name,
                "encoding": "hybrid",
                "files": files,
                "hybrid": o.report,
            }),
        }
    }
}

/// Everything besides the set that fixes an event-based program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlcOptions {
    /// Name of the set (POU names derive from it).
    pub name: String,
    /// State encoding.
    pub encoding: Encoding,
    /// Avalanche elimination (bits encoding).
    pub avalanche: Avalanche,
    /// Choice policy.
    pub policy: ScanPolicy,
    /// Inexact-synchronisation guard's initial value.
    pub guard: bool,
    /// Seed of the random policy.
    pub seed: u64,
    /// Reaction to a fault.
    pub on_fault: OnFault,
    /// The task's interval in milliseconds.
    pub cycle_ms: u32,
    /// The I/O map.
    pub spec: PlcSpec,
    /// Whether every controllable event must drive an output or be listed in `[plc] internal` (set when
    /// the manifest's `[plc]` gives an I/O map — any input, output or internal entry; a program without
    /// one drives no outputs by design).
    pub require_outputs: bool,
    /// Whether a controllable event also needs its caller's request (a `req_<event>` input per
    /// controllable event): a sequence beside the interlocks asks for a command, the supervisors allow
    /// it ([`sequence`]). Off, the block chooses among every allowed event.
    pub requests: bool,
    /// Timeouts (`[[timers]]`): one `TON` each, whose output raises the timeout event.
    pub timers: Vec<crate::manifest::TimerSpec>,
    /// The modules' variables, guards and actions (before unfolding): the program keeps each variable it
    /// can as an integer and writes the supervisors' enablement as guards over them where it can
    /// ([`guards`]).
    pub efa: Vec<crate::formats::efa::Efa>,
}

impl Default for PlcOptions {
    fn default() -> Self {
        PlcOptions {
            name: String::from("set"),
            encoding: Encoding::default(),
            avalanche: Avalanche::default(),
            policy: ScanPolicy::LocalQueue,
            guard: true,
            seed: 0,
            on_fault: OnFault::default(),
            cycle_ms: 10,
            spec: PlcSpec::default(),
            require_outputs: false,
            requests: false,
            timers: Vec::new(),
            efa: Vec::new(),
        }
    }
}

impl PlcOptions {
    /// The options of a set named `name` with the run-time configuration `runtime` (guard, seed, fault
    /// reaction) and the `[plc]` section `spec`; the policy is `policy` when given, else `[plc] policy`,
    /// else `runtime`'s when it has a scan-cycle form, else `random` (the program header names it).
    /// The encoding and avalanche option stay at their defaults.
    ///
    /// The runtime policies without a scan-cycle form are the random queues (the default among them):
    /// they draw, so that no interleaving of the plants is ruled out, and `random` is the scan-cycle
    /// policy that keeps that. A fixed rule in their place can keep a nonblocking closed loop out of its
    /// marked states for ever: the EFA buffer (`examples/efa/buffer.wmod`) under `local-queue` cycles
    /// through buffer levels 1 and 2 and never empties it with both machines idle (issue 36).
    pub fn new(
        name: &str,
        runtime: &RuntimeConfig,
        spec: Option<&PlcSpec>,
        policy: Option<ScanPolicy>,
    ) -> Result<PlcOptions, PlcError> {
        let require_outputs =
            spec.is_some_and(|s| !(s.inputs.is_empty() && s.outputs.is_empty() && s.internal.is_empty()));
        let spec = spec.cloned().unwrap_or_default();
        let policy = match (policy.or(spec.policy), ScanPolicy::of_runtime(runtime.policy)) {
            (Some(p), _) | (None, Some(p)) => p,
            (None, None) => ScanPolicy::Random,
        };
        Ok(PlcOptions {
            name: name.to_owned(),
            policy,
            guard: runtime.guard,
            seed: runtime.seed,
            on_fault: runtime.on_fault,
            cycle_ms: spec.cycle_ms.unwrap_or(10),
            spec,
            require_outputs,
            ..PlcOptions::default()
        })
    }

    /// The command-line words of these options (`--encoding int --avalanche auto --policy first`).
    pub fn words(&self) -> Vec<String> {
        vec![
            format!("--encoding {}", self.encoding.name()),
            format!("--avalanche {}", self.avalanche.name()),
            format!("--policy {}", self.policy.name()),
        ]
    }
}

/// The files of one event-based program, its report and its syntax trees.
#[derive(Clone, Debug)]
pub struct Output {
    /// `(file name, contents)`: `<name>.st`, `<name>_config.st`, `<name>.xml`.
    pub files: Vec<File>,
    /// The report.
    pub report: Report,
    /// The program's syntax trees.
    pub program: Program,
    /// The program the files are written from, for a vendor's printer.
    pub sources: Vec<Source>,
}

/// Writes the program for `set` with `opts`; `provenance` goes into every file's header.
pub fn generate(set: &PackSet, opts: &PlcOptions, provenance: &Provenance) -> Result<Output, PlcError> {
    assemble(set, opts, provenance, None)
}

/// Writes the interlocks' program for `set` with the sequence `net` beside it in one PLC program
/// ([`sequence::beside`]): the sequence requests commands, the supervisors allow them. `net` must be
/// bound to `set`'s event table. The same three files as [`generate`]: the ST file holds the interlocks'
/// block, the sequence's token-passing block and the one `PROGRAM`; the XML the same POUs with the
/// sequence as an SFC.
pub fn generate_with_sequence(
    set: &PackSet,
    opts: &PlcOptions,
    provenance: &Provenance,
    net: &Interpretation,
) -> Result<Output, PlcError> {
    assemble(set, &PlcOptions { requests: true, ..opts.clone() }, provenance, Some(net))
}

/// The event-based program's size for `set` with `opts`, without writing it: its top-level statements
/// (function block and program) and the most statements one scan executes — the figures the
/// state-based report compares against.
pub fn event_figures(set: &PackSet, opts: &PlcOptions) -> Result<(usize, u64), PlcError> {
    let program = program::build(set, opts)?;
    let statements = [&program.fb, &program.main].iter().flat_map(|p| p.statements()).map(|(_, n)| n).sum();
    Ok((statements, program.fb.bound() + program.main.bound()))
}

/// [`generate`], with the sequence `net` beside the interlocks when given.
fn assemble(
    set: &PackSet,
    opts: &PlcOptions,
    provenance: &Provenance,
    net: Option<&Interpretation>,
) -> Result<Output, PlcError> {
    let mut program = program::build(set, opts)?;
    let base = stem(&opts.name);
    let mut header = header(set, opts, provenance);
    // The bits encoding with AEEM carries the supervisors' rungs as an `<LD>` body beside the ST.
    let ladder =
        if program.rungs.is_empty() { Graphic::Text } else { Graphic::Ladder(program.rungs.clone()) };
    let mut pous = vec![(program.fb.clone(), ladder)];
    if let Some(net) = net {
        let s = sequence::beside(net, &program, &base)?;
        program.main = s.main;
        header.notes.push(format!(
            "Sequence: a net of {} places and {} transitions in {} (token passing in ST, an SFC in the XML), requesting the interlocks' commands.",
            net.net.places.len(),
            net.net.transitions.len(),
            s.block.name
        ));
        pous.push((s.block, Graphic::Chart(s.chart)));
    }
    pous.push((program.main.clone(), Graphic::Text));
    let scan = ScanProgram {
        base,
        types: program.events_type.iter().cloned().collect(),
        pous,
        cycle_ms: opts.cycle_ms,
    };
    let source = Source { program: scan, header };
    let files = source.files()?;
    let report = Report::new(set, opts, &program, &files)?;
    Ok(Output { files, report, program, sources: vec![source] })
}

/// The set's line of a header: its plants, supervisors and events.
pub fn about(set: &PackSet, name: &str) -> String {
    let plants = set.members().iter().filter(|m| m.role == crate::pack::Role::Plant).count();
    format!(
        "Set '{name}': {plants} plants, {} supervisors, {} events.",
        set.members().len() - plants,
        set.events().len()
    )
}

/// The event-based program's header.
fn header(set: &PackSet, opts: &PlcOptions, provenance: &Provenance) -> Header {
    Header {
        about: vec![about(set, &opts.name)],
        provenance: provenance.clone(),
        options: vec![
            ("encoding", opts.encoding.name().to_owned()),
            ("avalanche", opts.avalanche.name().to_owned()),
            ("policy", opts.policy.name().to_owned()),
            ("guard", opts.guard.to_string()),
            ("on_fault", opts.on_fault.to_string()),
            ("seed", opts.seed.to_string()),
            ("cycle_ms", opts.cycle_ms.to_string()),
        ],
        notes: Vec::new(),
    }
}
