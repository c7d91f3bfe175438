//! This module is the home of the reader of the `compact` layout: bit-packed, each automaton over its
//! own alphabet (the size report's densest layout, `codegen pack`'s `compact` streams and directories).
//!
//! An automaton of `s` states over an alphabet of `a` events numbers its events locally `0..a` (in
//! global-id order); a state takes `w = ⌈log₂ s⌉` bits. From its start ([`super::Automaton::start`]) its
//! part of the block holds a header, a directory and a bit stream (most significant bit first):
//!
//! ```text
//! [s: u16 LE][a: u16 LE][w: u8][d: u8][directory bytes: u16 LE]
//! [directory: the bit offset in the stream of states 16, 32, …, d bits each]
//! [stream: per state, an a-bit mask (bit i: local event i leaves it), then per set bit its target's
//!  index in w bits]
//! ```
//!
//! A state's position is the bit offset of its mask in the block (so the block is at most 8 KiB with
//! 16-bit positions, 512 MiB with 32-bit ones, [`super::Position`]), its handle the bit offset in its
//! automaton's stream; a directory entry takes at most as many bits as a position. A step ranks the event's local place in the mask,
//! reads the target's index, jumps to the nearest directory entry and skips at most 15 states by the
//! popcounts of their masks: bounded work whatever `s` is. The block ends with two bytes of padding, so
//! that every field is read with three byte loads.

use super::{place, Automaton, Event, Position, SupervisorSet};

/// Bytes of an automaton's header.
pub const HEADER: usize = 8;
/// Every `STRIDE`-th state has a directory entry.
pub const STRIDE: usize = 16;
/// Widest field one read takes: a target (a state index), or a directory entry of a set with 16-bit
/// positions.
const MAX_FIELD: u32 = 16;
/// Bytes of padding after the last stream: a field read loads 3 bytes.
pub const PADDING: usize = 2;

/// An automaton's header: the alphabet size, field widths and where its directory and stream start.
#[derive(Clone, Copy)]
struct Shape {
    states: usize,
    alphabet: usize,
    w: u32,
    d: u32,
    directory: usize,
    stream: usize,
}

/// The `n` bits (n ≤ 16) at bit `pos` of `block`, most significant first, if its 3 bytes from
/// `pos / 8` lie in the block (the checked reader).
const fn bits_checked(block: &[u8], pos: usize, n: u32) -> Option<usize> {
    let at = pos / 8;
    if n > MAX_FIELD || at + 2 >= block.len() {
        return None;
    }
    let word = (block[at] as u32) << 16 | (block[at + 1] as u32) << 8 | block[at + 2] as u32;
    Some((word >> (24 - (pos % 8) as u32 - n) & ((1 << n) - 1)) as usize)
}

/// The `n` bits (n ≤ 16) at bit `pos` of `block`, most significant first.
///
/// # Safety
///
/// The 3 bytes from `pos / 8` lie in the block.
#[inline(always)]
unsafe fn bits(block: &[u8], pos: usize, n: u32) -> usize {
    let at = pos / 8;
    // SAFETY: the caller's promise.
    let word = unsafe {
        u32::from(*block.get_unchecked(at)) << 16
            | u32::from(*block.get_unchecked(at + 1)) << 8
            | u32::from(*block.get_unchecked(at + 2))
    };
    (word >> (24 - (pos % 8) as u32 - n) & ((1 << n) - 1)) as usize
}

/// The `n` bits (n ≤ 32) at bit `pos` of `block`, most significant first: a directory entry, which
/// takes more than 16 bits only with 32-bit positions (`Q`), read in two parts then.
///
/// # Safety
///
/// As for [`bits`], for the first 16 and the last `n − 16` bits when `n` > 16.
#[inline(always)]
unsafe fn entry<Q: Position>(block: &[u8], pos: usize, n: u32) -> usize {
    // SAFETY: the caller's promise.
    unsafe {
        if Q::BITS > MAX_FIELD && n > MAX_FIELD {
            bits(block, pos, MAX_FIELD) << (n - MAX_FIELD)
                | bits(block, pos + MAX_FIELD as usize, n - MAX_FIELD)
        } else {
            bits(block, pos, n)
        }
    }
}

/// The `n` bits (n ≤ 32) at bit `pos` of `block`, most significant first, if they lie in the block
/// (the checked reader of a directory entry).
fn entry_checked(block: &[u8], pos: usize, n: u32) -> Option<usize> {
    if n > MAX_FIELD {
        let high = bits_checked(block, pos, MAX_FIELD)?;
        Some(high << (n - MAX_FIELD) | bits_checked(block, pos + MAX_FIELD as usize, n - MAX_FIELD)?)
    } else {
        bits_checked(block, pos, n)
    }
}

