//! The three memory figures the reference paper compares implementations by.
//!
//! For a set of automata with Σs states and Σt transitions in all, over `e` events: an adjacency matrix
//! (Σs)² + e, a chained list 2Σs + 5Σt + e, and the memory-safe vector Σs + 3Σt + e. They are formulas
//! over counts, so they can be given for sets too large to pack, such as the monolithic supervisor.

use crate::model::Automaton;

/// The paper's columns for one set of automata.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Columns {
    /// Σs.
    pub states: usize,
    /// Σt.
    pub transitions: usize,
    /// Events of the whole set.
    pub events: usize,
}

impl Columns {
    /// Counts the states and transitions of `automata`, over `events` events.
    pub fn of<'a>(automata: impl IntoIterator<Item = &'a Automaton>, events: usize) -> Columns {
        let (mut states, mut transitions) = (0, 0);
        for a in automata {
            states += a.states.len();
            transitions += a.transitions.len();
        }
        Columns { states, transitions, events }
    }

    /// Adjacency matrix: (Σs)² + e.
    pub fn matrix(&self) -> usize {
        self.states * self.states + self.events
    }

    /// Chained list: 2Σs + 5Σt + e.
    pub fn chained_list(&self) -> usize {
        2 * self.states + 5 * self.transitions + self.events
    }

    /// Memory-safe vector: Σs + 3Σt + e.
    pub fn memory_safe(&self) -> usize {
        self.states + 3 * self.transitions + self.events
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's Tables 1–3 for the manufacturing cell.
    #[test]
    fn published_rows() {
        let row = |states, transitions| {
            let c = Columns { states, transitions, events: 23 };
            [c.matrix(), c.chained_list(), c.memory_safe()]
        };
        assert_eq!(row(233, 697), [54_312, 3_974, 2_347]);
        assert_eq!(row(3420, 11_808), [11_696_423, 65_903, 38_867]);
        assert_eq!(row(1036, 6386), [1_073_319, 34_025, 20_217]);
    }
}
