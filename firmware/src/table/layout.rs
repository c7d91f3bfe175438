//! This module is the home of the layout ids: which reader the runtime compiles in. The id is the
//! runtime's and [`super::CheckedSet`]'s `LAYOUT` const parameter and the set's
//! [`super::SupervisorSet::layout`] field, so that one runtime and one event loop run every layout and
//! each build carries only its own reader.

/// A target per event of the state's out-mask, the target found by the event's rank in it.
pub const RANKED: u8 = 0;
/// A target per event of the alphabet, the target found by the event's place in it (holder lists).
pub const INDEXED: u8 = 1;
/// The reference tool's vector, targets as state indices: a step walks to the target's record.
pub const MEMORY_SAFE: u8 = 2;
/// The reference tool's records, targets as record offsets: a step jumps.
pub const OFFSET: u8 = 3;
/// Bit-packed over local alphabets, with a directory every 16 states.
pub const COMPACT: u8 = 4;

/// Every layout id, in the size report's order.
pub const ALL: [u8; 5] = [MEMORY_SAFE, OFFSET, RANKED, INDEXED, COMPACT];

/// The name `codegen` gives layout `id` (`--layout`, the manifest's `[runtime] layout`).
pub const fn name(id: u8) -> &'static str {
    match id {
        RANKED => "ranked",
        INDEXED => "indexed",
        MEMORY_SAFE => "memory-safe",
        OFFSET => "offset",
        COMPACT => "compact",
        _ => "unknown",
    }
}

/// Whether the layout's records name pool masks ([`super::SupervisorSet::masks`]) and have a field width.
pub const fn has_pool(id: u8) -> bool {
    id == RANKED || id == INDEXED
}
