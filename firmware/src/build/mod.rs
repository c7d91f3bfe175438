//! Building the tables on the host (feature `build`): the encoder of every layout ([`encode_as`]; the
//! `ranked` one is [`encode`], the others are in [`records`] and [`compact`]; the layouts themselves are
//! described once, in [`crate::table`]), the side tables of the runtime's hot path
//! ([`SideTables`]) and tables owned on the host that the runtime can borrow ([`HostTables`]).
//!
//! As regex-automata builds its DFAs with `dfa-build` and searches them `no_std`, the construction of
//! the tables lives here, beside their reader, behind a feature the firmware applications never enable:
//! `codegen` packs and emits with it, and the firmware's own tests build their tables with it, so there
//! is one encoder.
//!
//! # Overview
//!
//! * [`Source`] — a set as the encoder takes it: plants then supervisors over global event ids.
//! * [`encode`] — the [`Packed`] tables, or the [`BuildError`] naming the limit a set breaks;
//!   [`Packed::records`] reads a block back.
//! * [`SideTables`] — per event the automata holding it, per plant the controllable events it
//!   generates, the choice sites; [`unowned`] finds a controllable event no plant can generate.
//! * [`image`] — the set as the one image of bytes the firmware compiles
//!   ([`crate::table::image`]): written, checked with the runtime's own check, carried in Rust source.
//! * [`HostTables`] — the image owned on the host, lending the runtime a
//!   [`SupervisorSet`](crate::table::SupervisorSet).
//! * [`bitset`] — event bitsets of any word count, as the tables hold them.

pub mod bitset;
pub mod compact;
mod error;
mod host;
pub mod image;
mod ranked;
pub mod records;
mod side;

pub use error::{BuildError, ReadError};
pub use host::HostTables;
pub use ranked::{
    encode, encode_as, extent, position_bytes, smallest_scale, Block, Layout, Packed, Record, Source,
    SourceAutomaton, DESCRIPTOR_BYTES, MAX_POSITION, MAX_SCALE, MAX_STATES, NARROW_HANDLE, NARROW_IDS,
    WIDE_HANDLE,
};
pub use side::{unowned, SideTables};
