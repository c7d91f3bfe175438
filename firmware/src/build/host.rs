//! This module is the home of [`HostTables`]: a set owned on the host as the image the firmware
//! compiles ([`super::image`]), from which the runtime borrows a [`SupervisorSet`] — how `codegen`'s
//! virtual plant and the host tests run the very runtime that ships on the very bytes it reads.

use alloc::vec::Vec;
use core::marker::PhantomData;

use super::{image, BuildError, Packed, SideTables};
use crate::table::image::{header_bytes, read_slice};
use crate::table::{Position, SupervisorSet};

/// A set (in any layout) with its side tables, owned as its image for a runtime of `W`-word event
/// bitsets and positions of type `Q`; [`HostTables::set`] lends the runtime its view.
///
/// `W` must be the set's word count (⌈events / 32⌉), as `EVENT_WORDS` of the emitted file, and `Q` its
/// position type (`Position` there).
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
pub struct HostTables<const W: usize, Q = u16> {
    /// The tables.
    pub packed: Packed,
    /// Their side tables.
    pub side: SideTables,
    /// The image: header, then the sections.
    image: Vec<u8>,
    /// The sections again, in words: aligned as the firmware's static.
    sections: Vec<u32>,
    positions: PhantomData<Q>,
}

impl<const W: usize, Q: Position> HostTables<W, Q> {
    /// Computes the side tables and the image of `packed`; refuses a set whose bitsets are not `W` words
    /// or whose positions are not `Q`.
    pub fn new(packed: Packed) -> Result<Self, BuildError> {
        let side = SideTables::of(&packed)?;
        let words = packed.words();
        if words != W {
            return Err(BuildError::Words { words, want: W });
        }
        let bytes = (Q::BITS / 8) as usize;
        if packed.position_bytes != bytes {
            return Err(BuildError::Positions { bytes: packed.position_bytes, want: bytes });
        }
        let image = image::write(&packed, &side);
        let tail = image.get(header_bytes(W)..).unwrap_or_default();
        let sections =
            tail.chunks(4).map(|c| c.iter().rev().fold(0, |w, &b| w << 8 | u32::from(b))).collect();
        Ok(HostTables { packed, side, image, sections, positions: PhantomData })
    }

    /// Event names by global id (not part of the runtime's tables).
    pub fn event_names(&self) -> &[alloc::string::String] {
        &self.packed.event_names
    }

    /// The image the firmware compiles.
    pub fn image(&self) -> &[u8] {
        &self.image
    }

    /// The runtime's view of the tables, read off the image as the firmware reads it.
    pub fn set(&self) -> SupervisorSet<'_, W, Q> {
        let len = self.image.len() - header_bytes(W);
        // SAFETY: the words hold the sections' `len` bytes, little-endian as the image (the tables are
        // read on little-endian machines only, `crate::table`).
        let bytes = unsafe { core::slice::from_raw_parts(self.sections.as_ptr().cast::<u8>(), len) };
        match read_slice(&self.image, bytes, true) {
            Ok(set) => set,
            // `new` wrote the image for `W` and `Q`: it reads back.
            Err(e) => unreachable!("an image written for its own shape does not read back: {e:?}"),
        }
    }
}
