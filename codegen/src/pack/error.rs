//! What can stop a supervisor set from being packed, or a packed table from being read back.

use firmware::build::{BuildError, ReadError};

use crate::model::ModelError;

/// A set that cannot be packed in the requested layout.
///
/// Every limit names the layout, the automaton and the number that broke it, so the engineer knows
/// which layout to choose instead or which automaton to split ([`super::fit`] adds what would fit).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PackError {
    /// An automaton is invalid, or two automata disagree on an event's controllability.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An automaton has no state, so it has no initial state to start the runtime in.
    #[error("automaton '{automaton}' has no state")]
    Empty {
        /// Automaton name.
        automaton: String,
    },
    /// The set breaks a limit of a layout or of the runtime (the encoder's error, which names the number
    /// and the limit).
    #[error("layout {layout}: {source}")]
    Layout {
        /// Layout name.
        layout: &'static str,
        /// What the encoder refused.
        source: BuildError,
    },
}

/// Bytes that do not form a table of the layout they claim to be.
///
/// Decoders are the inverse of the encoders and the test oracle for them; they also check every
/// reference, so a corrupted table is reported, never followed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    /// The bytes end inside a record.
    #[error("{what}: truncated at byte {at}")]
    Truncated {
        /// Which table or automaton.
        what: String,
        /// Offset where more bytes were expected.
        at: usize,
    },
    /// A target or initial state that is not a state of the automaton.
    #[error("{what}: byte {at} refers to {target}, which is not a state")]
    BadState {
        /// Which table or automaton.
        what: String,
        /// Offset of the reference.
        at: usize,
        /// The offset or index found there.
        target: usize,
    },
    /// A record naming a mask id beyond the mask pool.
    #[error("{what}: the record at byte {at} names mask {id}, which is not in the pool")]
    BadMask {
        /// Which table or automaton.
        what: String,
        /// Offset of the record.
        at: usize,
        /// The mask id found there.
        id: usize,
    },
    /// An event id beyond the event table or outside the automaton's alphabet.
    #[error("{what}: byte {at} holds event {event}, which is not in the alphabet")]
    BadEvent {
        /// Which table or automaton.
        what: String,
        /// Offset of the event field.
        at: usize,
        /// The event id found there.
        event: usize,
    },
    /// A state lists one event twice.
    #[error("{what}: state {state} lists event {event} twice")]
    Nondeterministic {
        /// Which table or automaton.
        what: String,
        /// State index.
        state: usize,
        /// Event id.
        event: usize,
    },
    /// Side tables disagree with each other (lengths, counts).
    #[error("{what}: {detail}")]
    Inconsistent {
        /// Which table or automaton.
        what: String,
        /// What does not match.
        detail: String,
    },
}

impl From<ReadError> for DecodeError {
    fn from(e: ReadError) -> Self {
        match e {
            ReadError::Truncated { what, at } => DecodeError::Truncated { what, at },
            ReadError::BadMask { what, at, id } => DecodeError::BadMask { what, at, id },
            ReadError::Inconsistent { what, detail } => DecodeError::Inconsistent { what, detail },
        }
    }
}
