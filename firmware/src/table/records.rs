//! This module is the home of the readers of the `memory-safe` and `offset` layouts, the reference
//! microcontroller tool's records.
//!
//! Every automaton's records lie in the block from its start ([`super::Automaton::start`]), one per
//! state in state-index order:
//!
//! ```text
//! [count n] then n times [global event id][target, big-endian]
//! ```
//!
//! events in increasing id order. In `memory-safe` the target is the target state's index in 2 bytes: the
//! block is the reference tool's transition vector to the byte, and a step walks the records of the
//! states before the target to find its record, as the reference runtime does (O(k) for state k). In
//! `offset` the target is the byte offset of the target's record from the automaton's start, in 2 bytes,
//! or 4 in a set with wide fields ([`super::SupervisorSet::wide`]) — one whose automaton spans more than
//! 64 KiB: the same number of bytes as `memory-safe` (or 2 more per transition), and a step jumps. A
//! state's position is its record's byte offset in the block, its handle the offset from the
//! automaton's start; what a state allows is its record's events and every event outside the alphabet.

use super::checked::marked;
use super::layout::MEMORY_SAFE;
use super::{Automaton, Event, Position, SupervisorSet};

/// Bytes of one transition of a record: the event id and the target (2 bytes, or 4 when `wide`).
#[inline(always)]
const fn transition(wide: bool) -> usize {
    if wide {
        5
    } else {
        3
    }
}

/// The big-endian target of 2 bytes (4 when `wide`) at `p` of `block`, if it lies there.
fn target_at(block: &[u8], p: usize, wide: bool) -> Option<usize> {
    if wide {
        let b = block.get(p..p + 4)?;
        Some(u32::from_be_bytes([b[0], b[1], b[2], b[3]]) as usize)
    } else {
        let b = block.get(p..p + 2)?;
        Some(usize::from(u16::from_be_bytes([b[0], b[1]])))
    }
}

