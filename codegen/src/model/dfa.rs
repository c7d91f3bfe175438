//! This module is the home of [`Dfa`]: an automaton's transitions re-indexed by the global event ids of
//! one [`EventTable`] — what synthesis works on, what the packed layouts are written from and what a
//! [`Composition`](super::Composition) steps.
//!
//! States are dense `u32` ids; the transitions of all states sit in two flat arrays (events and targets)
//! indexed by a per-state offset (compressed sparse rows), sorted by event within each state. Events are
//! global ids of one [`EventTable`], so automata built over the same table compose without renaming.
//! There is no per-state allocation: an automaton with `s` states and `t` transitions takes about
//! `9 s + 8 t` bytes ([`Dfa::memory_usage`]).

use super::{Automaton, Event, EventId, EventTable, Kind, ModelError, State, StateId};

/// Marker for "no state" in `u32` state arrays.
pub(crate) const NONE: u32 = u32::MAX;

/// A deterministic automaton over the global events of one [`EventTable`], in compressed sparse rows.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Dfa {
    /// Global event ids of the alphabet, ascending.
    pub(crate) alphabet: Vec<u32>,
    /// Initial state, `None` for the empty automaton.
    pub(crate) initial: Option<u32>,
    /// Whether each state is marked.
    pub(crate) marked: Vec<bool>,
    /// `offsets[s]..offsets[s + 1]` indexes the transitions of state `s`; length states + 1.
    pub(crate) offsets: Vec<usize>,
    /// Event of each transition (global id), ascending within a state.
    pub(crate) events: Vec<u32>,
    /// Target of each transition.
    pub(crate) targets: Vec<u32>,
}

impl Dfa {
    /// Converts `a` to global event ids of `table`; refuses an automaton that fails
    /// [`Automaton::validate`] or has an event `table` does not hold.
    pub fn from_automaton(a: &Automaton, table: &EventTable) -> Result<Dfa, ModelError> {
        a.validate()?;
        let global = table.global_ids(a).ok_or_else(|| {
            let missing = a.events.iter().find(|e| table.id(&e.name).is_none());
            ModelError::UnknownEvent(missing.map_or_else(String::new, |e| e.name.clone()))
        })?;
        let mut alphabet: Vec<u32> = global.iter().map(|e| e.as_u32()).collect();
        alphabet.sort_unstable();
        let mut rows: Vec<(u32, u32, u32)> = a
            .transitions
            .iter()
            .map(|t| (t.source.as_u32(), global[t.event.index()].as_u32(), t.target.as_u32()))
            .collect();
        rows.sort_unstable();
        rows.dedup();
        let mut b = DfaBuilder::new(alphabet);
        let mut row = rows.iter().peekable();
        for (s, state) in a.states.iter().enumerate() {
            b.start_state(state.marked);
            while let Some(&&(src, e, t)) = row.peek() {
                if src as usize != s {
                    break;
                }
                b.push(e, t);
                row.next();
            }
        }
        Ok(b.finish(a.initial.map(StateId::as_u32)))
    }

    /// Converts back to a model automaton named `name`, naming states with `state_name`.
    pub fn to_automaton(
        &self,
        name: &str,
        kind: Kind,
        table: &EventTable,
        mut state_name: impl FnMut(u32) -> String,
    ) -> Automaton {
        let mut a = Automaton::new(name, kind);
        let mut local = vec![NONE; table.len()];
        for &e in &self.alphabet {
            let id = EventId::from_u32(e);
            local[e as usize] = a.events.len() as u32;
            a.events.push(Event { name: table.name(id).to_owned(), controllable: table.is_controllable(id) });
        }
        for s in 0..self.state_count() as u32 {
            a.states.push(State { name: state_name(s), marked: self.marked[s as usize] });
        }
        a.initial = self.initial.map(StateId::from_u32);
        a.transitions.reserve(self.transition_count());
        for s in 0..self.state_count() as u32 {
            for (e, t) in self.edges(s) {
                a.add_transition(
                    StateId::from_u32(s),
                    EventId::from_u32(local[e as usize]),
                    StateId::from_u32(t),
                );
            }
        }
        a
    }

    /// Number of states.
    pub fn state_count(&self) -> usize {
        self.marked.len()
    }

    /// Number of transitions.
    pub fn transition_count(&self) -> usize {
        self.targets.len()
    }

    /// Initial state, `None` when the automaton is empty.
    pub fn initial(&self) -> Option<u32> {
        self.initial
    }

    /// Global event ids of the alphabet, ascending.
    pub fn alphabet(&self) -> &[u32] {
        &self.alphabet
    }

    /// Whether state `s` is marked.
    pub fn is_marked(&self, s: u32) -> bool {
        self.marked[s as usize]
    }

    /// The transitions leaving `s` as (event, target), ascending by event.
    pub fn edges(&self, s: u32) -> impl Iterator<Item = (u32, u32)> + '_ {
        let r = self.offsets[s as usize]..self.offsets[s as usize + 1];
        self.events[r.clone()].iter().copied().zip(self.targets[r].iter().copied())
    }

    /// Number of transitions leaving `s`.
    pub fn degree(&self, s: u32) -> usize {
        self.offsets[s as usize + 1] - self.offsets[s as usize]
    }

    /// The target of `s` under event `e`, if the transition exists.
    pub fn step(&self, s: u32, e: u32) -> Option<u32> {
        let r = self.offsets[s as usize]..self.offsets[s as usize + 1];
        let ev = &self.events[r.clone()];
        ev.binary_search(&e).ok().map(|i| self.targets[r.start + i])
    }

    /// Bytes of heap memory held by this automaton.
    pub fn memory_usage(&self) -> usize {
        self.alphabet.capacity() * 4
            + self.marked.capacity()
            + self.offsets.capacity() * std::mem::size_of::<usize>()
            + self.events.capacity() * 4
            + self.targets.capacity() * 4
    }

    /// Whether `e` is in the alphabet.
    pub fn has_event(&self, e: u32) -> bool {
        self.alphabet.binary_search(&e).is_ok()
    }
}

/// Appends states one at a time, each with its transitions in ascending event order.
pub(crate) struct DfaBuilder {
    dfa: Dfa,
}

impl DfaBuilder {
    /// A builder for an automaton over `alphabet` (ascending global ids).
    pub(crate) fn new(alphabet: Vec<u32>) -> Self {
        DfaBuilder { dfa: Dfa { alphabet, offsets: vec![0], ..Dfa::default() } }
    }

    /// Starts the next state; transitions pushed after this belong to it.
    pub(crate) fn start_state(&mut self, marked: bool) {
        if !self.dfa.marked.is_empty() {
            self.dfa.offsets.push(self.dfa.targets.len());
        }
        self.dfa.marked.push(marked);
    }

    /// Adds a transition of the current state (events must come in ascending order).
    pub(crate) fn push(&mut self, event: u32, target: u32) {
        self.dfa.events.push(event);
        self.dfa.targets.push(target);
    }

    /// Closes the last state and returns the automaton.
    pub(crate) fn finish(mut self, initial: Option<u32>) -> Dfa {
        if !self.dfa.marked.is_empty() {
            self.dfa.offsets.push(self.dfa.targets.len());
        }
        self.dfa.initial = if self.dfa.marked.is_empty() { None } else { initial };
        self.dfa
    }
}
