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
}