impl<const W: usize, Q: Position> SupervisorSet<'_, W, Q> {
    /// The byte after the record at byte `at`, if its count byte lies in the block.
    pub(super) fn record_end(&self, at: usize) -> Option<usize> {
        let n = usize::from(*self.block.get(at)?);
        Some(at + 1 + transition(self.wide) * n)
    }

    /// The target field of transition `r` of the record at byte `at`, if it lies in the block.
    fn target_field(&self, at: usize, r: usize) -> Option<usize> {
        target_at(self.block, at + 2 + transition(self.wide) * r, self.wide)
    }

    /// One automaton of a `memory-safe` or `offset` set: its records tile its part of the block and start
    /// at positions `Q` holds, their events ascend within the alphabet, every target names a state (an
    /// index below the state count, or the offset of a record) and the initial handle is a state's.
    /// Linear in the part's size (times its length / 256 for `offset` targets).
    pub(super) fn records_sound(&self, a: usize) -> bool {
        let (start, end) = self.part(a);
        let (alphabet, events) = (&self.automata[a].alphabet, self.events());
        let step = transition(self.wide);
        if start == end || self.automata[a].scale != 1 || !self.is_record(a, self.initials[a]) {
            return false;
        }
        let mut states = 0;
        let mut at = start;
        while at < end {
            let Some(next) = self.record_end(at) else { return false };
            if next > end || at > Q::MAX {
                return false;
            }
            let mut last = None;
            for r in 0..usize::from(self.block[at]) {
                let e = usize::from(self.block[at + 1 + step * r]);
                if last.is_some_and(|l| e <= l) || e >= events || alphabet[e / 32] & (1 << (e % 32)) == 0 {
                    return false;
                }
                last = Some(e);
            }
            states += 1;
            at = next;
        }
        if self.layout == MEMORY_SAFE {
            return !self.wide && self.targets_below(start, end, states);
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
                for r in 0..usize::from(self.block[at]) {
                    match self.target_field(at, r) {
                        Some(t) if marked(&starts, base, len, t) => {}
                        _ => return false,
                    }
                }
                let Some(next) = self.record_end(at) else { return false };
                at = next;
            }
            base += 256;
        }
        true
    }

    /// Whether every target of the records from `start` to `end` is below `states`.
    fn targets_below(&self, start: usize, end: usize, states: usize) -> bool {
        let mut at = start;
        while at < end {
            for r in 0..usize::from(self.block[at]) {
                if self.target_field(at, r).is_none_or(|t| t >= states) {
                    return false;
                }
            }
            let Some(next) = self.record_end(at) else { return false };
            at = next;
        }
        true
    }

    /// Whether `handle` (a byte offset from automaton `a`'s start) starts one of its records: a walk.
    pub(super) fn is_record(&self, a: usize, handle: Q) -> bool {
        let (start, end) = self.part(a);
        let wanted = start + handle.get();
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
        for &e in self.block.get(at + 1..end)?.iter().step_by(transition(self.wide)) {
            *out.get_mut(usize::from(e / 32))? |= 1 << (e % 32);
        }
        Some(out)
    }

    /// The handle `event` leads to from `aut`'s record at byte `at` (a state index resolved by the walk
    /// in `memory-safe`), if the record has the event (the checked reader).
    pub(super) fn record_step(&self, aut: &Automaton<W, Q>, at: usize, event: u8) -> Option<Q> {
        let end = self.record_end(at)?;
        let step = transition(self.wide);
        let r = self.block.get(at + 1..end)?.iter().step_by(step).position(|&e| e == event)?;
        let target = self.target_field(at, r)?;
        if self.layout != MEMORY_SAFE {
            return (target <= Q::MAX).then(|| Q::at(target));
        }
        let start = aut.start.get();
        let mut at = start;
        for _ in 0..target {
            at = self.record_end(at)?;
        }
        (at - start <= Q::MAX).then(|| Q::at(at - start))
    }

    /// What `aut` allows in the state whose record starts at byte `at`: the record's events and every
    /// event outside the alphabet. Reads without bounds checks, transitions of 5 bytes when `WIDE`.
    ///
    /// # Safety
    ///
    /// The set passed the check in a `memory-safe` or `offset` layout with wide fields exactly when
    /// `WIDE`, `aut` is one of its automata and `at` the position of one of its states.
    #[inline(always)]
    pub(super) unsafe fn records_allowed<const WIDE: bool>(&self, aut: &Automaton<W, Q>, at: Q) -> [u32; W] {
        let at = at.get();
        let mut allowed = [0; W];
        // SAFETY: the check proved the record in the block and its events below 32 · W.
        unsafe {
            let n = usize::from(*self.block.get_unchecked(at));
            for r in 0..n {
                let e = Event::new(*self.block.get_unchecked(at + 1 + transition(WIDE) * r));
                *allowed.get_unchecked_mut(e.word()) |= e.bit();
            }
        }
        for (m, al) in allowed.iter_mut().zip(&aut.alphabet) {
            *m |= !al;
        }
        allowed
    }

    /// The position of the state `event` leads to from `aut`'s state at byte `at`: the record's target,
    /// an offset (of 4 bytes when `WIDE`), or (`WALK`, the `memory-safe` layout) a state index whose
    /// record the reference runtime's walk finds. Reads without bounds checks.
    ///
    /// # Safety
    ///
    /// As for [`SupervisorSet::records_allowed`], `WALK` exactly for `memory-safe`, and the record has a
    /// transition on `event`.
    #[inline(always)]
    pub(super) unsafe fn records_next<const WALK: bool, const WIDE: bool>(
        &self,
        aut: &Automaton<W, Q>,
        at: Q,
        event: Event,
    ) -> Q {
        let block = self.block;
        // SAFETY: the record has the event, so the search stops within it; the check proved its target
        // a state's, whose record (and those before it, for the walk) lie in the automaton's part.
        unsafe {
            let mut p = at.get() + 1;
            while *block.get_unchecked(p) != event.0 {
                p += transition(WIDE);
            }
            let b = |i: usize| usize::from(*block.get_unchecked(p + i));
            let target = if WIDE { b(1) << 24 | b(2) << 16 | b(3) << 8 | b(4) } else { b(1) << 8 | b(2) };
            if !WALK {
                return Q::at(aut.start.get() + target);
            }
            let mut p = aut.start.get();
            for _ in 0..target {
                p += 1 + transition(WIDE) * usize::from(*block.get_unchecked(p));
            }
            // A checked set's records start at positions `Q` holds.
            Q::at(p)
        }
    }
}
