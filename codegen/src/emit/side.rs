//! The side tables of a `ranked` set that keep the runtime's hot path small: per event the automata
//! holding it, per plant the controllable events it generates, and the choice sites of the local policies
//! (`firmware::table`); and [`HostTables`], the same set as runtime tables on the host.

use firmware::table::{holder_bytes, Automaton, SupervisorSet, MAX_AUTOMATA};

use crate::pack::ranked::Packed;
use crate::pack::{DecodeError, PackError, Role};

/// Why a set cannot be emitted for the runtime.
#[derive(Debug, thiserror::Error)]
pub enum EmitError {
    /// The set breaks a limit of the `ranked` layout.
    #[error(transparent)]
    Pack(#[from] PackError),
    /// The packed tables do not read back (only tables built by hand or altered after packing).
    #[error(transparent)]
    Tables(#[from] DecodeError),
    /// More automata than the runtime's per-event holder mask has bits.
    #[error("the set has {count} automata, more than the runtime's limit of {limit}")]
    TooManyAutomata {
        /// Automata in the set.
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// A controllable event no plant has in its alphabet: nothing can generate it.
    #[error("controllable event '{event}' belongs to no plant, so the product system cannot generate it")]
    Unowned {
        /// Event name.
        event: String,
    },
    /// The host runtime was asked for event bitsets of another word count than the set's.
    #[error("the set's event bitsets take {words} words, the runtime was built for {want}")]
    Words {
        /// Words of the set's bitsets.
        words: usize,
        /// Words the runtime's `W` says.
        want: usize,
    },
    /// The `[board]` section does not fit the set.
    #[error(transparent)]
    Board(#[from] super::BoardError),
    /// The input buffer capacity is 0 or too large for the firmware's queue.
    #[error("input buffer of {capacity} events: it must hold 1 to 65535")]
    InputBuffer {
        /// The capacity asked for.
        capacity: usize,
    },
}

/// The side tables, in the runtime's representation (bitsets as `Vec<u32>` of the set's word count).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SideTables {
    /// Per global event id, `firmware::table::holder_bytes` bytes little-endian: bit `a` set when
    /// automaton `a` holds the event.
    pub holders: Vec<u8>,
    /// Number of plants: the first automata.
    pub plants: u8,
    /// Per plant, a bitset: the controllable events it generates (of its alphabet, those no earlier
    /// plant holds).
    pub plant_events: Vec<Vec<u32>>,
    /// Choice sites (plant states with two or more owned controllable out-events), each as the offset
    /// of its record in the blocks back to back, ascending.
    pub sites: Vec<u16>,
}

fn has(words: &[u32], e: usize) -> bool {
    words.get(e / 32).is_some_and(|w| w & (1 << (e % 32)) != 0)
}

impl SideTables {
    /// Computes the side tables of `packed`, or says which runtime limit it breaks.
    pub fn of(packed: &Packed) -> Result<SideTables, EmitError> {
        let count = packed.automata.len();
        if count > MAX_AUTOMATA {
            return Err(EmitError::TooManyAutomata { count, limit: MAX_AUTOMATA });
        }
        let events = packed.event_names.len();
        let width = holder_bytes(count);
        let holders = (0..events)
            .flat_map(|e| {
                let mask: u32 = packed
                    .automata
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| has(&b.alphabet, e))
                    .map(|(a, _)| 1u32 << a)
                    .sum();
                mask.to_le_bytes().into_iter().take(width)
            })
            .collect();
        let plants = packed.automata.iter().take_while(|b| b.role == Role::Plant).count();
        let mut owner = vec![None; events];
        for (e, o) in owner.iter_mut().enumerate().filter(|(e, _)| has(&packed.controllable, *e)) {
            match packed.automata[..plants].iter().position(|b| has(&b.alphabet, e)) {
                Some(p) => *o = Some(p),
                None => return Err(EmitError::Unowned { event: packed.event_names[e].clone() }),
            }
        }
        let words = packed.words();
        let mut plant_events = vec![vec![0u32; words]; plants];
        for (e, o) in owner.iter().enumerate() {
            if let Some(p) = o {
                plant_events[*p][e / 32] |= 1 << (e % 32);
            }
        }
        let mut sites = Vec::new();
        for (p, start) in packed.starts().into_iter().enumerate().take(plants) {
            for r in packed.records(p)? {
                let mask = packed.masks.get(r.mask).map_or(&[][..], Vec::as_slice);
                let generated = (0..events).filter(|&e| has(mask, e) && owner[e] == Some(p)).count();
                if generated >= 2 {
                    // Records start in the first 64 KiB of the blocks back to back (`encode`).
                    sites.push((start + r.at) as u16);
                }
            }
        }
        // At most MAX_AUTOMATA automata, so the count fits.
        Ok(SideTables { holders, plants: plants as u8, plant_events, sites })
    }
}

/// A `ranked` set with its side tables, owned on the host in the runtime's representation for event
/// bitsets of `W` words, from which a runtime [`SupervisorSet`] is borrowed: the virtual plant and the
/// host tests run the firmware's runtime on it.
///
/// `W` must be the set's word count (⌈events / 32⌉), as `EVENT_WORDS` of the emitted file; the
/// `[u32; W]` arrays and the blocks back to back that the runtime reads are built once, in
/// [`HostTables::new`].
///
/// ```
/// # use codegen::{emit::HostTables, pack::{ranked, PackSet}};
/// # fn borrow(set: &PackSet) -> Result<(), Box<dyn std::error::Error>> {
/// let host = HostTables::<1>::new(ranked::encode(set)?)?;
/// let runtime_set = host.set();
/// # let _ = runtime_set;
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct HostTables<const W: usize> {
    /// The `ranked` tables.
    pub packed: Packed,
    /// Their side tables.
    pub side: SideTables,
    automata: Vec<Automaton<W>>,
    block: Vec<u8>,
    masks: Vec<u8>,
    plant_events: Vec<[u32; W]>,
    controllable: [u32; W],
}

impl<const W: usize> HostTables<W> {
    /// Computes the side tables of `packed` and the runtime's `W`-word arrays; refuses a set whose
    /// bitsets are not `W` words.
    pub fn new(packed: Packed) -> Result<Self, EmitError> {
        let side = SideTables::of(&packed)?;
        let words = packed.words();
        let array = |v: &[u32]| <[u32; W]>::try_from(v).map_err(|_| EmitError::Words { words, want: W });
        let controllable = array(&packed.controllable)?;
        let plant_events = side.plant_events.iter().map(|m| array(m)).collect::<Result<_, _>>()?;
        // `encode` kept every record start, hence every start, below 64 KiB.
        let automata = packed
            .automata
            .iter()
            .zip(packed.starts())
            .map(|(b, start)| {
                Ok(Automaton { alphabet: array(&b.alphabet)?, start: start as u16, scale: b.scale })
            })
            .collect::<Result<_, EmitError>>()?;
        let block = packed.automata.iter().flat_map(|b| b.block.iter().copied()).collect();
        let masks = packed.mask_pool();
        Ok(HostTables { packed, side, automata, block, masks, plant_events, controllable })
    }

    /// Event names by global id (not part of the runtime's tables).
    pub fn event_names(&self) -> &[String] {
        &self.packed.event_names
    }

    /// The runtime's view of the tables.
    pub fn set(&self) -> SupervisorSet<'_, W> {
        SupervisorSet {
            controllable: self.controllable,
            plants: self.side.plants,
            automata: &self.automata,
            block: &self.block,
            wide: self.packed.wide,
            masks: &self.masks,
            // At most 256 events: 32 bytes.
            mask_bytes: self.packed.mask_width() as u8,
            holders: &self.side.holders,
            plant_events: &self.plant_events,
            sites: &self.side.sites,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::{ranked, PackSet};

    #[test]
    fn host_tables_pass_the_runtime_check_and_refuse_another_width() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S")]).unwrap();
        let host = HostTables::<1>::new(ranked::encode(&set).unwrap()).unwrap();
        let rt = host.set();
        assert_eq!(rt.check(2), Ok(()));
        assert_eq!(rt.plants, 1);
        assert_eq!((rt.automata[1].start, rt.block.len()), (4, 8));
        let after_a = rt.step(1, 0, 0).unwrap();
        assert_eq!(rt.step(1, after_a, 1), Some(0));
        let err = HostTables::<2>::new(ranked::encode(&set).unwrap()).unwrap_err();
        assert_eq!(err.to_string(), "the set's event bitsets take 1 words, the runtime was built for 2");
    }

    #[test]
    fn a_site_is_a_plant_state_with_two_owned_controllable_events() {
        use crate::model::{Automaton, Kind};
        let mut g = Automaton::new("G", Kind::Plant);
        let s0 = g.add_state("0", true).unwrap();
        let s1 = g.add_state("1", false).unwrap();
        let a = g.add_event("a", true).unwrap();
        let b = g.add_event("b", true).unwrap();
        let u = g.add_event("u", false).unwrap();
        g.initial = Some(s0);
        g.add_transition(s0, a, s1);
        g.add_transition(s0, b, s1);
        g.add_transition(s1, u, s0);
        g.add_transition(s1, a, s1);
        let packed = ranked::encode(&PackSet::new(vec![g.clone()], vec![]).unwrap()).unwrap();
        let side = SideTables::of(&packed).unwrap();
        assert_eq!(side.sites, [0]);
        assert_eq!(side.plant_events, [vec![0b011]]);
        assert_eq!(side.holders, [1, 1, 1]);
        // Sites are offsets in the blocks back to back (after H's record of 2 bytes); holder masks take a
        // byte per 8 automata.
        let mut h = Automaton::new("H", Kind::Plant);
        let q = h.add_state("0", true).unwrap();
        let x = h.add_event("x", false).unwrap();
        h.initial = Some(q);
        h.add_transition(q, x, q);
        let sups = (0..8)
            .map(|i| {
                let mut s = h.clone();
                s.name = format!("S{i}");
                s
            })
            .collect();
        let set = PackSet::new(vec![h, g], sups);
        let side = SideTables::of(&ranked::encode(&set.unwrap()).unwrap()).unwrap();
        assert_eq!(side.sites, [2]);
        assert_eq!(side.holders.len(), 2 * 4);
    }
}
