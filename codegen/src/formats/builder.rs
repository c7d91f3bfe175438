//! Builds an [`Automaton`] while a reader walks a file, so that every broken invariant is reported
//! with the line that broke it.

use std::collections::HashMap;
use std::path::Path;

use super::ParseError;
use crate::model::{Automaton, EventId, Kind, ModelError, StateId};

/// An automaton under construction, with name indexes and the file it comes from.
pub(crate) struct Builder<'f> {
    file: &'f Path,
    automaton: Automaton,
    states: HashMap<String, StateId>,
    events: HashMap<String, EventId>,
    successor: HashMap<(StateId, EventId), StateId>,
}

impl<'f> Builder<'f> {
    /// Starts an empty automaton called `name` read from `file`.
    pub(crate) fn new(file: &'f Path, name: impl Into<String>, kind: Kind) -> Self {
        Builder {
            file,
            automaton: Automaton::new(name, kind),
            states: HashMap::new(),
            events: HashMap::new(),
            successor: HashMap::new(),
        }
    }

    /// Adds a state, refusing a second state with the same name.
    pub(crate) fn state(&mut self, name: &str, marked: bool, line: usize) -> Result<StateId, ParseError> {
        if self.states.contains_key(name) {
            return Err(self.err(line, ModelError::DuplicateState(name.to_owned())));
        }
        let id = self.automaton.add_state(name, marked).map_err(|e| self.err(line, e))?;
        self.states.insert(name.to_owned(), id);
        Ok(id)
    }

    /// Adds an event, refusing a second event with the same name.
    pub(crate) fn event(
        &mut self,
        name: &str,
        controllable: bool,
        line: usize,
    ) -> Result<EventId, ParseError> {
        if self.events.contains_key(name) {
            return Err(self.err(line, ModelError::DuplicateEvent(name.to_owned())));
        }
        let id = self.automaton.add_event(name, controllable).map_err(|e| self.err(line, e))?;
        self.events.insert(name.to_owned(), id);
        Ok(id)
    }

    /// The state called `name`, or an error at `line`.
    pub(crate) fn state_named(&self, name: &str, line: usize) -> Result<StateId, ParseError> {
        self.states
            .get(name)
            .copied()
            .ok_or_else(|| self.err(line, ModelError::UnknownState(name.to_owned())))
    }

    /// The event called `name`, or an error at `line`.
    pub(crate) fn event_named(&self, name: &str, line: usize) -> Result<EventId, ParseError> {
        self.events
            .get(name)
            .copied()
            .ok_or_else(|| self.err(line, ModelError::UnknownEvent(name.to_owned())))
    }

    /// Number of states so far.
    pub(crate) fn state_count(&self) -> usize {
        self.automaton.states.len()
    }

    /// Marks `state`.
    pub(crate) fn mark(&mut self, state: StateId) {
        self.automaton.states[state.index()].marked = true;
    }

    /// Marks every state (formats where "no marking given" or `*` means "all marked").
    pub(crate) fn mark_all(&mut self) {
        self.automaton.states.iter_mut().for_each(|s| s.marked = true);
    }

    /// Makes `state` the initial state, refusing a second, different one.
    pub(crate) fn initial(&mut self, state: StateId, line: usize) -> Result<(), ParseError> {
        match self.automaton.initial {
            Some(first) if first != state => Err(ParseError::syntax(
                self.file,
                line,
                format!(
                    "second initial state '{}' (the first is '{}'); only one is supported",
                    self.automaton.states[state.index()].name,
                    self.automaton.states[first.index()].name
                ),
            )),
            _ => {
                self.automaton.initial = Some(state);
                Ok(())
            }
        }
    }

    /// Adds a transition, refusing one that makes the automaton nondeterministic.
    pub(crate) fn transition(
        &mut self,
        source: StateId,
        event: EventId,
        target: StateId,
        line: usize,
    ) -> Result<(), ParseError> {
        if let Some(&other) = self.successor.get(&(source, event)) {
            if other == target {
                return Ok(());
            }
            let a = &self.automaton;
            return Err(self.err(
                line,
                ModelError::Nondeterministic {
                    state: a.states[source.index()].name.clone(),
                    event: a.events[event.index()].name.clone(),
                    first: a.states[other.index()].name.clone(),
                    second: a.states[target.index()].name.clone(),
                },
            ));
        }
        self.successor.insert((source, event), target);
        self.automaton.add_transition(source, event, target);
        Ok(())
    }

    /// Validates and canonicalizes the automaton.
    pub(crate) fn finish(self) -> Result<Automaton, ParseError> {
        let mut a = self.automaton;
        a.validate().map_err(|e| ParseError::model(self.file, None, e))?;
        a.canonicalize();
        Ok(a)
    }

    fn err(&self, line: usize, e: impl Into<ModelError>) -> ParseError {
        ParseError::model(self.file, Some(line), e.into())
    }
}
