//! The encoder of the `memory-safe` and `offset` layouts ([`crate::table::records`] describes both):
//! every state's record in state-index order, targets as state indices (the reference tool's vector, to
//! the byte) or as record offsets — of 2 bytes, or of 4 in every record when an automaton's records
//! span more than 64 KiB (wide fields).

use alloc::vec::Vec;

use super::{bitset, Block, BuildError, Layout, Source, SourceAutomaton, MAX_POSITION};

/// Most transitions a record's count byte holds.
pub const MAX_TRANSITIONS: usize = 255;
/// Most states of a `memory-safe` automaton: a target is a 2-byte state index (the reference tool's
/// limit, as it states it).
pub const MAX_STATES: usize = 65_535;

/// The blocks of `source` in `layout` (`memory-safe` or `offset`), whether their targets are wide (4
/// bytes, `offset` only) and the largest position, or the limit a set breaks: at most
/// [`MAX_TRANSITIONS`] per state, [`MAX_STATES`] states per `memory-safe` automaton.
pub(super) fn encode(source: &Source, layout: Layout) -> Result<(bool, Vec<Block>, usize), BuildError> {
    let events = source.event_names.len();
    for a in &source.automata {
        if layout == Layout::MemorySafe && a.out.len() > MAX_STATES {
            return Err(BuildError::TooManyStates {
                automaton: a.name.clone(),
                states: a.out.len(),
                limit: MAX_STATES,
            });
        }
    }
    // Offsets of 2 bytes while every automaton's last record starts below 64 KiB.
    let narrow = source.automata.iter().map(|a| offsets(a, 3)).collect::<Result<Vec<_>, _>>()?;
    let wide = layout == Layout::Offset && narrow.iter().any(|o| o.last().is_some_and(|&l| l > 0xFFFF));
    let target = if wide { 4 } else { 2 };
    let (mut start, mut last) = (0, 0);
    let mut blocks = Vec::with_capacity(source.automata.len());
    for a in &source.automata {
        let offsets = offsets(a, 1 + target)?;
        let mut block = Vec::new();
        for edges in &a.out {
            // Counts ≤ 255 (`offsets`), event ids < 256 (`encode_as`), indices < 65 536 (above) and
            // offsets within the target's bytes: the casts cannot truncate.
            block.push(edges.len() as u8);
            for &(e, t) in edges {
                block.push(e as u8);
                match (layout, wide) {
                    (Layout::MemorySafe, _) => block.extend_from_slice(&(t as u16).to_be_bytes()),
                    (_, false) => block.extend_from_slice(&(offsets[t] as u16).to_be_bytes()),
                    (_, true) => block.extend_from_slice(&(offsets[t] as u32).to_be_bytes()),
                }
            }
        }
        let end = offsets.last().copied().unwrap_or(0);
        if start + end > MAX_POSITION {
            return Err(BuildError::BlocksTooLarge {
                automaton: a.name.clone(),
                bytes: start + block.len(),
                limit: MAX_POSITION + 1,
            });
        }
        last = start + end;
        start += block.len();
        blocks.push(Block {
            name: a.name.clone(),
            initial: a.initial,
            handle: offsets.get(a.initial).copied().unwrap_or(0),
            scale: 1,
            block,
            alphabet: bitset::from_ids(a.alphabet.iter().copied(), events),
        });
    }
    Ok((wide, blocks, last))
}

/// The offset of every state's record from the automaton's start, transitions of `transition` bytes,
/// refusing a state of more than [`MAX_TRANSITIONS`] transitions.
fn offsets(a: &SourceAutomaton, transition: usize) -> Result<Vec<usize>, BuildError> {
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
        at += 1 + transition * edges.len();
    }
    Ok(offsets)
}

/// Every state of a `memory-safe` or `offset` block, transitions of `transition` bytes: its record's
/// offset and its out-events (a bitset of `words` words), in state-index order.
pub(super) fn states(block: &[u8], transition: usize, words: usize) -> Vec<(usize, Vec<u32>)> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(&n) = block.get(at) {
        let end = (at + 1 + transition * usize::from(n)).min(block.len());
        let events =
            block.get(at + 1..end).unwrap_or(&[]).iter().step_by(transition).map(|&e| usize::from(e));
        let events = events.filter(|&e| e < 32 * words);
        out.push((at, bitset::from_ids(events, 32 * words)));
        at = end;
    }
    out
}