/// The set bits among the `n` bits at bit `pos` of `block`.
///
/// # Safety
///
/// As for [`bits`], for every 16-bit field of the `n` bits.
#[inline(always)]
unsafe fn ones(block: &[u8], pos: usize, n: usize) -> usize {
    let (mut count, mut i) = (0, 0);
    while i < n {
        let chunk = (n - i).min(MAX_FIELD as usize);
        // SAFETY: the caller's promise; `chunk` ≤ 16.
        count += unsafe { bits(block, pos + i, chunk as u32) }.count_ones() as usize;
        i += chunk;
    }
    count
}

impl<const W: usize, Q: Position> SupervisorSet<'_, W, Q> {
    /// The header of the automaton starting at byte `start`, if it lies in the block (the checked
    /// reader).
    fn shape(&self, start: usize) -> Option<Shape> {
        if start + HEADER > self.block.len() {
            return None;
        }
        let b = self.block;
        let dir = u16::from_le_bytes([b[start + 6], b[start + 7]]) as usize;
        Some(Shape {
            states: u16::from_le_bytes([b[start], b[start + 1]]) as usize,
            alphabet: u16::from_le_bytes([b[start + 2], b[start + 3]]) as usize,
            w: b[start + 4] as u32,
            d: b[start + 5] as u32,
            directory: start + HEADER,
            stream: start + HEADER + dir,
        })
    }

    /// The bit offset in the stream of the state after the one at bit `p`, and the first of its targets
    /// at or beyond `states`, if any (`usize::MAX` when none), if its fields lie in the block.
    fn next_state(&self, sh: &Shape, p: usize) -> Option<(usize, usize)> {
        let base = 8 * sh.stream;
        let (mut pop, mut i) = (0, 0);
        while i < sh.alphabet {
            let chunk = if sh.alphabet - i < 16 { sh.alphabet - i } else { 16 };
            match bits_checked(self.block, base + p + i, chunk as u32) {
                Some(x) => pop += x.count_ones() as usize,
                None => return None,
            }
            i += chunk;
        }
        let mut bad = usize::MAX;
        let mut r = 0;
        while r < pop {
            match bits_checked(self.block, base + p + sh.alphabet + r * sh.w as usize, sh.w) {
                Some(t) if t < sh.states => {}
                Some(t) => {
                    if bad == usize::MAX {
                        bad = t;
                    }
                }
                None => return None,
            }
            r += 1;
        }
        Some((p + sh.alphabet + pop * sh.w as usize, bad))
    }

    /// One automaton of a `compact` set: its header fits its alphabet, the directory its size, every
    /// state's fields lie in its part with two bytes to spare in the block, every target is below the
    /// state count, every directory entry is its state's offset, every position fits 16 bits and the
    /// initial handle is a state's. Linear in the part's size.
    pub(super) fn compact_sound(&self, a: usize) -> bool {
        let (start, end) = self.part(a);
        let aut = &self.automata[a];
        let Some(sh) = self.shape(start) else { return false };
        let mut n = 0;
        let mut w = 0;
        while w < W {
            n += aut.alphabet[w].count_ones() as usize;
            w += 1;
        }
        let entries = if sh.states == 0 { 0 } else { (sh.states - 1) / STRIDE };
        if sh.states == 0
            || aut.scale != 1
            || sh.alphabet != n
            || sh.w > MAX_FIELD
            || (sh.states - 1) >> sh.w != 0
            || sh.d > Q::BITS
            || sh.stream - sh.directory != (entries * sh.d as usize).div_ceil(8)
            || sh.stream > end
        {
            return false;
        }
        let (mut p, mut k, mut initial) = (0, 0, false);
        while k < sh.states {
            if k > 0 && k.is_multiple_of(STRIDE) {
                let at = 8 * sh.directory + (k / STRIDE - 1) * sh.d as usize;
                match entry_checked(self.block, at, sh.d) {
                    Some(entry) if entry == p => {}
                    _ => return false,
                }
            }
            initial |= p == self.initials[a].get();
            match self.next_state(&sh, p) {
                Some((next, usize::MAX)) => p = next,
                _ => return false,
            }
            k += 1;
        }
        let last = 8 * sh.stream + p;
        initial && last <= 8 * end && last.div_ceil(8) + PADDING <= self.block.len() && last <= Q::MAX
    }

    /// Whether `handle` (a bit offset in automaton `a`'s stream) is one of its states: a walk.
    pub(super) fn is_compact_state(&self, a: usize, handle: Q) -> bool {
        let Some(sh) = self.shape(self.part(a).0) else { return false };
        let (mut p, mut k) = (0, 0);
        while k < sh.states && p < handle.get() {
            match self.next_state(&sh, p) {
                Some((next, _)) => p = next,
                None => return false,
            }
            k += 1;
        }
        k < sh.states && p == handle.get()
    }

    /// The first bit of automaton `aut`'s stream in the block (the checked reader).
    pub(super) fn compact_stream(&self, aut: &Automaton<W, Q>) -> Option<usize> {
        Some(8 * self.shape(aut.start.get())?.stream)
    }

    /// The out-events of `aut`'s state at bit `pos` of the block (the checked reader).
    pub(super) fn compact_events(&self, aut: &Automaton<W, Q>, pos: usize) -> Option<[u32; W]> {
        let sh = self.shape(aut.start.get())?;
        let mut out = [0; W];
        let mut l = 0;
        for e in 0..32 * W {
            if super::bit(&aut.alphabet, e as u8) {
                if bits_checked(self.block, pos + l, 1)? == 1 {
                    out[e / 32] |= 1 << (e % 32);
                }
                l += 1;
            }
        }
        (l == sh.alphabet).then_some(out)
    }

    /// The handle `event` leads to from `aut`'s state at bit `pos`, if it leaves it (the checked reader).
    pub(super) fn compact_step(&self, aut: &Automaton<W, Q>, pos: usize, event: u8) -> Option<Q> {
        let sh = self.shape(aut.start.get())?;
        if !super::bit(&self.compact_events(aut, pos)?, event) {
            return None;
        }
        let q = place(&aut.alphabet, usize::from(event));
        let mut r = 0;
        for i in 0..q {
            r += bits_checked(self.block, pos + i, 1)?;
        }
        let k = bits_checked(self.block, pos + sh.alphabet + r * sh.w as usize, sh.w)?;
        let mut p = 0;
        for _ in 0..k {
            p = self.next_state(&sh, p)?.0;
        }
        (p <= Q::MAX).then(|| Q::at(p))
    }

    /// What `aut` allows in its state at bit `pos` of the block: the events of its mask and every event
    /// outside the alphabet. Reads without bounds checks.
    ///
    /// # Safety
    ///
    /// The set passed the check in the `compact` layout, `aut` is one of its automata and `pos` the
    /// position of one of its states.
    #[inline(always)]
    pub(super) unsafe fn compact_allowed(&self, aut: &Automaton<W, Q>, pos: Q) -> [u32; W] {
        let mut allowed = [0; W];
        let mut at = pos.get();
        for (m, &al) in allowed.iter_mut().zip(&aut.alphabet) {
            let mut rest = al;
            while rest != 0 {
                let b = rest.trailing_zeros();
                rest &= rest - 1;
                // SAFETY: the check proved the state's mask (local bit `l` at `at`) in the block, with
                // its 2 bytes of padding.
                if unsafe { bits(self.block, at, 1) } != 0 {
                    *m |= 1 << b;
                }
                at += 1;
            }
            *m |= !al;
        }
        allowed
    }

    /// The position of the state `event` leads to from `aut`'s state at bit `pos`. Reads without bounds
    /// checks.
    ///
    /// # Safety
    ///
    /// As for [`SupervisorSet::compact_allowed`], and `event`, of the alphabet, leaves the state.
    #[inline(always)]
    pub(super) unsafe fn compact_next(&self, aut: &Automaton<W, Q>, pos: Q, event: Event) -> Q {
        let (block, start, pos) = (self.block, aut.start.get(), pos.get());
        // SAFETY: the check proved the header, the directory and every state's fields in the block with
        // its padding, the target an index below the state count and the directory entries the states'
        // offsets, so every read below is of a state's field or a directory entry.
        unsafe {
            let h = |i: usize| usize::from(*block.get_unchecked(start + i));
            let (a, w, d) = (h(2) | h(3) << 8, h(4) as u32, h(5) as u32);
            let stream = 8 * (start + HEADER + (h(6) | h(7) << 8));
            let rank = ones(block, pos, place(&aut.alphabet, event.index()));
            let k = bits(block, pos + a + rank * w as usize, w);
            let mut p = stream;
            if k >= STRIDE {
                p += entry::<Q>(block, 8 * (start + HEADER) + (k / STRIDE - 1) * d as usize, d);
            }
            for _ in 0..k % STRIDE {
                p += a + ones(block, p, a) * w as usize;
            }
            // A checked set's positions fit `Q`.
            Q::at(p)
        }
    }
}
