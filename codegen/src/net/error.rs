//! Why a net could not be read, bound to its interpretation or explored.

use std::path::PathBuf;

use crate::formats::ParseError;
use crate::model::ModelError;
use crate::synth::SynthError;

/// A net, its interpretation or its IO-reachability graph went wrong; every variant names the file (and
/// the line where there is one).
#[derive(Debug, thiserror::Error)]
pub enum NetError {
    /// The PNML file is malformed (the reader's error names it and the line).
    #[error(transparent)]
    Pnml(#[from] ParseError),
    /// The manifest's `[net]` section names something that does not exist or does not fit.
    #[error("{}:{line}: {message}", file.display())]
    Spec {
        /// The manifest file.
        file: PathBuf,
        /// The line of the offending key or value.
        line: usize,
        /// What is wrong, naming it.
        message: String,
    },
    /// The automata of the admissible behaviour do not compose.
    #[error("admissible behaviour: {0}")]
    Model(#[from] ModelError),
    /// Building the admissible behaviour stopped (state or memory limit).
    #[error("admissible behaviour: {0}")]
    Synth(#[from] SynthError),
    /// The graph grew past `--state-limit`.
    #[error("IO-reachability graph: more than {limit} nodes (raise --state-limit)")]
    StateLimit {
        /// The limit.
        limit: usize,
    },
    /// The process grew past `--memory-limit`.
    #[error("IO-reachability graph: {nodes} nodes use {} of memory, past the limit of {} (raise --memory-limit)",
        crate::synth::memory::human(*resident), crate::synth::memory::human(*limit))]
    MemoryLimit {
        /// Nodes built when it stopped.
        nodes: usize,
        /// Resident bytes then.
        resident: u64,
        /// The limit.
        limit: u64,
    },
    /// A place would hold more tokens than a counter can.
    #[error("place '{place}' overflows: the net is unbounded")]
    Unbounded {
        /// The place's id.
        place: String,
    },
    /// An event labels two transitions enabled together that lead to different markings: the net's
    /// language is no deterministic automaton.
    #[error("event '{event}' labels transitions '{first}' and '{second}', enabled together at marking {marking} with different results")]
    Nondeterministic {
        /// The event.
        event: String,
        /// The first transition.
        first: String,
        /// The second transition.
        second: String,
        /// The marking, as its state name.
        marking: String,
    },
    /// A reachable marking puts more than one token in a place: a program's one-bit place cannot hold it.
    #[error("place '{place}' holds {tokens} tokens {}: a PLC program keeps a place in one BOOL, so only safe nets are written",
        if sequence.is_empty() { "in the initial marking".to_owned() } else { format!("after the firing sequence {} (conditions and delays aside)", sequence.join(" ")) })]
    Unsafe {
        /// The place's id.
        place: String,
        /// Its tokens there.
        tokens: u32,
        /// A shortest firing sequence from the initial marking to there, by transition id (empty: the
        /// initial marking itself).
        sequence: Vec<String>,
    },
    /// An arc of weight above one, which a one-bit place cannot follow.
    #[error("transition '{transition}' has an arc of weight {weight} with place '{place}': a PLC program keeps a place in one BOOL, so only safe nets are written")]
    Weight {
        /// The transition's id.
        transition: String,
        /// The place's id.
        place: String,
        /// The arc's weight.
        weight: u32,
    },
    /// The safe-net check explored its limit of markings.
    #[error("more than {limit} reachable markings: the safe-net check stops there")]
    Markings {
        /// The limit.
        limit: usize,
    },
}
