//! A single finite automaton with named states and events.

use std::collections::HashMap;

use super::{EventId, ModelError, StateId};

/// The role an automaton plays in a supervisor set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub enum Kind {
    /// Free behaviour of a plant subsystem.
    Plant,
    /// A control specification.
    Spec,
    /// A supervisor (synthesised or given).
    Supervisor,
    /// The file did not say.
    #[default]
    Unknown,
}

impl Kind {
    /// Lower-case name used in reports and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Plant => "plant",
            Kind::Spec => "spec",
            Kind::Supervisor => "supervisor",
            Kind::Unknown => "unknown",
        }
    }
}

/// An event of an alphabet.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Event {
    /// Name, unique within the alphabet.
    pub name: String,
    /// Whether the controller may disable (and must generate) it.
    pub controllable: bool,
}

/// A state of an automaton.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct State {
    /// Name, unique within the automaton.
    pub name: String,
    /// Whether the state is marked (a completed task).
    pub marked: bool,
}

/// One transition; the event id indexes the automaton's own alphabet.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Transition {
    /// Source state.
    pub source: StateId,
    /// Event, as an index into [`Automaton::events`].
    pub event: EventId,
    /// Target state.
    pub target: StateId,
}

/// A finite automaton: states, alphabet, initial state, marked states, transitions.
///
/// Fields are public so readers and algorithms can build automata directly; [`Automaton::validate`]
/// checks the invariants (unique names, references in range, an initial state when there are states,
/// determinism) and [`Automaton::canonicalize`] puts transitions in their one sorted order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Automaton {
    /// Name of the automaton (file stem or the name inside the file).
    pub name: String,
    /// Role in the set.
    pub kind: Kind,
    /// The alphabet; an [`EventId`] indexes this vector.
    pub events: Vec<Event>,
    /// The states; a [`StateId`] indexes this vector.
    pub states: Vec<State>,
    /// Initial state, absent only for the empty automaton.
    pub initial: Option<StateId>,
    /// Transitions, sorted by (source, event, target) after [`Automaton::canonicalize`].
    pub transitions: Vec<Transition>,
    /// Whether its file said nothing of controllability (a libFAUDES generator without `+C+`, where
    /// controllability belongs to the plant): every event's `controllable` is then a placeholder until
    /// [`super::resolve_controllability`] takes it from the files of the set that say it.
    pub controllability_unsaid: bool,
}

impl Automaton {
    /// An empty automaton with a name and a role.
    pub fn new(name: impl Into<String>, kind: Kind) -> Self {
        Automaton { name: name.into(), kind, ..Automaton::default() }
    }

    /// Appends a state and returns its id.
    pub fn add_state(&mut self, name: impl Into<String>, marked: bool) -> Result<StateId, ModelError> {
        let id = StateId::new(self.states.len())?;
        self.states.push(State { name: name.into(), marked });
        Ok(id)
    }

    /// Appends an event to the alphabet and returns its id.
    pub fn add_event(&mut self, name: impl Into<String>, controllable: bool) -> Result<EventId, ModelError> {
        let id = EventId::new(self.events.len())?;
        self.events.push(Event { name: name.into(), controllable });
        Ok(id)
    }

    /// Appends a transition (no checks; see [`Automaton::validate`]).
    pub fn add_transition(&mut self, source: StateId, event: EventId, target: StateId) {
        self.transitions.push(Transition { source, event, target });
    }

    /// The id of the event called `name`, if it is in the alphabet.
    pub fn event_id(&self, name: &str) -> Option<EventId> {
        self.events.iter().position(|e| e.name == name).map(|i| EventId::from_u32(i as u32))
    }

    /// The id of the state called `name`, if there is one.
    pub fn state_id(&self, name: &str) -> Option<StateId> {
        self.states.iter().position(|s| s.name == name).map(|i| StateId::from_u32(i as u32))
    }

    /// Number of marked states.
    pub fn marked_count(&self) -> usize {
        self.states.iter().filter(|s| s.marked).count()
    }

    /// Number of controllable events in the alphabet.
    pub fn controllable_count(&self) -> usize {
        self.events.iter().filter(|e| e.controllable).count()
    }

    /// Sorts and deduplicates the transitions into their canonical order.
    pub fn canonicalize(&mut self) {
        self.transitions.sort_unstable();
        self.transitions.dedup();
    }

    /// Checks every invariant later stages rely on.
    pub fn validate(&self) -> Result<(), ModelError> {
        unique(self.states.iter().map(|s| s.name.as_str()), ModelError::DuplicateState)?;
        unique(self.events.iter().map(|e| e.name.as_str()), ModelError::DuplicateEvent)?;
        if !self.states.is_empty() && self.initial.is_none() {
            return Err(ModelError::MissingInitial(self.name.clone()));
        }
        if let Some(init) = self.initial {
            self.check_state(init)?;
        }
        let mut seen: HashMap<(StateId, EventId), StateId> = HashMap::with_capacity(self.transitions.len());
        for t in &self.transitions {
            self.check_state(t.source)?;
            self.check_state(t.target)?;
            if t.event.index() >= self.events.len() {
                return Err(ModelError::UnknownEvent(format!("#{}", t.event)));
            }
            if let Some(&other) = seen.get(&(t.source, t.event)) {
                if other != t.target {
                    return Err(ModelError::Nondeterministic {
                        state: self.states[t.source.index()].name.clone(),
                        event: self.events[t.event.index()].name.clone(),
                        first: self.states[other.index()].name.clone(),
                        second: self.states[t.target.index()].name.clone(),
                    });
                }
            }
            seen.insert((t.source, t.event), t.target);
        }
        Ok(())
    }

    fn check_state(&self, s: StateId) -> Result<(), ModelError> {
        if s.index() < self.states.len() {
            Ok(())
        } else {
            Err(ModelError::UnknownState(format!("#{s}")))
        }
    }
}

fn unique<'a>(names: impl Iterator<Item = &'a str>, err: fn(String) -> ModelError) -> Result<(), ModelError> {
    let mut seen = std::collections::HashSet::new();
    for n in names {
        if !seen.insert(n) {
            return Err(err(n.to_owned()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_state() -> Automaton {
        let mut a = Automaton::new("G", Kind::Plant);
        let s0 = a.add_state("0", true).unwrap();
        let s1 = a.add_state("1", false).unwrap();
        let e = a.add_event("a", true).unwrap();
        a.initial = Some(s0);
        a.add_transition(s0, e, s1);
        a
    }

    #[test]
    fn valid_automaton_passes() {
        assert_eq!(two_state().validate(), Ok(()));
    }

    #[test]
    fn nondeterminism_is_named() {
        let mut a = two_state();
        a.add_transition(StateId::new(0).unwrap(), EventId::new(0).unwrap(), StateId::new(0).unwrap());
        let msg = a.validate().unwrap_err().to_string();
        assert_eq!(msg, "nondeterministic: state '0' has event 'a' to both '1' and '0'");
    }

    #[test]
    fn missing_initial_and_duplicates_are_refused() {
        let mut a = two_state();
        a.initial = None;
        assert_eq!(a.validate(), Err(ModelError::MissingInitial("G".into())));
        let mut b = two_state();
        b.add_state("1", false).unwrap();
        assert_eq!(b.validate(), Err(ModelError::DuplicateState("1".into())));
    }
}
