//! This module is the home of [`Names`]: what a packed set keeps besides its bytes — the names of its
//! events and automata and the automata's roles — for reports and for decoding the bytes back to
//! automata. Layouts keep them apart from the tables they measure, and never count them.

use super::{DecodeError, PackSet, Role};

/// The names of a packed set's events and automata, and the automata's roles.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Names {
    /// Event names by global id.
    pub events: Vec<String>,
    /// Per automaton, plants first: its name and role.
    pub automata: Vec<(String, Role)>,
}

impl Names {
    /// The names of `set`.
    pub fn of(set: &PackSet) -> Names {
        let events = set.events();
        Names {
            events: events.ids().map(|e| events.name(e).to_owned()).collect(),
            automata: set.members().iter().map(|m| (m.name().to_owned(), m.role)).collect(),
        }
    }

    /// Name and role of automaton `a`, or why there is none.
    pub fn automaton(&self, a: usize) -> Result<(&str, Role), DecodeError> {
        self.automata.get(a).map(|(n, r)| (n.as_str(), *r)).ok_or_else(|| DecodeError::Inconsistent {
            what: String::from("names"),
            detail: format!("no name for automaton {a} of {}", self.automata.len()),
        })
    }

    /// Each automaton's name with the bytes of its block, from `bytes` in automaton order (`?` for a
    /// block without a name): the per-automaton part of a [`Size`](super::Size).
    pub fn with_bytes(&self, bytes: impl IntoIterator<Item = usize>) -> Vec<(String, usize)> {
        let name = |a: usize| self.automata.get(a).map_or_else(|| String::from("?"), |(n, _)| n.clone());
        bytes.into_iter().enumerate().map(|(a, b)| (name(a), b)).collect()
    }
}
