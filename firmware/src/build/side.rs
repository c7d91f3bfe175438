//! The side tables of a `ranked` set that keep the runtime's hot path small: per event the automata
//! holding it, per plant the controllable events it generates, and the choice sites of the local
//! policies ([`crate::table::SupervisorSet`]).

use alloc::vec;
use alloc::vec::Vec;

use super::{bitset, BuildError, Packed};
use crate::table::{holder_bytes, MAX_AUTOMATA};

/// The side tables, in the runtime's representation (bitsets as `Vec<u32>` of the set's word count).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SideTables {
    /// Per global event id, [`holder_bytes`] bytes little-endian: bit `a` set when automaton `a` holds
    /// the event.
    pub holders: Vec<u8>,
    /// Number of plants: the first automata.
    pub plants: u8,
    /// Per plant, a bitset: the controllable events it generates (of its alphabet, those no earlier
    /// plant holds).
    pub plant_events: Vec<Vec<u32>>,
    /// Choice sites (plant states with two or more generated controllable out-events), each as its
    /// position in the blocks back to back (its record's offset; its mask's bit offset in `compact`),
    /// ascending.
    pub sites: Vec<usize>,
}

/// The plant that generates each global event: the first plant holding it, for controllable events
/// only.
fn owners(packed: &Packed) -> Vec<Option<usize>> {
    let plants = &packed.automata[..packed.plants.min(packed.automata.len())];
    (0..packed.event_names.len())
        .map(|e| {
            let controllable = bitset::contains(&packed.controllable, e);
            plants.iter().position(|b| bitset::contains(&b.alphabet, e)).filter(|_| controllable)
        })
        .collect()
}

/// The first controllable event of `packed` that no plant has in its alphabet: nothing can generate
/// it, so the runtime never fires it.
pub fn unowned(packed: &Packed) -> Option<usize> {
    let owners = owners(packed);
    (0..packed.event_names.len()).find(|&e| bitset::contains(&packed.controllable, e) && owners[e].is_none())
}

impl SideTables {
    /// Computes the side tables of `packed`, or says which runtime limit it breaks. A controllable event
    /// no plant holds ([`unowned`]) is in no plant's events.
    pub fn of(packed: &Packed) -> Result<SideTables, BuildError> {
        let count = packed.automata.len();
        if count > MAX_AUTOMATA {
            return Err(BuildError::TooManyAutomata { count, limit: MAX_AUTOMATA });
        }
        let events = packed.event_names.len();
        let width = holder_bytes(count);
        let holders = (0..events)
            .flat_map(|e| {
                let mask: u32 = packed
                    .automata
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| bitset::contains(&b.alphabet, e))
                    .map(|(a, _)| 1u32 << a)
                    .sum();
                mask.to_le_bytes().into_iter().take(width)
            })
            .collect();
        let plants = packed.plants.min(count);
        let owner = owners(packed);
        let mut plant_events = vec![vec![0u32; packed.words()]; plants];
        for (e, o) in owner.iter().enumerate() {
            if let Some(p) = o {
                plant_events[*p][e / 32] |= 1 << (e % 32);
            }
        }
        let mut sites = Vec::new();
        let unit = packed.position_unit();
        for (p, start) in packed.starts().into_iter().enumerate().take(plants) {
            for (at, out) in packed.state_positions(p)? {
                let generated =
                    (0..events).filter(|&e| bitset::contains(&out, e) && owner[e] == Some(p)).count();
                if generated >= 2 {
                    sites.push(unit * start + at);
                }
            }
        }
        // At most MAX_AUTOMATA automata, so the count fits.
        Ok(SideTables { holders, plants: plants as u8, plant_events, sites })
    }
}
