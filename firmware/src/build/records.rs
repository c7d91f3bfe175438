//! The encoder of the `memory-safe` and `offset` layouts ([`crate::table::records`] describes both):
//! every state's record in state-index order, targets as state indices (the reference tool's vector, to
//! the byte) or as record offsets.

use alloc::vec::Vec;

use super::{bitset, Block, BuildError, Layout, Source, SourceAutomaton};
use crate::table::MAX_BLOCK;

/// Most transitions a record's count byte holds.
pub const MAX_TRANSITIONS: usize = 255;

/// The blocks of `source` in `layout` (`memory-safe` or `offset`), or the limit a set breaks: at most
/// [`MAX_TRANSITIONS`] per state and every record starting in the first 64 KiB of the blocks back to
/// back.
pub(super) fn encode(source: &Source, layout: Layout) -> Result<Vec<Block>, BuildError> {
    let events = source.event_names.len();
    let mut start = 0;
    let mut blocks = Vec::with_capacity(source.automata.len());
    for a in &source.automata {
        let offsets = offsets(a)?;
        let mut block = Vec::new();
        for edges in &a.out {
            // Counts ≤ 255 (`offsets`), event ids < 256 (`encode_as`), indices and offsets < 65 536
            // (below): the casts cannot truncate.
            block.push(edges.len() as u8);
            for &(e, t) in edges {
                let target = if layout == Layout::MemorySafe { t } else { offsets[t] };
                block.push(e as u8);
                block.extend_from_slice(&(target as u16).to_be_bytes());
            }
        }
        let last = offsets.last().copied().unwrap_or(0);
        if start + last >= MAX_BLOCK || a.out.len() > usize::from(u16::MAX) {
            return Err(BuildError::BlocksTooLarge {
                automaton: a.name.clone(),
                bytes: start + block.len(),
                limit: MAX_BLOCK,
            });
        }
        start += block.len();
        blocks.push(Block {
            name: a.name.clone(),
            initial: a.initial,
            handle: offsets.get(a.initial).map_or(0, |&o| o as u16),
            scale: 1,
            block,
            alphabet: bitset::from_ids(a.alphabet.iter().copied(), events),
        });
    }
    Ok(blocks)
}

/// The offset of every state's record from the automaton's start, refusing a state of more than
/// [`MAX_TRANSITIONS`] transitions.
fn offsets(a: &SourceAutomaton) -> Result<Vec<usize>, BuildError> {
    let mut at = 0;
    let mut offsets = Vec::with_capacity(a.out.len());
    for (s, edges) in a.out.iter().enumerate() {
        if edges.len() > MAX_TRANSITIONS {
            return Err(BuildError::TooManyTransitions {
                automaton: a.name.clone(),
                state: s,
                transitions: edges.len(),
                limit: MAX_TRANSITIONS,
            });
        }
        offsets.push(at);
        at += 1 + 3 * edges.len();
    }
    Ok(offsets)
}

/// Every state of a `memory-safe` or `offset` block: its record's offset and its out-events (a bitset
/// of `words` words), in state-index order.
pub(super) fn states(block: &[u8], words: usize) -> Vec<(usize, Vec<u32>)> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(&n) = block.get(at) {
        let end = (at + 1 + 3 * usize::from(n)).min(block.len());
        let events = block.get(at + 1..end).unwrap_or(&[]).iter().step_by(3).map(|&e| usize::from(e));
        let events = events.filter(|&e| e < 32 * words);
        out.push((at, bitset::from_ids(events, 32 * words)));
        at = end;
    }
    out
}
