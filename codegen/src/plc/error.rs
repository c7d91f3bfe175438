//! The PLC wing's one error type: why a program of any form cannot be written.

use std::path::PathBuf;

use crate::feedback::FeedbackError;
use crate::net::NetError;
use crate::scan::strict::Violation;
use crate::synth::SynthError;

/// Why a PLC program cannot be written. The kinds of the event-based form (the `[plc]` I/O map, the
/// avalanche option), of the sequence beside it, of the state-based form (its feedback, naming the
/// manifest) and of the hybrid controller (its net and supervisor, naming their files), and the one a
/// writer's bug would give.
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
    /// A signal of the sequence net that the interlocks' program has no variable for.
    #[error("net: signal '{signal}' has no variable in [plc]; it is {wanted}")]
    Signal {
        /// The signal.
        signal: String,
        /// What it is and where to map it.
        wanted: &'static str,
    },
    /// The net of a sequence or of a hybrid controller: unsafe, unbounded, or its interpretation does
    /// not fit.
    #[error(transparent)]
    Net(#[from] NetError),
    /// The state feedback of a state-based program, in the manifest `file` (or the set's name).
    #[error("{}: {source}", file.display())]
    Feedback {
        /// The manifest, or the set's name without one.
        file: PathBuf,
        /// Why (boxed: the other kinds are small).
        source: Box<FeedbackError>,
    },
    /// A hybrid manifest without its `[net]` section.
    #[error("{}: a hybrid controller needs the sections [net] (the plant's automation net) and [hybrid] (its transitions' events)", file.display())]
    Sections {
        /// The manifest.
        file: PathBuf,
    },
    /// `[[timers]]` with a form whose program has no timers: only the event-based program runs them (a
    /// `TON` per timer, its timeout an event the program takes); the state-based program decides on
    /// signal vectors and the hybrid controller times its plant net's own transitions, and neither has a
    /// timeout event to raise.
    #[error(
        "{}: [[timers]] run in the event-based program only (a TON per timer); the {form} has no timeout \
         event to raise, so its program would drop them: write the event-based program (`codegen plc` \
         without --encoding state), or leave [[timers]] out",
        file.display()
    )]
    Timers {
        /// The manifest.
        file: PathBuf,
        /// The form, as a user names it ("state-based program", "hybrid controller").
        form: &'static str,
    },
    /// No supervisor exists for a hybrid controller: the specifications forbid what the net cannot be
    /// kept from.
    #[error("{}: no supervisor exists: the specifications cannot be enforced on the net (supC is empty)", file.display())]
    NoSupervisor {
        /// The manifest.
        file: PathBuf,
    },
    /// A hybrid manifest gives no specification and no supervisor, both, or more than one supervisor.
    #[error("{}: a hybrid controller takes either `specs` (its supervisor is synthesised) or one ready supervisor in `supervisors`; {specs} specification file(s) and {supervisors} supervisor file(s) given", file.display())]
    Source {
        /// The manifest.
        file: PathBuf,
        /// How many specification files it lists.
        specs: usize,
        /// How many supervisor files it lists.
        supervisors: usize,
    },
    /// A hybrid controller's ready supervisor cannot control the net: an event no transition generates,
    /// an uncontrollable event it refuses, or a state of the closed loop from which no marked state is
    /// reachable.
    #[error("{}: supervisor '{name}': {problem}", file.display())]
    Given {
        /// The supervisor's file.
        file: PathBuf,
        /// The supervisor.
        name: String,
        /// What is wrong, with a trace where there is one.
        problem: String,
    },
    /// A hybrid controller's coupled net does not run its supervisor's closed loop: the writer's bug.
    #[error("internal error, please report: the coupled net of {supervisor} differs from plant ‖ supervisor after {trace}")]
    Coupling {
        /// The supervisor.
        supervisor: String,
        /// A shortest trace on which they differ.
        trace: String,
    },
    /// The program breaks a rule of the standard: a bug of the writer, never of the input.
    #[error("internal error, please report: the program is not strict IEC 61131-3: {0}")]
    Strict(#[from] Violation),
    /// The closed loop of the simultaneity check could not be built.
    #[error("simultaneity check: {0}")]
    Simultaneity(SynthError),
    /// A hybrid controller's synthesis, reduction or control data.
    #[error(transparent)]
    Synth(#[from] SynthError),
}

impl PlcError {
    /// Whether the error is a finding about the set rather than bad input: the supervisors' memory
    /// decides the state feedback somewhere and memory is not allowed (`codegen plc` exits 1).
    pub fn is_finding(&self) -> bool {
        matches!(self, PlcError::Feedback { source, .. } if matches!(**source, FeedbackError::Memory(_)))
    }
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
