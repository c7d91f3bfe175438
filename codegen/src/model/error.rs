//! What can be wrong with an automaton or a set of automata, independent of the file it came from.

/// A model that breaks one of the invariants every later stage relies on.
///
/// Readers attach the file and the line or element to these; synthesis and packing can trust any
/// automaton that passed [`Automaton::validate`](super::Automaton::validate).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ModelError {
    /// Two states of one automaton share a name.
    #[error("duplicate state name '{0}'")]
    DuplicateState(String),
    /// Two events of one alphabet share a name.
    #[error("duplicate event name '{0}'")]
    DuplicateEvent(String),
    /// A transition or marking refers to a state that does not exist.
    #[error("unknown state '{0}'")]
    UnknownState(String),
    /// A transition refers to an event outside the alphabet.
    #[error("unknown event '{0}'")]
    UnknownEvent(String),
    /// The automaton has states but no initial state.
    #[error("automaton '{0}' has no initial state")]
    MissingInitial(String),
    /// Two transitions leave one state with one event for different targets.
    #[error("nondeterministic: state '{state}' has event '{event}' to both '{first}' and '{second}'")]
    Nondeterministic {
        /// Source state name.
        state: String,
        /// Event name.
        event: String,
        /// One target.
        first: String,
        /// The other target.
        second: String,
    },
    /// One event is controllable in one automaton and uncontrollable in another.
    #[error(
        "event '{event}' is {} in '{first}' but {} in '{second}'",
        if *first_controllable { "controllable" } else { "uncontrollable" },
        if *first_controllable { "uncontrollable" } else { "controllable" }
    )]
    InconsistentControllability {
        /// Event name.
        event: String,
        /// Automaton (or file) where the event was first seen.
        first: String,
        /// Whether it was controllable there.
        first_controllable: bool,
        /// Automaton (or file) that disagrees.
        second: String,
    },
    /// No automaton of the set says whether an event is controllable: the files holding it leave it
    /// unsaid (libFAUDES generators without `+C+`).
    #[error(
        "no file of the set says whether event '{event}' is controllable: {} {} it unsaid (a libFAUDES \
         generator without +C+ takes controllability from the plant; add the plant that has the event, \
         or mark it +C+)",
        automata.join(", "),
        if automata.len() == 1 { "leaves" } else { "all leave" }
    )]
    UnsaidControllability {
        /// Event name.
        event: String,
        /// The automata that hold it, none saying.
        automata: Vec<String>,
    },
    /// A count exceeds what the model can index.
    #[error(transparent)]
    Limit(#[from] super::IdError),
}
