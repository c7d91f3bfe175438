//! Builds an [`Automaton`] while a reader walks a file, so that every broken invariant is reported
//! with the line that broke it.

use std::borrow::Cow;
use std::path::Path;

use super::hash::FastMap;
use super::ParseError;
use crate::model::{Automaton, EventId, Kind, ModelError, StateId, Transition};

/// An automaton under construction, with name indexes and the file it comes from.
///
/// State names of at most [`SHORT`] bytes are indexed by their bytes packed into two words, so that a
/// lookup compares integers in the map's own bucket (the usual `q123`-style names in large files);
/// longer names are indexed by `Cow`s that borrow from the text being read when they can.
pub(crate) struct Builder<'f> {
    file: &'f Path,
    automaton: Automaton,
    short_states: FastMap<(u64, u64), StateId>,
    long_states: FastMap<Cow<'f, str>, StateId>,
    events: FastMap<String, EventId>,
    /// The events of at most [`SHORT`] bytes again, by [`pack`]ed name: every transition looks one up.
    short_events: FastMap<(u64, u64), EventId>,
    /// Transitions with the line each came from, checked for determinism in [`Builder::finish`].
    transitions: Vec<(Transition, u32)>,
}

impl<'f> Builder<'f> {
    /// Starts an empty automaton called `name` read from `file`.
    pub(crate) fn new(file: &'f Path, name: impl Into<String>, kind: Kind) -> Self {
        Builder {
            file,
            automaton: Automaton::new(name, kind),
            short_states: FastMap::default(),
            long_states: FastMap::default(),
            events: FastMap::default(),
            short_events: FastMap::default(),
            transitions: Vec::new(),
        }
    }

    /// Adds a state, refusing a second state with the same name.
    pub(crate) fn state(
        &mut self,
        name: impl Into<Cow<'f, str>>,
        marked: bool,
        line: usize,
    ) -> Result<StateId, ParseError> {
        let name = name.into();
        let known = match pack(&name) {
            Some(key) => self.short_states.contains_key(&key),
            None => self.long_states.contains_key(&name),
        };
        if known {
            return Err(self.err(line, ModelError::DuplicateState(name.into_owned())));
        }
        let id = self.automaton.add_state(name.as_ref(), marked).map_err(|e| self.err(line, e))?;
        match pack(&name) {
            Some(key) => self.short_states.insert(key, id),
            None => self.long_states.insert(name, id),
        };
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
        if let Some(key) = pack(name) {
            self.short_events.insert(key, id);
        }
        Ok(id)
    }

    /// The state called `name`, or an error at `line`.
    pub(crate) fn state_named(&self, name: &str, line: usize) -> Result<StateId, ParseError> {
        match pack(name) {
            Some(key) => self.short_states.get(&key),
            None => self.long_states.get(name),
        }
        .copied()
        .ok_or_else(|| self.err(line, ModelError::UnknownState(name.to_owned())))
    }

    /// The event called `name`, or an error at `line`.
    pub(crate) fn event_named(&self, name: &str, line: usize) -> Result<EventId, ParseError> {
        match pack(name) {
            Some(key) => self.short_events.get(&key),
            None => self.events.get(name),
        }
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

    /// Adds a transition; [`Builder::finish`] refuses it if it makes the automaton nondeterministic.
    pub(crate) fn transition(&mut self, source: StateId, event: EventId, target: StateId, line: usize) {
        // Lines beyond u32 saturate: only an error message would show them.
        let line = u32::try_from(line).unwrap_or(u32::MAX);
        self.transitions.push((Transition { source, event, target }, line));
    }

    /// Checks determinism (naming the later of two conflicting lines), sorts and deduplicates the
    /// transitions, and checks that a non-empty automaton has an initial state.
    pub(crate) fn finish(mut self) -> Result<Automaton, ParseError> {
        self.transitions.sort_unstable();
        for pair in self.transitions.windows(2) {
            let ((t, l1), (u, l2)) = (pair[0], pair[1]);
            if (t.source, t.event) == (u.source, u.event) && t.target != u.target {
                let a = &self.automaton;
                let (first, second) = if l1 <= l2 { (t.target, u.target) } else { (u.target, t.target) };
                return Err(self.err(
                    l1.max(l2) as usize,
                    ModelError::Nondeterministic {
                        state: a.states[t.source.index()].name.clone(),
                        event: a.events[t.event.index()].name.clone(),
                        first: a.states[first.index()].name.clone(),
                        second: a.states[second.index()].name.clone(),
                    },
                ));
            }
        }
        let mut a = self.automaton;
        if !a.states.is_empty() && a.initial.is_none() {
            return Err(ParseError::model(self.file, None, ModelError::MissingInitial(a.name)));
        }
        // Names were checked unique as they came and every id was made here, so with determinism
        // checked above the automaton passes `Automaton::validate` (the tests assert it).
        a.transitions = self.transitions.into_iter().map(|(t, _)| t).collect();
        a.transitions.dedup();
        Ok(a)
    }

    fn err(&self, line: usize, e: impl Into<ModelError>) -> ParseError {
        ParseError::model(self.file, Some(line), e.into())
    }
}

/// The longest state name indexed by [`pack`]ed bytes.
const SHORT: usize = 15;

/// A name of at most [`SHORT`] bytes packed into two words: the bytes, zero-padded, with the length in
/// the last byte (so that names differing only by trailing zero bytes stay apart).
fn pack(name: &str) -> Option<(u64, u64)> {
    let bytes = name.as_bytes();
    if bytes.len() > SHORT {
        return None;
    }
    let mut word = [0u8; 16];
    word[..bytes.len()].copy_from_slice(bytes);
    word[15] = bytes.len() as u8;
    let (lo, hi) = word.split_at(8);
    Some((u64::from_le_bytes(lo.try_into().ok()?), u64::from_le_bytes(hi.try_into().ok()?)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_and_long_names_stay_apart() {
        let mut b = Builder::new(Path::new("t"), "t", Kind::Unknown);
        let names = ["a", "a\0", "", "exactly15bytes!", "sixteen_bytes_xx", "a_much_longer_state_name"];
        for (i, n) in names.iter().enumerate() {
            assert_eq!(b.state(*n, false, 1).unwrap().index(), i);
        }
        for (i, n) in names.iter().enumerate() {
            assert_eq!(b.state_named(n, 1).unwrap().index(), i);
            assert!(b.state(*n, false, 2).is_err(), "{n:?} is a duplicate");
        }
        assert!(b.state_named("b", 1).is_err());
        b.event("e", true, 1).unwrap();
        b.event("an_event_name_over_15", false, 1).unwrap();
        assert_eq!(b.event_named("an_event_name_over_15", 1).unwrap().index(), 1);
        assert_eq!(b.event_named("e", 1).unwrap().index(), 0);
        assert!(b.event("e", false, 2).is_err() && b.event_named("f", 1).is_err());
    }
}
