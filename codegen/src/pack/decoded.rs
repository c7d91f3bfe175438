//! Rebuilding model automata from decoded tables: the common tail of every layout's decoder.

use crate::model::{Automaton, Event, EventId, State, StateId, Transition};

use firmware::build::bitset;

use super::{DecodeError, Role};

/// What a decoder recovered of one automaton; turned into an [`Automaton`] by [`Recovered::build`].
pub(crate) struct Recovered<'a> {
    /// Automaton name.
    pub name: &'a str,
    /// Plant or supervisor.
    pub role: Role,
    /// Global event ids of the alphabet, increasing.
    pub alphabet: Vec<usize>,
    /// Number of states.
    pub states: usize,
    /// Initial state index.
    pub initial: usize,
    /// `(source, global event, target)` triples, all in range.
    pub edges: Vec<(usize, usize, usize)>,
}

impl Recovered<'_> {
    /// The automaton: states named by index and unmarked (layouts keep no marking, the runtime needs
    /// none), the alphabet in global-id order with names and controllability from the event table.
    pub fn build(self, names: &[String], controllable: &[u32]) -> Result<Automaton, DecodeError> {
        let mut local = vec![None; names.len()];
        let mut events = Vec::with_capacity(self.alphabet.len());
        for (i, &g) in self.alphabet.iter().enumerate() {
            let name = names.get(g).ok_or_else(|| DecodeError::Inconsistent {
                what: self.name.to_owned(),
                detail: format!("alphabet holds event {g} of {}", names.len()),
            })?;
            local[g] = Some(EventId::from_u32(i as u32));
            events.push(Event { name: name.clone(), controllable: bitset::contains(controllable, g) });
        }
        let mut transitions = Vec::with_capacity(self.edges.len());
        for (source, g, target) in self.edges {
            let event = local.get(g).copied().flatten().ok_or_else(|| DecodeError::BadEvent {
                what: self.name.to_owned(),
                at: source,
                event: g,
            })?;
            transitions.push(Transition {
                source: StateId::from_u32(source as u32),
                event,
                target: StateId::from_u32(target as u32),
            });
        }
        let mut a = Automaton {
            name: self.name.to_owned(),
            kind: self.role.kind(),
            events,
            states: (0..self.states).map(|i| State { name: i.to_string(), marked: false }).collect(),
            initial: Some(StateId::from_u32(self.initial as u32)),
            transitions,
            controllability_unsaid: false,
        };
        a.canonicalize();
        Ok(a)
    }
}
