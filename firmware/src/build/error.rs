//! Why tables cannot be built for a set, or built tables cannot be read back.

use alloc::string::String;

/// A set a layout or the runtime cannot hold; every variant names the number that broke the limit and
/// the limit (the layout is the caller's to name: the encoder was asked for it).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BuildError {
    /// More events than an event id (one byte) numbers.
    #[error("the set has {events} events, more than the limit of {limit}")]
    TooManyEvents {
        /// Events in the set.
        events: usize,
        /// [`crate::table::MAX_EVENTS`].
        limit: usize,
    },
    /// An automaton with more states than 2-byte handles name.
    #[error("'{automaton}' has {states} states, more than the limit of {limit}")]
    TooManyStates {
        /// Automaton name.
        automaton: String,
        /// Its states.
        states: usize,
        /// [`super::MAX_STATES`].
        limit: usize,
    },
    /// A state with more transitions than a record's count byte holds (`memory-safe`, `offset`).
    #[error("state {state} of '{automaton}' has {transitions} outgoing transitions, more than the limit of {limit}")]
    TooManyTransitions {
        /// Automaton name.
        automaton: String,
        /// The state's index.
        state: usize,
        /// Its outgoing transitions.
        transitions: usize,
        /// 255.
        limit: usize,
    },
    /// More distinct out-masks than 2-byte mask ids number.
    #[error("the set has {masks} distinct out-masks, more than the limit of {limit}")]
    TooManyMasks {
        /// Distinct out-masks in the set.
        masks: usize,
        /// [`crate::table::MAX_MASKS`].
        limit: usize,
    },
    /// An automaton's records fit 2-byte handles at no scale.
    #[error("the {bytes} bytes of records of '{automaton}' fit 16-bit handles at no scale up to 255")]
    NoScale {
        /// Automaton name.
        automaton: String,
        /// Bytes of its records with 2-byte fields, without padding.
        bytes: usize,
    },
    /// The blocks put back to back, up to an automaton's, start records beyond 32-bit positions.
    #[error(
        "the blocks up to '{automaton}' take {bytes} bytes back to back, more than the limit of {limit}"
    )]
    BlocksTooLarge {
        /// The automaton whose records start beyond the limit.
        automaton: String,
        /// Bytes of the blocks up to and including its own.
        bytes: usize,
        /// Bytes 32-bit positions address.
        limit: usize,
    },
    /// More automata than the runtime's per-event holder mask has bits.
    #[error("the set has {count} automata, more than the runtime's limit of {limit}")]
    TooManyAutomata {
        /// Automata in the set.
        count: usize,
        /// [`crate::table::MAX_AUTOMATA`].
        limit: usize,
    },
    /// Host tables were asked for event bitsets of another word count than the set's.
    #[error("the set's event bitsets take {words} words, the runtime was built for {want}")]
    Words {
        /// Words of the set's bitsets.
        words: usize,
        /// Words the runtime's `W` says.
        want: usize,
    },
    /// Host tables were asked for positions of another width than the set's.
    #[error("the set's positions take {bytes} bytes, the runtime was built for {want}")]
    Positions {
        /// Bytes of the set's positions.
        bytes: usize,
        /// Bytes of the runtime's `Q`.
        want: usize,
    },
    /// The tables do not read back (only tables built by hand or altered after encoding).
    #[error(transparent)]
    Read(#[from] ReadError),
}

/// Bytes of a block that do not form the records of the `ranked` layout.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    /// The block ends inside a record.
    #[error("{what}: truncated at byte {at}")]
    Truncated {
        /// The automaton.
        what: String,
        /// Offset where more bytes were expected.
        at: usize,
    },
    /// A record naming a mask id beyond the pool.
    #[error("{what}: the record at byte {at} names mask {id}, which is not in the pool")]
    BadMask {
        /// The automaton.
        what: String,
        /// Offset of the record.
        at: usize,
        /// The mask id found there.
        id: usize,
    },
    /// Lengths, scale or padding that break the layout.
    #[error("{what}: {detail}")]
    Inconsistent {
        /// The automaton or table.
        what: String,
        /// What does not match.
        detail: String,
    },
}
