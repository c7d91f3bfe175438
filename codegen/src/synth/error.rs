//! Why a synthesis run stopped.

use crate::model::ModelError;

/// A synthesis run could not produce its result.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SynthError {
    /// An input automaton breaks a model invariant.
    #[error("automaton '{automaton}': {source}")]
    Model {
        /// Name of the automaton.
        automaton: String,
        /// The broken invariant.
        source: ModelError,
    },
    /// The input automata disagree (for example on an event's controllability).
    #[error(transparent)]
    Events(#[from] ModelError),
    /// A product or supervisor grew past [`Config::state_limit`](super::Config::state_limit).
    #[error("{what} exceeded the state limit of {limit}")]
    StateLimit {
        /// The automaton being built.
        what: String,
        /// The limit in force.
        limit: usize,
    },
    /// No supervisor exists for a specification (supC is empty): a verdict, not bad input.
    #[error(transparent)]
    NoSupervisor(Box<super::verify::NoSupervisor>),
    /// A product grew the process past [`Config::memory_limit`](super::Config::memory_limit).
    #[error(
        "{what}: {states} states so far took the process to {} resident, and {} more would pass the \
         memory limit of {} (--memory-limit)",
        super::memory::human(*resident),
        super::memory::human(*extra),
        super::memory::human(*limit)
    )]
    MemoryLimit {
        /// The automaton being built.
        what: String,
        /// Its states so far.
        states: usize,
        /// The process's resident size, bytes.
        resident: u64,
        /// The limit in force, bytes.
        limit: u64,
        /// The bytes the next step was about to take.
        extra: u64,
    },
    /// A symbolic fixed point grew the process past [`Config::memory_limit`](super::Config::memory_limit).
    #[error(
        "{what}: BDDs of {nodes} nodes took the process to {} resident, past the memory limit of {} \
         (--memory-limit)",
        super::memory::human(*resident),
        super::memory::human(*limit)
    )]
    BddMemoryLimit {
        /// The fixed point being computed.
        what: String,
        /// BDD nodes held at the time.
        nodes: usize,
        /// The process's resident size, bytes.
        resident: u64,
        /// The limit in force, bytes.
        limit: u64,
    },
    /// The automata need more state bits than the BDD library has variables.
    #[error("{what}: {bits} state bits need {} BDD variables, more than the {max} the BDD library holds", 2 * bits)]
    TooManyBits {
        /// The product to encode.
        what: String,
        /// State bits of all components together.
        bits: usize,
        /// Most BDD variables the library holds.
        max: usize,
    },
    /// A chosen supervisor set (`[runtime] supervisors`) does not give the plants the full set's closed
    /// loop, so it is not used.
    #[error(
        "supervisors = \"{choice}\": the closed loop of {what} differs from the full set's: {}",
        super::deploy::describe(difference)
    )]
    ClosedLoopDiffers {
        /// The choice.
        choice: String,
        /// The closed loop compared (the supervisor and its plants).
        what: String,
        /// A shortest string on which they differ.
        difference: Box<super::language::Difference>,
    },
}
