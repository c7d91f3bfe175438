//! The encoder of the `compact` layout ([`crate::table::compact`] describes it): per automaton a header,
//! a directory of every 16th state's bit offset and the bit stream of masks and targets, the block
//! ending with the padding the runtime's 3-byte field reads need.

use alloc::vec::Vec;

use super::{bitset, Block, BuildError, Source, MAX_POSITION};
use crate::table::compact::{HEADER, PADDING, STRIDE};

/// Most states of a `compact` automaton: a u16 state count.
pub const MAX_STATES: usize = 65_535;

/// Bits needed to write every value in `0..n` (0 when `n` ≤ 1).
pub fn width(n: usize) -> u32 {
    match n {
        0 | 1 => 0,
        _ => usize::BITS - (n - 1).leading_zeros(),
    }
}

/// Appends fields to a byte vector, most significant bit first.
#[derive(Default)]
pub struct Writer {
    bytes: Vec<u8>,
    len: usize,
}

impl Writer {
    /// Appends the low `bits` bits of `value`.
    pub fn put(&mut self, value: usize, bits: u32) {
        for i in (0..bits).rev() {
            if self.len.is_multiple_of(8) {
                self.bytes.push(0);
            }
            if (value >> i) & 1 == 1 {
                if let Some(last) = self.bytes.last_mut() {
                    *last |= 0x80 >> (self.len % 8);
                }
            }
            self.len += 1;
        }
    }

    /// Bits written so far.
    pub fn bit_len(&self) -> usize {
        self.len
    }

    /// The bytes, the last one padded with zero bits.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }
}

/// The blocks of `source` in the `compact` layout (no wide fields) and the largest position (a bit
/// offset), or the limit a set breaks.
pub(super) fn encode(source: &Source) -> Result<(bool, Vec<Block>, usize), BuildError> {
    let events = source.event_names.len();
    let mut blocks: Vec<Block> = Vec::with_capacity(source.automata.len());
    let (mut total, mut last) = (0, 0);
    for a in &source.automata {
        let s = a.out.len();
        if s > MAX_STATES || s == 0 {
            return Err(BuildError::TooManyStates {
                automaton: a.name.clone(),
                states: s,
                limit: MAX_STATES,
            });
        }
        let alphabet: Vec<usize> =
            bitset::ids(&bitset::from_ids(a.alphabet.iter().copied(), events)).collect();
        let w = width(s);
        let mut stream = Writer::default();
        let mut starts = Vec::with_capacity(s);
        for edges in &a.out {
            starts.push(stream.bit_len());
            for e in &alphabet {
                stream.put(usize::from(edges.iter().any(|(x, _)| x == e)), 1);
            }
            for &(_, t) in edges {
                stream.put(t, w);
            }
        }
        let stream = stream.into_bytes();
        let d = width(stream.len() * 8 + 1);
        let mut directory = Writer::default();
        for &start in starts.iter().skip(STRIDE).step_by(STRIDE) {
            directory.put(start, d);
        }
        let directory = directory.into_bytes();
        let directory_len = directory.len();
        let mut block = Vec::with_capacity(HEADER + directory.len() + stream.len());
        // s ≤ 65 535, the alphabet ≤ 256 events, widths ≤ 32 bits (positions are checked below), the
        // directory at most 4 bytes per 16 states: the casts cannot truncate.
        block.extend_from_slice(&(s as u16).to_le_bytes());
        block.extend_from_slice(&(alphabet.len() as u16).to_le_bytes());
        block.extend_from_slice(&[w as u8, d as u8]);
        block.extend_from_slice(&(directory.len() as u16).to_le_bytes());
        block.extend(directory);
        block.extend(stream);
        let stream_at = 8 * (total + HEADER + directory_len);
        last = stream_at + starts.last().copied().unwrap_or(0);
        total += block.len();
        if last > MAX_POSITION {
            return Err(BuildError::BlocksTooLarge {
                automaton: a.name.clone(),
                bytes: total,
                limit: MAX_POSITION.div_ceil(8),
            });
        }
        blocks.push(Block {
            name: a.name.clone(),
            initial: a.initial,
            handle: starts.get(a.initial).copied().unwrap_or(0),
            scale: 1,
            block,
            alphabet: bitset::from_ids(a.alphabet.iter().copied(), events),
        });
    }
    if let Some(end) = blocks.last_mut() {
        end.block.extend_from_slice(&[0; PADDING]);
    }
    Ok((false, blocks, last))
}

/// Every state of a `compact` block: its mask's bit offset from the block's start and its out-events (a
/// bitset of `words` words), in state-index order; `alphabet` is the automaton's.
pub(super) fn states(block: &[u8], alphabet: &[u32], words: usize) -> Vec<(usize, Vec<u32>)> {
    let bit = |pos: usize| block.get(pos / 8).map_or(0, |b| (b >> (7 - pos % 8)) & 1);
    let header = |i: usize| usize::from(block.get(i).copied().unwrap_or(0));
    let (s, w) = (header(0) | header(1) << 8, header(4) as u32);
    let ids: Vec<usize> = bitset::ids(alphabet).filter(|&e| e < 32 * words).collect();
    let mut p = 8 * (HEADER + (header(6) | header(7) << 8));
    let mut out = Vec::with_capacity(s);
    for _ in 0..s {
        let present: Vec<usize> =
            ids.iter().enumerate().filter(|&(l, _)| bit(p + l) == 1).map(|(_, &e)| e).collect();
        out.push((p, bitset::from_ids(present.iter().copied(), 32 * words)));
        p += ids.len() + present.len() * w as usize;
    }
    out
}
