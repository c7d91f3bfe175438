//! The PLC back end: IEC 61131-3 Structured Text and PLCopen TC6 XML 2.01 from the same supervisor set
//! the firmware runs, with the scan-cycle problems solved in the code and reported.
//!
//! # Overview
//!
//! * [`spec`] — the manifest's `[plc]` section: input variables and their edges, output variables and
//!   their actions, the choice policy, the task's cycle.
//! * [`io`] — that map checked against the set's events.
//! * [`names`] — IEC identifiers for the models' names.
//! * [`avalanche`] — the avalanche events of each automaton and how each is eliminated (statement order
//!   or an AEEM memory bit).
//! * [`choice`] — the choice policies in ST.
//! * [`st`] — the ST syntax tree, its printer, and the measures of it the report gives (statements per
//!   section, a static bound on the statements a scan executes).
//! * [`program`] — the builder: a `FUNCTION_BLOCK` with plants, supervisors and interface, and a
//!   `PROGRAM` instantiating it (the scan is described there).
//! * [`strict`] — the IEC 61131-3 Ed. 3 rules every program is checked against before it is printed
//!   (keywords, located variables, no implicit conversion), so a strict compiler takes it.
//! * [`hybrid`] — an automation net as the plant, coupled to its reduced supervisor by inhibitor arcs, in
//!   Ladder Diagram and ST (Uzam & Gelen 2013).
//! * [`net_program`] — a sequence net ([`crate::net`]) as token-passing ST and as an SFC.
//! * [`xml`] — the same POUs, and the configuration, as PLCopen XML with ST bodies.
//! * [`report`] — what the program costs and how it solves each problem.
//! * [`ld`] — Ladder Diagram rungs, their PLCopen `<LD>` body and instruction-list cost.
//! * [`state_based`] — the state-based program (state feedback control, `--encoding state`): no state
//!   tracked, one rung per controllable event over the plant's signals.
//!
//! Two encodings: `int` — one integer state per automaton and a `CASE` per event, where no event can
//! chain (a `CASE` takes one branch); `bits` — one `BOOL` per state and one statement per transition,
//! the ladder form, where avalanche events need elimination. Output is deterministic: the same set and
//! options give the same bytes (the XML's creation time is fixed).

pub mod avalanche;
pub mod choice;
pub mod hybrid;
pub mod io;
pub mod ld;
pub mod names;
pub mod net_program;
pub mod program;
pub mod report;
pub mod st;
pub mod state_based;
pub mod strict;
pub mod xml;

use std::fmt::Write as _;

use crate::config::{ChoicePolicy, OnFault, RuntimeConfig};
use crate::pack::PackSet;
use crate::provenance::Provenance;

pub use crate::config::{PlcSpec, ScanPolicy};
pub use avalanche::{Avalanche, Method};
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

/// Everything besides the set that fixes the program.
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
    /// it ([`net_program`]). Off, the block chooses among every allowed event.
    pub requests: bool,
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
        }
    }
}

impl PlcOptions {
    /// The options of a set named `name` with the run-time configuration `runtime` (guard, seed, fault
    /// reaction) and the `[plc]` section `spec`; the policy is `policy` when given, else `[plc] policy`,
    /// else `runtime`'s when it has a scan-cycle form. The encoding and avalanche option stay at their
    /// defaults.
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
            (None, None) => return Err(PlcError::Policy(runtime.policy)),
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
}

