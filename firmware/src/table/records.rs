//! This module is the home of the readers of the `memory-safe` and `offset` layouts, the reference
//! microcontroller tool's records.
//!
//! Every automaton's records lie in the block from its start ([`super::Automaton::start`]), one per
//! state in state-index order:
//!
//! ```text
//! [count n] then n times [global event id][target, u16 big-endian]
//! ```
//!
//! events in increasing id order. In `memory-safe` the target is the target state's index: the block is
//! the reference tool's transition vector to the byte, and a step walks the records of the states before
//! the target to find its record, as the reference runtime does (O(k) for state k). In `offset` the
//! target is the byte offset of the target's record from the automaton's start: the same number of
//! bytes, and a step jumps. A state's position is its record's byte offset in the block, its handle the
//! offset from the automaton's start; what a state allows is its record's events and every event outside
//! the alphabet.

use super::checked::marked;
use super::layout::MEMORY_SAFE;
use super::{Automaton, Event, SupervisorSet, MAX_BLOCK};

/// Bytes of one transition of a record: the event id and the 2-byte target.
const TRANSITION: usize = 3;

impl<const W: usize> SupervisorSet<'_, W> {
    /// The byte after the record at byte `at`, if its count byte lies in the block.
    pub(super) const fn record_end(&self, at: usize) -> Option<usize> {
        if at < self.block.len() {
            Some(at + 1 + TRANSITION * self.block[at] as usize)
        } else {
            None
        }
    }

    /// The target field of transition `r` of the record at byte `at` (it lies in the block).
    const fn target_field(&self, at: usize, r: usize) -> usize {
        let p = at + 2 + TRANSITION * r;
        u16::from_be_bytes([self.block[p], self.block[p + 1]]) as usize
    }

    /// One automaton of a `memory-safe` or `offset` set: its records tile its part of the block and start
    /// in the first 64 KiB, their events ascend within the alphabet, every target names a state (an
    /// index below the state count, or the offset of a record) and the initial handle is a state's.
    /// Linear in the part's size (times its length / 256 for `offset` targets).
    pub(super) const fn records_sound(&self, a: usize) -> bool {
        let (start, end) = self.part(a);
        let (alphabet, events) = (&self.automata[a].alphabet, self.events());
        if start == end || self.automata[a].scale != 1 || !self.is_record(a, self.initials[a]) {
            return false;
        }
        let mut states = 0;
        let mut at = start;
        while at < end {
            let Some(next) = self.record_end(at) else { return false };
            if next > end || at >= MAX_BLOCK {
                return false;
            }
            let mut r = 0;
            let mut last = -1;
            while r < self.block[at] as usize {
                let e = self.block[at + 1 + TRANSITION * r] as usize;
                if e as isize <= last || e >= events || alphabet[e / 32] & (1 << (e % 32)) == 0 {
                    return false;
                }
                last = e as isize;
                r += 1;
            }
            states += 1;
            at = next;
        }
        if self.layout == MEMORY_SAFE {
            return self.targets_below(start, end, states);
        }
        // Offsets: every target starts a record, checked 256 bytes at a time with a bitmap.
        let len = end - start;
        let mut base = 0;
        while base < len {
            let mut starts = [0u32; 8];
            let mut at = start;
            while at < end {
                let i = (at - start).wrapping_sub(base);
                if i < 256 {
                    starts[i / 32] |= 1 << (i % 32);
                }
                let Some(next) = self.record_end(at) else { return false };
                at = next;
            }
            at = start;
            while at < end {
                let mut r = 0;
                while r < self.block[at] as usize {
                    if !marked(&starts, base, len, self.target_field(at, r)) {
                        return false;
                    }
                    r += 1;
                }
                let Some(next) = self.record_end(at) else { return false };
                at = next;
            }
            base += 256;
        }
        true
    }

    /// Whether every target of the records from `start` to `end` is below `states`.
    const fn targets_below(&self, start: usize, end: usize, states: usize) -> bool {
        let mut at = start;
        while at < end {
            let mut r = 0;
            while r < self.block[at] as usize {
                if self.target_field(at, r) >= states {
                    return false;
                }
                r += 1;
            }
            let Some(next) = self.record_end(at) else { return false };
            at = next;
        }
        true
    }

    /// Whether `handle` (a byte offset from automaton `a`'s start) starts one of its records: a walk.
    pub(super) const fn is_record(&self, a: usize, handle: u16) -> bool {
        let (start, end) = self.part(a);
        let wanted = start + handle as usize;
        let mut at = start;
        while at < wanted {
            match self.record_end(at) {
                Some(next) => at = next,
                None => return false,
            }
        }
        at == wanted && at < end
    }

    /// The events of the record at byte `at`, if it lies in the block (the checked reader).
    pub(super) fn record_events(&self, at: usize) -> Option<[u32; W]> {
        let end = self.record_end(at)?;
        let mut out = [0; W];
        for &e in self.block.get(at + 1..end)?.iter().step_by(TRANSITION) {
            *out.get_mut(usize::from(e / 32))? |= 1 << (e % 32);
        }
        Some(out)
    }

    /// The handle `event` leads to from `aut`'s record at byte `at` (a state index resolved by the walk
    /// in `memory-safe`), if the record has the event (the checked reader).
    pub(super) fn record_step(&self, aut: &Automaton<W>, at: usize, event: u8) -> Option<u16> {
        let end = self.record_end(at)?;
        let r = self.block.get(at + 1..end)?.iter().step_by(TRANSITION).position(|&e| e == event)?;
        let p = at + 2 + TRANSITION * r;
        let target = u16::from_be_bytes([*self.block.get(p)?, *self.block.get(p + 1)?]);
        if self.layout != MEMORY_SAFE {
            return Some(target);
        }
        let start = usize::from(aut.start);
        let mut at = start;
        for _ in 0..target {
            at = self.record_end(at)?;
        }
        u16::try_from(at - start).ok()
    }

    /// What `aut` allows in the state whose record starts at byte `at`: the record's events and every
    /// event outside the alphabet. Reads without bounds checks.
    ///
    /// # Safety
    ///
    /// The set passed the check in a `memory-safe` or `offset` layout, `aut` is one of its automata and
    /// `at` the position of one of its states.
    #[inline(always)]
    pub(super) unsafe fn records_allowed(&self, aut: &Automaton<W>, at: u16) -> [u32; W] {
        let at = usize::from(at);
        let mut allowed = [0; W];
        // SAFETY: the check proved the record in the block and its events below 32 · W.
        unsafe {
            let n = usize::from(*self.block.get_unchecked(at));
            for r in 0..n {
                let e = Event::new(*self.block.get_unchecked(at + 1 + TRANSITION * r));
                *allowed.get_unchecked_mut(e.word()) |= e.bit();
            }
        }
        for (m, al) in allowed.iter_mut().zip(&aut.alphabet) {
            *m |= !al;
        }
        allowed
    }

    /// The position of the state `event` leads to from `aut`'s state at byte `at`: the record's target,
    /// an offset, or (`WALK`, the `memory-safe` layout) a state index whose record the reference
    /// runtime's walk finds. Reads without bounds checks.
    ///
    /// # Safety
    ///
    /// As for [`SupervisorSet::records_allowed`], `WALK` exactly for `memory-safe`, and the record has a
    /// transition on `event`.
    #[inline(always)]
    pub(super) unsafe fn records_next<const WALK: bool>(
        &self,
        aut: &Automaton<W>,
        at: u16,
        event: Event,
    ) -> u16 {
        let block = self.block;
        // SAFETY: the record has the event, so the search stops within it; the check proved its target
        // a state's, whose record (and those before it, for the walk) lie in the automaton's part.
        unsafe {
            let mut p = usize::from(at) + 1;
            while *block.get_unchecked(p) != event.0 {
                p += TRANSITION;
            }
            let target = u16::from_be_bytes([*block.get_unchecked(p + 1), *block.get_unchecked(p + 2)]);
            if !WALK {
                return aut.start.wrapping_add(target);
            }
            let mut p = usize::from(aut.start);
            for _ in 0..target {
                p += 1 + TRANSITION * usize::from(*block.get_unchecked(p));
            }
            // A checked set's records start in the first 64 KiB of the block.
            p as u16
        }
    }
}
