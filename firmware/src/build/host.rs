//! This module is the home of [`HostTables`]: a set owned on the host, from which the runtime
//! borrows a [`SupervisorSet`] — how `codegen`'s virtual plant and the host tests run the very runtime
//! that ships.

use alloc::vec::Vec;

use super::{BuildError, Packed, SideTables};
use crate::table::{Automaton, SupervisorSet};

/// A set (in any layout) with its side tables, owned in the runtime's representation for
/// event bitsets of `W` words; [`HostTables::set`] lends the runtime its view.
///
/// `W` must be the set's word count (⌈events / 32⌉), as `EVENT_WORDS` of the emitted file; the
/// `[u32; W]` arrays and the blocks back to back that the runtime reads are built once, in
/// [`HostTables::new`].
///
/// ```
/// use firmware::build::{encode, HostTables, Source, SourceAutomaton};
///
/// // One plant over one controllable event: 0 –go→ 0.
/// let source = Source {
///     event_names: vec!["go".into()],
///     controllable: vec![true],
///     plants: 1,
///     automata: vec![SourceAutomaton { name: "G".into(), initial: 0, alphabet: vec![0], out: vec![vec![(0, 0)]] }],
/// };
/// let host = HostTables::<1>::new(encode(&source)?)?;
/// assert_eq!(host.set().check(1), Ok(()));
/// assert_eq!(host.set().step(0, 0, 0), Some(0));
/// # Ok::<(), firmware::build::BuildError>(())
/// ```
#[derive(Clone, Debug)]
pub struct HostTables<const W: usize> {
    /// The tables.
    pub packed: Packed,
    /// Their side tables.
    pub side: SideTables,
    automata: Vec<Automaton<W>>,
    block: Vec<u8>,
    masks: Vec<u32>,
    holder_lists: Vec<u16>,
    initials: Vec<u16>,
    plant_events: Vec<[u32; W]>,
    controllable: [u32; W],
}

impl<const W: usize> HostTables<W> {
    /// Computes the side tables of `packed` and the runtime's `W`-word arrays; refuses a set whose
    /// bitsets are not `W` words.
    pub fn new(packed: Packed) -> Result<Self, BuildError> {
        let side = SideTables::of(&packed)?;
        let words = packed.words();
        let array = |v: &[u32]| <[u32; W]>::try_from(v).map_err(|_| BuildError::Words { words, want: W });
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
            .collect::<Result<_, BuildError>>()?;
        let block = packed.automata.iter().flat_map(|b| b.block.iter().copied()).collect();
        let masks = packed.mask_pool();
        let holder_lists = packed.holder_lists();
        let initials = packed.initials();
        Ok(HostTables {
            packed,
            side,
            automata,
            block,
            masks,
            holder_lists,
            initials,
            plant_events,
            controllable,
        })
    }

    /// Event names by global id (not part of the runtime's tables).
    pub fn event_names(&self) -> &[alloc::string::String] {
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
            layout: self.packed.layout.id(),
            initials: &self.initials,
            holder_lists: &self.holder_lists,
            holders: &self.side.holders,
            plant_events: &self.plant_events,
            sites: &self.side.sites,
        }
    }
}
