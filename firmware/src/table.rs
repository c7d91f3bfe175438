//! This module is the home of the tables the runtime reads: one [`SupervisorSet`] of automata in the
//! `offset` layout, emitted by `codegen` as `static` data in flash.
//!
//! # The `offset` layout
//!
//! Each automaton is one byte block. For every state, in state-index order: one byte `n` (the number of
//! outgoing transitions), then `n` records of three bytes `[event][target_hi][target_lo]`: the global event
//! id and the *byte offset* of the target state's count byte within the same block, big-endian. This is
//! the reference tool's "memory safe" vector (size Σs + 3Σt per automaton) with one change: targets are
//! record offsets instead of state indices, so reaching the next state costs nothing rather than a walk
//! over k records. A state is held at run time as its offset.
//!
//! Limits: at most 256 events (one byte per event id), at most 255 transitions out of one state, and a
//! block of at most 65 536 bytes. `codegen` refuses sets beyond them.
//!
//! # Side tables
//!
//! Beside the blocks, a set carries what makes the hot path independent of the set's size: per event the
//! automata that hold it ([`SupervisorSet::holders`], so an event touches only those), per plant the
//! controllable events it generates and the *choice sites* of the local-queue policies
//! ([`SupervisorSet::plant_events`], [`SupervisorSet::sites`]; see [`crate::choice`]). A set has at most
//! [`MAX_AUTOMATA`] automata.

/// Most automata in one set: one bit each in a `u32` of [`SupervisorSet::holders`].
pub const MAX_AUTOMATA: usize = 32;

/// What an automaton does in the loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A plant subsystem of the product system: generates the controllable events it can physically
    /// take and tracks the uncontrollable ones.
    Plant,
    /// A supervisor: only disables controllable events.
    Supervisor,
}

/// One automaton of the set in the `offset` layout.
#[derive(Clone, Copy, Debug)]
pub struct Automaton<'t> {
    /// Name, for logs and reports.
    pub name: &'t str,
    /// Plant or supervisor.
    pub role: Role,
    /// Offset of the initial state within [`Automaton::block`].
    pub initial: u16,
    /// The states and transitions, as described in the module documentation.
    pub block: &'t [u8],
    /// Bitset over global event ids (bit `e % 32` of word `e / 32`): the automaton's alphabet. An event
    /// outside it never moves or blocks the automaton.
    pub alphabet: &'t [u32],
}

/// The whole set the firmware runs: plants and supervisors over one event numbering. On the target every
/// slice is a `static` in flash (`'t = 'static`); on the host the tables may be borrowed from owned data.
#[derive(Clone, Copy, Debug)]
pub struct SupervisorSet<'t> {
    /// Event names by global id.
    pub event_names: &'t [&'t str],
    /// Bitset over global event ids: the controllable ones.
    pub controllable: &'t [u32],
    /// Plants first, then supervisors, in manifest order.
    pub automata: &'t [Automaton<'t>],
    /// Per global event id: bit `a` set when automaton `a` has the event in its alphabet.
    pub holders: &'t [u32],
    /// Per plant, a bitset of `controllable.len()` words: the controllable events it generates (those
    /// of its alphabet no earlier plant holds). Every controllable event belongs to exactly one plant.
    pub plant_events: &'t [u32],
    /// The choice sites with two or more controllable out-events, sorted by automaton then state.
    pub sites: &'t [Site],
}

/// A choice site: a state of a plant where two or more controllable events it generates leave.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Site {
    /// Index of the plant in [`SupervisorSet::automata`].
    pub automaton: u8,
    /// The state, as its offset in the plant's block.
    pub state: u16,
}

/// Why a set cannot run with a runtime of the given sizes (a table emitted for another build).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableError {
    /// The automaton count differs from the runtime's, or exceeds [`MAX_AUTOMATA`].
    Automata,
    /// A bitset has another word count than the runtime's, or a per-event table another length.
    EventWords,
    /// An automaton's initial offset lies outside its block.
    Initial,
    /// A site names no plant or is out of order.
    Sites,
}

impl SupervisorSet<'_> {
    /// Checks the sizes a runtime with `words` bitset words and `automata` automata relies on.
    pub fn check(&self, words: usize, automata: usize) -> Result<(), TableError> {
        if self.automata.len() != automata || automata > MAX_AUTOMATA {
            return Err(TableError::Automata);
        }
        let events = self.event_names.len();
        if events > 32 * words
            || self.controllable.len() != words
            || self.holders.len() != events
            || self.plant_events.len() != words * self.plant_count()
            || self.automata.iter().any(|a| a.alphabet.len() != words)
        {
            return Err(TableError::EventWords);
        }
        if self.automata.iter().any(|a| usize::from(a.initial) >= a.block.len()) {
            return Err(TableError::Initial);
        }
        let plants = self.plant_count();
        let ordered = self.sites.windows(2).all(|w| w[0] < w[1]);
        if !ordered || self.sites.iter().any(|s| usize::from(s.automaton) >= plants) {
            return Err(TableError::Sites);
        }
        Ok(())
    }

    /// Number of plants (they come first in [`SupervisorSet::automata`]).
    pub fn plant_count(&self) -> usize {
        self.automata.iter().take_while(|a| a.role == Role::Plant).count()
    }

    /// The index of the site of plant `automaton` in state `state`, if it is one.
    pub fn site(&self, automaton: u8, state: u16) -> Option<usize> {
        self.sites.binary_search(&Site { automaton, state }).ok()
    }
}

impl<'t> Automaton<'t> {
    /// The offset of the state reached from the state at `state` by `event`, or `None` when the state
    /// has no such transition (or `state` is not a state offset of this block).
    #[inline]
    pub fn step(&self, state: u16, event: u8) -> Option<u16> {
        self.records(state).chunks_exact(3).find(|r| r[0] == event).map(|r| u16::from_be_bytes([r[1], r[2]]))
    }

    /// The transition records `[event][target_hi][target_lo]` of the state at `state` (empty when
    /// `state` is not a state offset of this block).
    #[inline]
    pub fn records(&self, state: u16) -> &'t [u8] {
        let block = self.block;
        let at = usize::from(state);
        let Some(&n) = block.get(at) else { return &[] };
        block.get(at + 1..at + 1 + 3 * usize::from(n)).unwrap_or(&[])
    }

    /// Whether `event` belongs to this automaton's alphabet.
    pub fn has_event(&self, event: u8) -> bool {
        let word = usize::from(event / 32);
        self.alphabet.get(word).is_some_and(|w| w & (1 << (event % 32)) != 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two states: 0 –e0→ 1 (offset 4), 1 –e1→ 0.
    static BLOCK: [u8; 8] = [1, 0, 0, 4, 1, 1, 0, 0];
    static ALPHABET: [u32; 1] = [0b11];

    fn toggle() -> Automaton<'static> {
        Automaton { name: "T", role: Role::Plant, initial: 0, block: &BLOCK, alphabet: &ALPHABET }
    }

    #[test]
    fn step_follows_offsets() {
        let t = toggle();
        assert_eq!(t.step(0, 0), Some(4));
        assert_eq!(t.step(4, 1), Some(0));
        assert_eq!(t.step(0, 1), None);
    }

    #[test]
    fn step_out_of_block_is_none_not_panic() {
        assert_eq!(toggle().step(200, 0), None);
        assert_eq!(toggle().step(7, 0), None);
    }

    #[test]
    fn alphabet_membership() {
        let t = toggle();
        assert!(t.has_event(1));
        assert!(!t.has_event(2));
        assert!(!t.has_event(255));
    }
}
