//! This module is the home of [`PackSet`]: the automata one firmware image runs, over one event numbering.

use crate::model::{Automaton, Dfa, EventId, EventTable, Kind, StateId};

use super::PackError;

/// What an automaton does in the loop; the runtime's `table::Role`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Role {
    /// A plant subsystem: generates the controllable events it can take, tracks the uncontrollable ones.
    Plant,
    /// A supervisor: only disables controllable events.
    Supervisor,
}

impl Role {
    /// Lower-case name used in reports and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Role::Plant => "plant",
            Role::Supervisor => "supervisor",
        }
    }

    /// The model kind an automaton of this role has once decoded.
    pub fn kind(self) -> Kind {
        match self {
            Role::Plant => Kind::Plant,
            Role::Supervisor => Kind::Supervisor,
        }
    }
}

/// One automaton of a [`PackSet`], with its transitions re-indexed by the set's global event ids.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Member {
    /// The automaton as given.
    pub automaton: Automaton,
    /// Plant or supervisor.
    pub role: Role,
    /// Its transitions over the set's global event ids, each state's sorted by event id: the order every
    /// layout writes records in, so the same set always gives the same bytes.
    pub dfa: Dfa,
}

impl Member {
    /// Name of the automaton.
    pub fn name(&self) -> &str {
        &self.automaton.name
    }

    /// Number of states.
    pub fn state_count(&self) -> usize {
        self.automaton.states.len()
    }

    /// Number of transitions.
    pub fn transition_count(&self) -> usize {
        self.dfa.transition_count()
    }

    /// Outgoing `(global event, target)` pairs of state `s`, by increasing event id.
    pub fn out(&self, s: usize) -> impl Iterator<Item = (EventId, StateId)> + '_ {
        self.dfa.edges(s as u32).map(|(e, t)| (EventId::from_u32(e), StateId::from_u32(t)))
    }

    /// Number of transitions leaving state `s`.
    pub fn degree(&self, s: usize) -> usize {
        self.dfa.degree(s as u32)
    }

    /// The initial state (every member has one: [`PackSet::new`] refuses automata without states).
    pub fn initial(&self) -> StateId {
        self.automaton.initial.unwrap_or_default()
    }

    /// The alphabet as global ids in increasing order.
    pub fn alphabet(&self) -> Vec<EventId> {
        self.dfa.alphabet().iter().map(|&e| EventId::from_u32(e)).collect()
    }
}

/// Plants and supervisors over one [`EventTable`]: the input of every layout.
///
/// Plants come first, then supervisors, each group in the order given; event ids follow first appearance
/// in that order (see [`EventTable::build`]). Every automaton has passed [`Automaton::validate`] and has at
/// least one state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PackSet {
    members: Vec<Member>,
    events: EventTable,
}

impl PackSet {
    /// Validates the automata and numbers their events.
    ///
    /// Refuses an invalid or empty automaton and an event whose controllability differs between two
    /// automata.
    pub fn new(plants: Vec<Automaton>, supervisors: Vec<Automaton>) -> Result<PackSet, PackError> {
        let tagged: Vec<(Automaton, Role)> = plants
            .into_iter()
            .map(|a| (a, Role::Plant))
            .chain(supervisors.into_iter().map(|a| (a, Role::Supervisor)))
            .collect();
        for (a, _) in &tagged {
            a.validate()?;
            if a.states.is_empty() {
                return Err(PackError::Empty { automaton: a.name.clone() });
            }
        }
        let events = EventTable::build(tagged.iter().map(|(a, _)| a))?;
        let members = tagged
            .into_iter()
            .map(|(automaton, role)| {
                Ok(Member { dfa: Dfa::from_automaton(&automaton, &events)?, automaton, role })
            })
            .collect::<Result<_, PackError>>()?;
        Ok(PackSet { members, events })
    }

    /// Plants first, then supervisors.
    pub fn members(&self) -> &[Member] {
        &self.members
    }

    /// The global event numbering.
    pub fn events(&self) -> &EventTable {
        &self.events
    }

    /// The members of one role only, over the same event numbering (so sizes of event-indexed tables
    /// stay those of the whole set). The paper counts supervisors this way.
    pub fn only(&self, role: Role) -> PackSet {
        PackSet {
            members: self.members.iter().filter(|m| m.role == role).cloned().collect(),
            events: self.events.clone(),
        }
    }

    /// Total states over all members (the paper's Σs).
    pub fn state_count(&self) -> usize {
        self.members.iter().map(Member::state_count).sum()
    }

    /// Total transitions over all members (the paper's Σt).
    pub fn transition_count(&self) -> usize {
        self.members.iter().map(Member::transition_count).sum()
    }
}
