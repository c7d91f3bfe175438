//! One event table for a whole set of automata.

use std::collections::HashMap;

use super::{Automaton, EventId, ModelError};

/// Every event of a set of automata with one dense global id.
///
/// Ids follow the order of first appearance: automata in the order given, each alphabet in its own
/// order. The same inputs in the same order therefore always give the same ids.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EventTable {
    names: Vec<String>,
    controllable: Vec<bool>,
    /// Name of the automaton where each event was first seen (for error messages).
    origin: Vec<String>,
    by_name: HashMap<String, EventId>,
}

impl EventTable {
    /// Builds the table for `automata`, refusing an event whose controllability differs between two of them.
    pub fn build<'a>(automata: impl IntoIterator<Item = &'a Automaton>) -> Result<Self, ModelError> {
        let mut table = EventTable::default();
        for a in automata {
            for e in &a.events {
                table.insert(&e.name, e.controllable, &a.name)?;
            }
        }
        Ok(table)
    }

    /// Adds one event (or checks it against the entry already there) and returns its id.
    pub fn insert(&mut self, name: &str, controllable: bool, origin: &str) -> Result<EventId, ModelError> {
        if let Some(&id) = self.by_name.get(name) {
            if self.controllable[id.index()] != controllable {
                return Err(ModelError::InconsistentControllability {
                    event: name.to_owned(),
                    first: self.origin[id.index()].clone(),
                    first_controllable: self.controllable[id.index()],
                    second: origin.to_owned(),
                });
            }
            return Ok(id);
        }
        let id = EventId::new(self.names.len())?;
        self.names.push(name.to_owned());
        self.controllable.push(controllable);
        self.origin.push(origin.to_owned());
        self.by_name.insert(name.to_owned(), id);
        Ok(id)
    }

    /// Number of events.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether the table holds no event.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// The global id of `name`.
    pub fn id(&self, name: &str) -> Option<EventId> {
        self.by_name.get(name).copied()
    }

    /// The name of `id`.
    pub fn name(&self, id: EventId) -> &str {
        &self.names[id.index()]
    }

    /// Whether `id` is controllable.
    pub fn is_controllable(&self, id: EventId) -> bool {
        self.controllable[id.index()]
    }

    /// All ids in order.
    pub fn ids(&self) -> impl Iterator<Item = EventId> + '_ {
        (0..self.names.len()).map(|i| EventId::from_u32(i as u32))
    }

    /// The global id of each event of `a`'s alphabet (indexed by the local id).
    ///
    /// Returns `None` when `a` has an event this table does not know.
    pub fn global_ids(&self, a: &Automaton) -> Option<Vec<EventId>> {
        a.events.iter().map(|e| self.id(&e.name)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Kind;

    fn with_events(name: &str, events: &[(&str, bool)]) -> Automaton {
        let mut a = Automaton::new(name, Kind::Plant);
        for &(e, c) in events {
            a.add_event(e, c).unwrap();
        }
        a
    }

    #[test]
    fn ids_follow_first_appearance() {
        let g1 = with_events("G1", &[("b", true), ("a", false)]);
        let g2 = with_events("G2", &[("a", false), ("c", true)]);
        let t = EventTable::build([&g1, &g2]).unwrap();
        let names: Vec<_> = t.ids().map(|i| t.name(i)).collect();
        assert_eq!(names, ["b", "a", "c"]);
        assert_eq!(t.global_ids(&g2).unwrap(), [t.id("a").unwrap(), t.id("c").unwrap()]);
    }

    #[test]
    fn inconsistent_controllability_names_both_automata() {
        let g1 = with_events("G1", &[("a", true)]);
        let g2 = with_events("G2", &[("a", false)]);
        let msg = EventTable::build([&g1, &g2]).unwrap_err().to_string();
        assert_eq!(msg, "event 'a' is controllable in 'G1' but uncontrollable in 'G2'");
    }
}