/// Why a program cannot be written for a set.
#[derive(Debug, thiserror::Error)]
pub enum PlcError {
    /// The set has no events.
    #[error("the set has no events: nothing to program")]
    Empty,
    /// `[plc]` names an event the set does not have.
    #[error("plc: event '{event}' is not an event of the set{hint}")]
    UnknownEvent {
        /// The name.
        event: String,
        /// ` (did you mean 'x'?)` naming the set's events closest in spelling, or empty.
        hint: String,
    },
    /// Controllable events `[plc]` maps to no output and does not list as internal: the program would
    /// never drive them. Every such event, each with its ` (did you mean …?)` tail (empty when no output
    /// variable is close).
    #[error("plc: {}; map each in [[plc.outputs]] or list it in [plc] internal", unmapped(.0))]
    Unmapped(Vec<(String, String)>),
    /// An input for a controllable event, or an output for an uncontrollable one.
    #[error("plc: event '{event}' is {what}")]
    WrongKind {
        /// Event.
        event: String,
        /// What is wrong.
        what: &'static str,
    },
    /// A variable name that is no IEC identifier (or a reserved word).
    #[error("plc: '{0}' is not an IEC 61131-3 identifier (letters, digits, single underscores, at most 63; not a keyword such as EN, SR, TON or TIME in any case: see docs/plc-strict.md)")]
    Identifier(String),
    /// A name used twice.
    #[error("plc: '{0}' is mapped twice or clashes with a generated name")]
    Duplicate(String),
    /// A bad value in `[plc]`.
    #[error("plc: {0}")]
    Value(String),
    /// A controllable event no plant has: nothing can generate it.
    #[error("controllable event '{0}' belongs to no plant, so the product system cannot generate it")]
    Unowned(String),
    /// `--avalanche order` and a cycle.
    #[error("--avalanche order: event '{event}' of {automaton} has a cycle among its transitions{}; use auto or aeem", if *conflict { " together with the events ordered before it" } else { "" })]
    Unorderable {
        /// Automaton.
        automaton: String,
        /// Event.
        event: String,
        /// The cycle is in the union with other ordered events.
        conflict: bool,
    },
    /// The manifest's policy has no scan-cycle form and `[plc]` names none.
    #[error("[runtime] policy {0} has no scan-cycle form; set [plc] policy (first, global-queue, local-queue or random)")]
    Policy(ChoicePolicy),
    /// The program breaks a rule of the standard: a bug of the writer, never of the input.
    #[error("internal error, please report: the program is not strict IEC 61131-3: {0}")]
    Strict(#[from] strict::Violation),
    /// The closed loop for the simultaneity check could not be built.
    #[error("simultaneity check: {0}")]
    Synth(#[from] crate::synth::SynthError),
}

/// The text of [`PlcError::Unmapped`].
fn unmapped(events: &[(String, String)]) -> String {
    let list: Vec<String> = events.iter().map(|(e, hint)| format!("'{e}'{hint}")).collect();
    let verb = if events.len() == 1 { "drives" } else { "drive" };
    format!(
        "controllable event{} {} {verb} no output",
        if events.len() == 1 { "" } else { "s" },
        list.join(", ")
    )
}

/// The files of one program and its report.
#[derive(Clone, Debug)]
pub struct Output {
    /// `(file name, contents)`: `<name>.st`, `<name>_config.st`, `<name>.xml`.
    pub files: Vec<(String, String)>,
    /// The report.
    pub report: Report,
    /// The program's syntax trees.
    pub program: Program,
}

/// Writes the program for `set` with `opts`; `provenance` goes into every file's header.
pub fn generate(set: &PackSet, opts: &PlcOptions, provenance: &Provenance) -> Result<Output, PlcError> {
    assemble(set, opts, provenance, None)
}

/// Writes the interlocks' program for `set` with the sequence `net` beside it in one PLC program
/// ([`net_program::beside`]): the sequence requests commands, the supervisors allow them. `net` must be
/// bound to `set`'s event table. The same three files as [`generate`]: the ST file holds the interlocks'
/// block, the sequence's token-passing block and the one `PROGRAM`; the XML the same POUs with the
/// sequence as an SFC.
pub fn generate_with_sequence(
    set: &PackSet,
    opts: &PlcOptions,
    provenance: &Provenance,
    net: &crate::net::Interpretation,
) -> Result<Output, PlcError> {
    assemble(set, &PlcOptions { requests: true, ..opts.clone() }, provenance, Some(net))
}

/// [`generate`], with the sequence `net` beside the interlocks when given.
fn assemble(
    set: &PackSet,
    opts: &PlcOptions,
    provenance: &Provenance,
    net: Option<&crate::net::Interpretation>,
) -> Result<Output, PlcError> {
    let mut program = program::build(set, opts)?;
    let base = names::stem(&opts.name);
    let sequence = net.map(|n| net_program::beside(n, &program, &base)).transpose()?;
    let mut header = header(set, opts, provenance);
    let (st_pous, xml_bodies) = match &sequence {
        Some(s) => {
            program.main = s.main.clone();
            header.push(format!(
                "Sequence: a net of {} places and {} transitions in {} (token passing in ST, an SFC in the XML), requesting the interlocks' commands.",
                net.map_or(0, |n| n.net.places.len()),
                net.map_or(0, |n| n.net.transitions.len()),
                s.block.name
            ));
            (
                vec![&program.fb, &s.block, &program.main],
                vec![
                    (&program.fb, Vec::new()),
                    (&s.sfc.0, vec![s.sfc.1.clone()]),
                    (&program.main, Vec::new()),
                ],
            )
        }
        None => {
            (vec![&program.fb, &program.main], vec![(&program.fb, Vec::new()), (&program.main, Vec::new())])
        }
    };
    strict::check(program.events_type.as_slice(), &st_pous)?;
    if let Some(s) = &sequence {
        strict::check(program.events_type.as_slice(), &[&program.fb, &s.sfc.0, &program.main])?;
    }
    let mut st = comment(&header);
    if let Some((name, members)) = &program.events_type {
        let _ = write!(st, "\n{}", st::struct_type(name, members));
    }
    for pou in &st_pous {
        let _ = write!(st, "\n{}", pou.text());
    }
    let config = format!("{}\n{}", comment(&header), xml::configuration_text(&base, opts.cycle_ms));
    let pous: Vec<(&st::Pou, &[String])> = xml_bodies.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    let xml = xml::document(program.events_type.as_ref(), &pous, &base, opts.cycle_ms, &header);
    let files =
        vec![(format!("{base}.st"), st), (format!("{base}_config.st"), config), (format!("{base}.xml"), xml)];
    let report = Report::new(set, opts, &program, &files)?;
    Ok(Output { files, report, program })
}

/// The header lines (without comment delimiters).
fn header(set: &PackSet, opts: &PlcOptions, provenance: &Provenance) -> Vec<String> {
    let plants = set.members().iter().filter(|m| m.role == crate::pack::Role::Plant).count();
    let mut lines = vec![
        format!("@generated by codegen {} (`codegen plc`): do not edit.", env!("CARGO_PKG_VERSION")),
        String::new(),
        format!(
            "Set '{}': {} plants, {} supervisors, {} events.",
            opts.name,
            plants,
            set.members().len() - plants,
            set.events().len()
        ),
    ];
    lines.extend(provenance.lines());
    lines.push(format!(
        "Options: encoding={} avalanche={} policy={} guard={} on_fault={} seed={} cycle_ms={}",
        opts.encoding.name(),
        opts.avalanche.name(),
        opts.policy.name(),
        opts.guard,
        opts.on_fault,
        opts.seed,
        opts.cycle_ms
    ));
    lines
}

/// `lines` as one ST comment (any comment delimiter inside them broken up).
pub(crate) fn comment(lines: &[String]) -> String {
    let mut out = String::from("(*\n");
    for l in lines {
        let l = st::safe_comment(l);
        let _ = writeln!(out, "{}", if l.is_empty() { l } else { format!("   {l}") });
    }
    out.push_str("*)\n");
    out
}
