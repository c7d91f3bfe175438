//! A set of automata run side by side over one global event numbering, stepped one event at a time.
//!
//! This is the synchronous product *tracked*, not built: the state is one local state per member, an event
//! moves every member whose alphabet holds it and is refused when one of them has no transition for it.
//! The virtual plant runs the plant subsystems this way, the monitor the closed loop plants ‖ supervisors.

use super::{Automaton, Dfa, EventId, EventTable, ModelError};

/// One automaton of a [`Composition`]: its [`Dfa`] over the global event ids, with a per-event alphabet
/// lookup and its state names for messages.
#[derive(Clone, Debug)]
struct Member {
    dfa: Dfa,
    /// Whether each global event is in the member's alphabet.
    alphabet: Vec<bool>,
    initial: u32,
    state_names: Vec<String>,
}

/// Automata composed over one [`EventTable`]; see the module documentation.
///
/// # Examples
///
/// ```
/// use codegen::model::{Automaton, EventTable, Kind};
/// use codegen::model::Composition;
///
/// let mut m = Automaton::new("M", Kind::Plant);
/// let idle = m.add_state("idle", true).unwrap();
/// let busy = m.add_state("busy", false).unwrap();
/// let start = m.add_event("start", true).unwrap();
/// let done = m.add_event("done", false).unwrap();
/// m.initial = Some(idle);
/// m.add_transition(idle, start, busy);
/// m.add_transition(busy, done, idle);
///
/// let table = EventTable::build([&m]).unwrap();
/// let c = Composition::new(&[&m], &table).unwrap();
/// let mut state = c.initial();
/// assert!(c.step(&mut state, table.id("start").unwrap()));
/// assert!(!c.step(&mut state, table.id("start").unwrap()), "busy machines do not start");
/// assert!(!c.is_marked(&state));
/// ```
#[derive(Clone, Debug)]
pub struct Composition {
    members: Vec<Member>,
    names: Vec<String>,
    events: usize,
}

impl Composition {
    /// Composes `automata` over `table`, which must hold every event of every automaton.
    pub fn new(automata: &[&Automaton], table: &EventTable) -> Result<Self, ModelError> {
        let mut members = Vec::with_capacity(automata.len());
        for a in automata {
            let dfa = Dfa::from_automaton(a, table)?;
            let initial = dfa.initial().ok_or_else(|| ModelError::MissingInitial(a.name.clone()))?;
            let mut alphabet = vec![false; table.len()];
            for &e in dfa.alphabet() {
                alphabet[e as usize] = true;
            }
            members.push(Member {
                dfa,
                alphabet,
                initial,
                state_names: a.states.iter().map(|s| s.name.clone()).collect(),
            });
        }
        Ok(Composition {
            members,
            names: automata.iter().map(|a| a.name.clone()).collect(),
            events: table.len(),
        })
    }

    /// Every member's automaton over the global events, in member order.
    pub fn dfas(&self) -> Vec<&Dfa> {
        self.members.iter().map(|m| &m.dfa).collect()
    }

    /// Number of member automata.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// Whether there is no member (then every event is allowed and every state marked).
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// The name of member `i`.
    pub fn name(&self, i: usize) -> &str {
        &self.names[i]
    }

    /// The name of local state `state` of member `i`.
    pub fn state_name(&self, i: usize, state: u32) -> &str {
        self.members[i].state_names.get(state as usize).map_or("?", String::as_str)
    }

    /// The initial state: every member in its initial state.
    pub fn initial(&self) -> Vec<u32> {
        self.members.iter().map(|m| m.initial).collect()
    }

    /// Whether member `i` has `event` in its alphabet.
    pub fn has_event(&self, i: usize, event: EventId) -> bool {
        self.members[i].alphabet.get(event.index()).copied().unwrap_or(false)
    }

    /// Where member `i` goes from its local `state` on `event`, if it has that transition.
    pub fn local_step(&self, i: usize, state: u32, event: EventId) -> Option<u32> {
        let dfa = &self.members[i].dfa;
        if state as usize >= dfa.state_count() {
            return None;
        }
        dfa.step(state, event.as_u32())
    }

    /// Whether `event` can happen in `state`: every member holding it has a transition for it. An event
    /// outside every alphabet (or outside the table) is refused, as the firmware refuses unknown ids.
    pub fn allows(&self, state: &[u32], event: EventId) -> bool {
        if event.index() >= self.events {
            return false;
        }
        self.members
            .iter()
            .enumerate()
            .all(|(i, m)| !m.alphabet[event.index()] || self.local_step(i, state[i], event).is_some())
    }

    /// Takes `event` in `state` when [`Composition::allows`] it; returns whether it did. A refused event
    /// leaves `state` unchanged.
    pub fn step(&self, state: &mut [u32], event: EventId) -> bool {
        if !self.allows(state, event) {
            return false;
        }
        for (i, m) in self.members.iter().enumerate() {
            if m.alphabet[event.index()] {
                if let Some(t) = self.local_step(i, state[i], event) {
                    state[i] = t;
                }
            }
        }
        true
    }

    /// The names of the members that refuse `event` in `state` (for messages).
    pub fn refusers(&self, state: &[u32], event: EventId) -> Vec<&str> {
        (0..self.members.len())
            .filter(|&i| self.has_event(i, event) && self.local_step(i, state[i], event).is_none())
            .map(|i| self.names[i].as_str())
            .collect()
    }

    /// The events [`Composition::allows`] in `state`, in id order.
    pub fn enabled(&self, state: &[u32]) -> Vec<EventId> {
        (0..self.events).map(|e| EventId::from_u32(e as u32)).filter(|&e| self.allows(state, e)).collect()
    }

    /// Whether every member is in a marked state.
    pub fn is_marked(&self, state: &[u32]) -> bool {
        self.members.iter().zip(state).all(|(m, &s)| (s as usize) < m.dfa.state_count() && m.dfa.is_marked(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::{automaton, machine};
    use crate::model::Kind;

    #[test]
    fn shared_events_synchronise_and_private_ones_interleave() {
        let m1 = machine("M1", "a1", "b1");
        let m2 = machine("M2", "a2", "b2");
        // A one-slot buffer between the machines: b1 fills it, a2 empties it.
        let buf = automaton("B", Kind::Spec, 2, &[0], &["a2"], &[(0, "b1", 1), (1, "a2", 0)]);
        let table = EventTable::build([&m1, &m2, &buf]).unwrap();
        let c = Composition::new(&[&m1, &m2, &buf], &table).unwrap();
        let id = |n| table.id(n).unwrap();
        let mut s = c.initial();
        assert_eq!(c.enabled(&s), [id("a1")]);
        assert!(c.step(&mut s, id("a1")));
        assert!(c.step(&mut s, id("b1")));
        assert_eq!(c.enabled(&s), [id("a1"), id("a2")]);
        assert!(!c.step(&mut s.clone(), id("b1")), "M1 is idle");
        assert_eq!(c.refusers(&s, id("b1")), ["M1", "B"]);
        assert!(c.step(&mut s, id("a2")));
        assert_eq!(s, [0, 1, 0]);
        assert!(!c.is_marked(&s));
    }

    #[test]
    fn unknown_event_is_refused_not_a_panic() {
        let m = machine("M", "a", "b");
        let table = EventTable::build([&m]).unwrap();
        let c = Composition::new(&[&m], &table).unwrap();
        assert!(!c.allows(&c.initial(), EventId::from_u32(200)));
    }
}
