//! The side tables of an `offset` set that keep the runtime's hot path small: per event the automata
//! holding it, per controllable event the plant that generates it, and the choice sites of the local
//! policies (`firmware::table`); and [`HostTables`], the same set as runtime tables on the host.

use firmware::table::{Automaton, Role as RtRole, Site, SupervisorSet, MAX_AUTOMATA};

use crate::pack::offset::Packed;
use crate::pack::{PackError, Role};

/// Why a set cannot be emitted for the runtime.
#[derive(Debug, thiserror::Error)]
pub enum EmitError {
    /// The set breaks a limit of the `offset` layout.
    #[error(transparent)]
    Pack(#[from] PackError),
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

/// The side tables, in the runtime's representation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SideTables {
    /// Per global event id: bit `a` set when automaton `a` holds the event.
    pub holders: Vec<u32>,
    /// Per plant, a bitset: the controllable events it generates (of its alphabet, those no earlier
    /// plant holds).
    pub plant_events: Vec<u32>,
    /// Choice sites with two or more owned controllable out-events, sorted.
    pub sites: Vec<Site>,
}

/// Offsets of the states of an `offset` block, in state order.
pub fn state_offsets(block: &[u8]) -> Vec<u16> {
    let mut out = Vec::new();
    let mut at = 0usize;
    while let (Some(&n), Ok(off)) = (block.get(at), u16::try_from(at)) {
        out.push(off);
        at += 1 + 3 * usize::from(n);
    }
    out
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
        let holders = (0..events)
            .map(|e| {
                packed
                    .automata
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| has(&b.alphabet, e))
                    .map(|(a, _)| 1 << a)
                    .sum()
            })
            .collect();
        let plants: Vec<_> = packed.automata.iter().take_while(|b| b.role == Role::Plant).collect();
        let mut owner = vec![None; events];
        for (e, o) in owner.iter_mut().enumerate().filter(|(e, _)| has(&packed.controllable, *e)) {
            match plants.iter().position(|b| has(&b.alphabet, e)) {
                Some(p) => *o = Some(p),
                None => return Err(EmitError::Unowned { event: packed.event_names[e].clone() }),
            }
        }
        let words = packed.controllable.len();
        let mut plant_events = vec![0u32; words * plants.len()];
        for (e, o) in owner.iter().enumerate() {
            if let Some(p) = o {
                plant_events[p * words + e / 32] |= 1 << (e % 32);
            }
        }
        let mut sites = Vec::new();
        for (p, b) in plants.iter().enumerate() {
            // At most MAX_AUTOMATA (32) automata, so the index fits.
            let automaton = u8::try_from(p).unwrap_or(u8::MAX);
            for state in state_offsets(&b.block) {
                let at = usize::from(state);
                let n = usize::from(b.block[at]);
                let generated = b.block[at + 1..at + 1 + 3 * n]
                    .chunks_exact(3)
                    .filter(|r| owner[usize::from(r[0])] == Some(p));
                if generated.count() >= 2 {
                    sites.push(Site { automaton, state });
                }
            }
        }
        Ok(SideTables { holders, plant_events, sites })
    }
}

/// A packed set with its side tables, owned on the host, from which a runtime [`SupervisorSet`] can be
/// borrowed: the virtual plant and the host tests run the firmware's runtime on it.
///
/// ```
/// # use codegen::{emit::HostTables, pack::{offset, PackSet}};
/// # fn borrow(set: &PackSet) -> Result<(), Box<dyn std::error::Error>> {
/// let host = HostTables::new(offset::encode(set)?)?;
/// let (names, automata) = (host.names(), host.automata());
/// let runtime_set = host.set(&names, &automata);
/// # let _ = runtime_set;
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct HostTables {
    /// The `offset` tables.
    pub packed: Packed,
    /// Their side tables.
    pub side: SideTables,
}

impl HostTables {
    /// Computes the side tables of `packed`.
    pub fn new(packed: Packed) -> Result<HostTables, EmitError> {
        let side = SideTables::of(&packed)?;
        Ok(HostTables { packed, side })
    }

    /// Event names as the runtime holds them.
    pub fn names(&self) -> Vec<&str> {
        self.packed.event_names.iter().map(String::as_str).collect()
    }

    /// Automata as the runtime holds them.
    pub fn automata(&self) -> Vec<Automaton<'_>> {
        self.packed
            .automata
            .iter()
            .map(|b| Automaton {
                name: &b.name,
                role: match b.role {
                    Role::Plant => RtRole::Plant,
                    Role::Supervisor => RtRole::Supervisor,
                },
                initial: b.initial,
                block: &b.block,
                alphabet: &b.alphabet,
            })
            .collect()
    }

    /// The runtime's view, over `names` and `automata` from [`HostTables::names`] and
    /// [`HostTables::automata`].
    pub fn set<'a>(&'a self, names: &'a [&'a str], automata: &'a [Automaton<'a>]) -> SupervisorSet<'a> {
        SupervisorSet {
            event_names: names,
            controllable: &self.packed.controllable,
            automata,
            holders: &self.side.holders,
            plant_events: &self.side.plant_events,
            sites: &self.side.sites,
        }
    }
}
