//! This module is the home of the tables the runtime reads: one [`SupervisorSet`] in the `ranked`
//! layout, emitted by `codegen` as `static` data in flash.
//!
//! # The `ranked` layout
//!
//! A state's *out-mask* is the bitset over global event ids of the events leaving it. The set keeps one
//! pool of distinct out-masks ([`SupervisorSet::masks`], `W` words each), shared by all automata. Each
//! automaton is a byte block (a slice of [`SupervisorSet::blocks`]) holding one record per state:
//!
//! ```text
//! [mask id]
//! [target handle, for every event of the mask in increasing id order]
//! ```
//!
//! A state is named by its *handle* `h`: its record starts at byte `h · scale` of the block
//! ([`Automaton::scale`]); records start on multiples of `scale` and the bytes between two records are
//! padding. The target of event `e` from a state is its `r`-th target, `r` the number of mask bits
//! below `e` (its rank). Mask ids and handles take 1 byte each, or 2 (little-endian) in a *wide* automaton
//! ([`Automaton::wide`]). So a step is a mask test, a rank and one load, whatever the state count; the
//! out-mask also gives at once which controllable events the automaton allows (those of its mask and
//! those outside its alphabet), so the enabled set costs one mask per automaton, not a scan.
//! `codegen` makes an automaton narrow when its mask ids fit a byte (the pool lists masks in order of first
//! use, plants first) and some scale makes its handles fit one, taking the smallest such scale.
//!
//! Limits: at most 256 events and [`MAX_AUTOMATA`] automata, 65 536 handles per automaton, and as a
//! [`Slot`] holds a state in one word: 4 096 masks and 1 MiB of blocks.
//!
//! # Side tables
//!
//! Per event the automata that hold it ([`SupervisorSet::holders`], so an event touches only those),
//! per plant the controllable events it generates ([`SupervisorSet::plant_events`]) and the *choice
//! sites* of the local-queue policies ([`SupervisorSet::sites`]; see [`crate::choice`]).
//!
//! # Checked once, then trusted
//!
//! [`SupervisorSet::check`] proves, once at boot, everything the hot path relies on: every record lies
//! in its block, every mask id in the pool, every target and initial handle is the start of a record,
//! every holder bit names an automaton. After it the runtime reads the tables without bounds checks
//! ([`SupervisorSet::slot_unchecked`], [`SupervisorSet::slot_mask`], [`SupervisorSet::advance`]); the checked readers
//! ([`SupervisorSet::mask`], [`SupervisorSet::step`]) serve host tools and tests.

use crate::event_set::ones;

/// Most automata in one set: one bit each in a `u32` of [`SupervisorSet::holders`].
pub const MAX_AUTOMATA: usize = 32;
/// Most events in one set: an event id is one byte.
pub const MAX_EVENTS: usize = 256;

/// One automaton of the set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Automaton<const W: usize> {
    /// Offset of the automaton's block in [`SupervisorSet::blocks`]; the block ends where the next
    /// automaton's starts (the last one at the end of `blocks`).
    pub start: u32,
    /// Handle of the initial state.
    pub initial: u16,
    /// Bytes per handle unit: a state's record starts at byte `handle · scale` of the block (≥ 1).
    pub scale: u8,
    /// Mask ids and target handles take 2 bytes (little-endian) instead of 1.
    pub wide: bool,
    /// Bitset over global event ids (bit `e % 32` of word `e / 32`): the automaton's alphabet. An event
    /// outside it never moves or blocks the automaton.
    pub alphabet: [u32; W],
}

/// The whole set the firmware runs: plants and supervisors over one event numbering, events in
/// `W`-word bitsets. On the target every slice is a `static` in flash (`'t = 'static`); on the host the
/// tables may be borrowed from owned data.
#[derive(Clone, Copy, Debug)]
pub struct SupervisorSet<'t, const W: usize> {
    /// Bitset over global event ids: the controllable ones.
    pub controllable: [u32; W],
    /// The first `plants` automata are the plants (the product system), the others supervisors.
    pub plants: u8,
    /// Plants first, then supervisors, in manifest order.
    pub automata: &'t [Automaton<W>],
    /// The blocks of all automata, back to back.
    pub blocks: &'t [u8],
    /// The pool of distinct out-masks that records name by id.
    pub masks: &'t [[u32; W]],
    /// Per global event id (its length is the event count): bit `a` set when automaton `a` has the
    /// event in its alphabet.
    pub holders: &'t [u32],
    /// Per plant: the controllable events it generates (those of its alphabet no earlier plant holds).
    /// Every controllable event belongs to exactly one plant.
    pub plant_events: &'t [[u32; W]],
    /// The *choice sites*, states of a plant where two or more controllable events it generates leave,
    /// each as the byte offset of its record in [`SupervisorSet::blocks`] (so unique across automata),
    /// ascending.
    pub sites: &'t [u32],
}

/// Why a set cannot run: sizes of another build, or tables that break the layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableError {
    /// The automaton count differs from the runtime's, exceeds [`MAX_AUTOMATA`], or the plant count
    /// exceeds it.
    Automata,
    /// More events than `W` words or [`MAX_EVENTS`] hold, a holder bit naming no automaton, or a
    /// per-plant table of another length.
    Events,
    /// More blocks or masks than a [`Slot`] addresses.
    Size,
    /// Automaton `0` has a block that is out of order, a scale of 0, a record outside its block or naming
    /// no mask, an out-event outside its alphabet, or a target or initial handle that starts no record.
    Block(u8),
}

/// Position of `event`'s target among a state's targets: the bits of its out-mask below `event`.
#[inline(always)]
fn rank<const W: usize>(mask: &[u32; W], event: Event) -> usize {
    let mut r = 0;
    for (w, &m) in mask.iter().enumerate() {
        if w < event.word() {
            r += ones(m) as usize;
        } else if w == event.word() {
            r += ones(m & (event.bit() - 1)) as usize;
        }
    }
    r
}

/// An event id, for bitset access: word index and bit within the word. Kept as the id, so that it
/// travels in one register and the compiler recomputes word and bit rather than spilling them.
#[derive(Clone, Copy, Debug)]
pub struct Event(u8);

impl Event {
    /// The event `id`.
    #[inline(always)]
    pub fn new(id: u8) -> Event {
        Event(id)
    }

    /// Index of the event's word in a bitset.
    #[inline(always)]
    fn word(self) -> usize {
        usize::from(self.0 / 32)
    }

    /// The event's bit within its word.
    #[inline(always)]
    fn bit(self) -> u32 {
        1 << (self.0 % 32)
    }

    /// Whether the event is in `words` (`false` when its word lies beyond them).
    #[inline(always)]
    pub fn in_set<const W: usize>(self, words: &[u32; W]) -> bool {
        words.get(self.word()).is_some_and(|w| w & self.bit() != 0)
    }

    /// Whether the event is in `words`, without a bounds check.
    ///
    /// # Safety
    ///
    /// The event's id is below `32 · W`.
    #[inline(always)]
    pub unsafe fn in_set_unchecked<const W: usize>(self, words: &[u32; W]) -> bool {
        // SAFETY: the caller's promise.
        unsafe { words.get_unchecked(self.word()) & self.bit() != 0 }
    }
}

/// Where an automaton is: its current state's record offset in [`SupervisorSet::blocks`] (low 20
/// bits) and mask id (high 12 bits), so that a step finds both in one word of RAM.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Slot(u32);

impl Slot {
    /// First bit of the mask id.
    const ID_SHIFT: u32 = 20;
    /// Most bytes of blocks a slot addresses.
    pub const MAX_BLOCKS: usize = 1 << Self::ID_SHIFT;
    /// Most masks a slot names.
    pub const MAX_MASKS: usize = 1 << (32 - Self::ID_SHIFT);

    /// The record offset.
    #[inline(always)]
    fn record(self) -> usize {
        (self.0 & (Self::MAX_BLOCKS as u32 - 1)) as usize
    }

    /// The handle of `aut`'s state in this slot.
    pub fn handle<const W: usize>(self, aut: &Automaton<W>) -> u16 {
        ((self.record() as u32).wrapping_sub(aut.start) / u32::from(aut.scale.max(1))) as u16
    }
}

/// Whether bit `event` is set in `words`.
#[inline(always)]
pub fn bit<const W: usize>(words: &[u32; W], event: u8) -> bool {
    Event::new(event).in_set(words)
}

/// The two ways of reading a block: checked (host tools, the boot check) and unchecked (the hot path,
/// after the boot check proved every read in bounds).
trait Bytes {
    fn byte(&self, at: usize) -> Option<u8>;
    fn mask<'t, const W: usize>(&self, masks: &'t [[u32; W]], id: usize) -> Option<&'t [u32; W]>;
}

struct Checked<'b>(&'b [u8]);

impl Bytes for Checked<'_> {
    #[inline(always)]
    fn byte(&self, at: usize) -> Option<u8> {
        self.0.get(at).copied()
    }

    #[inline(always)]
    fn mask<'t, const W: usize>(&self, masks: &'t [[u32; W]], id: usize) -> Option<&'t [u32; W]> {
        masks.get(id)
    }
}

/// Reads without bounds checks. Only built by the `unchecked` readers of [`SupervisorSet`], whose contract
/// guarantees every offset and id it is asked for is in bounds.
struct Unchecked<'b>(&'b [u8]);

impl Bytes for Unchecked<'_> {
    #[inline(always)]
    fn byte(&self, at: usize) -> Option<u8> {
        // SAFETY: see the type's documentation.
        Some(unsafe { *self.0.get_unchecked(at) })
    }

    #[inline(always)]
    fn mask<'t, const W: usize>(&self, masks: &'t [[u32; W]], id: usize) -> Option<&'t [u32; W]> {
        // SAFETY: see the type's documentation.
        Some(unsafe { masks.get_unchecked(id) })
    }
}

impl<'t, const W: usize> SupervisorSet<'t, W> {
    /// Number of events (ids `0..events`).
    pub fn events(&self) -> usize {
        self.holders.len()
    }

    /// Checks everything the runtime's unchecked reads rely on, for a runtime of `automata` automata.
    /// Linear in the size of the tables (times the handle count / 256 for automata of more than 256
    /// handle units); runs once at boot.
    #[inline(never)]
    pub fn check(&self, automata: usize) -> Result<(), TableError> {
        let plants = usize::from(self.plants);
        if self.automata.len() != automata || automata > MAX_AUTOMATA || plants > automata {
            return Err(TableError::Automata);
        }
        let events = self.events();
        let all = if automata == MAX_AUTOMATA { u32::MAX } else { (1u32 << automata) - 1 };
        if self.blocks.len() > Slot::MAX_BLOCKS || self.masks.len() > Slot::MAX_MASKS {
            return Err(TableError::Size);
        }
        if events > MAX_EVENTS
            || events > 32 * W
            || self.plant_events.len() != plants
            || self.holders.iter().any(|h| h & !all != 0)
        {
            return Err(TableError::Events);
        }
        for a in 0..automata {
            // At most MAX_AUTOMATA automata: the index fits a byte.
            self.check_block(a).ok_or(TableError::Block(a as u8))?;
        }
        Ok(())
    }

    /// Byte range of automaton `a`'s block in [`SupervisorSet::blocks`].
    fn block(&self, a: usize) -> Option<(usize, usize)> {
        let start = self.automata.get(a)?.start as usize;
        let end = self.automata.get(a + 1).map_or(self.blocks.len(), |n| n.start as usize);
        (start <= end && end <= self.blocks.len()).then_some((start, end))
    }

    /// One automaton: the records tile the block, name masks within the alphabet, and every target and
    /// the initial handle start one — checked 256 handles at a time with a bitmap on the stack: a first
    /// pass marks the record starts, a second checks the targets.
    fn check_block(&self, a: usize) -> Option<()> {
        let aut = self.automata.get(a)?;
        let (start, end) = self.block(a)?;
        let scale = usize::from(aut.scale);
        // Handles are 16-bit.
        if scale == 0 || (end - start).div_ceil(scale) > 1 << 16 {
            return None;
        }
        let mut base = 0;
        loop {
            let mut starts = [0u32; 8];
            let mut handles = 0;
            for pass in 0..2 {
                // Whether `h` is a handle met in pass 0 and, when in this chunk, a record start.
                let starts_record = |starts: &[u32; 8], handles: usize, h: usize| {
                    let i = h.wrapping_sub(base);
                    h < handles && (i >= 256 || starts[i / 32] & (1 << (i % 32)) != 0)
                };
                if pass == 1 && !starts_record(&starts, handles, usize::from(aut.initial)) {
                    return None;
                }
                let mut at = start;
                while at < end {
                    let (mask, n, next) = self.next_record(aut, at, end)?;
                    if pass == 0 {
                        let h = (at - start) / scale;
                        let i = h.wrapping_sub(base);
                        if i < 256 {
                            starts[i / 32] |= 1 << (i % 32);
                        }
                        handles = h + 1;
                        if mask.iter().zip(&aut.alphabet).any(|(m, al)| m & !al != 0) {
                            return None;
                        }
                    } else {
                        for r in 0..n {
                            let t = self.target_at(&Checked(self.blocks), aut, at, r)?;
                            if !starts_record(&starts, handles, usize::from(t)) {
                                return None;
                            }
                        }
                    }
                    at = start + (next - start).div_ceil(scale) * scale;
                }
            }
            base += 256;
            if base >= handles {
                return Some(());
            }
        }
    }

    /// The record of `aut` at byte `at`, if it lies before `end`: its out-mask, target count and end.
    #[inline(always)]
    fn next_record(&self, aut: &Automaton<W>, at: usize, end: usize) -> Option<(&'t [u32; W], usize, usize)> {
        let mask = self.mask_at(&Checked(self.blocks), aut, at)?;
        let n = mask.iter().map(|m| m.count_ones() as usize).sum();
        let next = at + (n + 1) * if aut.wide { 2 } else { 1 };
        (next <= end).then_some((mask, n, next))
    }

    /// Byte offset in [`SupervisorSet::blocks`] of the record of `aut`'s state `handle`.
    #[inline(always)]
    fn record(aut: &Automaton<W>, handle: u16) -> usize {
        aut.start as usize + usize::from(handle) * usize::from(aut.scale)
    }

    /// The out-mask of the record at byte `at`.
    #[inline(always)]
    fn mask_at<B: Bytes>(&self, read: &B, aut: &Automaton<W>, at: usize) -> Option<&'t [u32; W]> {
        read.mask(self.masks, usize::from(Self::field(read, aut, at, 0)?))
    }

    /// Field `i` of the record at byte `at` (the mask id, then the targets), 1 or 2 bytes wide.
    #[inline(always)]
    fn field<B: Bytes>(read: &B, aut: &Automaton<W>, at: usize, i: usize) -> Option<u16> {
        if aut.wide {
            let at = at + 2 * i;
            Some(u16::from_le_bytes([read.byte(at)?, read.byte(at + 1)?]))
        } else {
            Some(u16::from(read.byte(at + i)?))
        }
    }

    /// The `r`-th target handle of the record at byte `at`.
    #[inline(always)]
    fn target_at<B: Bytes>(&self, read: &B, aut: &Automaton<W>, at: usize, r: usize) -> Option<u16> {
        Self::field(read, aut, at, r + 1)
    }

    /// The out-mask of automaton `a`'s state `handle`, or `None` when it lies outside the tables. (A
    /// handle that starts no record gives a meaningless but harmless answer.)
    pub fn mask(&self, a: usize, handle: u16) -> Option<&'t [u32; W]> {
        let aut = self.automata.get(a)?;
        self.mask_at(&Checked(self.blocks), aut, Self::record(aut, handle))
    }

    /// The handle reached from automaton `a`'s state `handle` by `event`, or `None` when the state has
    /// no such transition (or the handle lies outside the tables).
    pub fn step(&self, a: usize, handle: u16, event: u8) -> Option<u16> {
        let read = Checked(self.blocks);
        let aut = self.automata.get(a)?;
        let at = Self::record(aut, handle);
        let mask = self.mask_at(&read, aut, at)?;
        let event = Event::new(event);
        if !event.in_set(mask) {
            return None;
        }
        self.target_at(&read, aut, at, rank(mask, event))
    }

    /// Whether `handle` starts a record of automaton `a` (a state of it).
    pub fn is_state(&self, a: usize, handle: u16) -> bool {
        let (Some(aut), Some((start, end))) = (self.automata.get(a), self.block(a)) else { return false };
        let scale = usize::from(aut.scale).max(1);
        let wanted = start + usize::from(handle) * scale;
        let mut at = start;
        while at < wanted {
            let Some((_, _, next)) = self.next_record(aut, at, end) else { return false };
            at = start + (next - start).div_ceil(scale) * scale;
        }
        at == wanted && self.next_record(aut, at, end).is_some()
    }

    /// The out-mask of the state in `slot`, read without bounds checks.
    ///
    /// # Safety
    ///
    /// [`SupervisorSet::check`] returned `Ok` for this set and `slot` came from
    /// [`SupervisorSet::slot_unchecked`] or [`SupervisorSet::advance`] on it.
    #[inline(always)]
    pub unsafe fn slot_mask(&self, slot: Slot) -> &'t [u32; W] {
        // SAFETY: the caller's promise: the slot's id was read from a checked record.
        unsafe { self.masks.get_unchecked((slot.0 >> Slot::ID_SHIFT) as usize) }
    }

    /// The slot of `aut`'s state `handle`, read without bounds checks.
    ///
    /// # Safety
    ///
    /// [`SupervisorSet::check`] returned `Ok` for this set, `aut` is one of its automata and `handle`
    /// one of its states.
    #[inline(always)]
    pub unsafe fn slot_unchecked(&self, aut: &Automaton<W>, handle: u16) -> Slot {
        let at = Self::record(aut, handle);
        let id = Self::field(&Unchecked(self.blocks), aut, at, 0);
        // SAFETY: `Unchecked` never answers `None`; the check bounds records and ids to the slot's fields.
        Slot(u32::from(unsafe { id.unwrap_unchecked() }) << Slot::ID_SHIFT | at as u32)
    }

    /// Moves `aut` by `event` from the state in `slot`, whose out-mask `mask` holds `event`: the slot
    /// becomes the target's. Reads without bounds checks.
    ///
    /// # Safety
    ///
    /// As for [`SupervisorSet::slot_mask`]; `aut` is the slot's automaton, `mask` its out-mask and it
    /// holds `event`.
    #[inline(always)]
    pub unsafe fn advance(&self, aut: &Automaton<W>, slot: &mut Slot, mask: &[u32; W], event: Event) {
        let target = self.target_at(&Unchecked(self.blocks), aut, slot.record(), rank(mask, event));
        // SAFETY: `Unchecked` never answers `None`, so neither does `target_at`; the target of a checked
        // set's record is one of its states.
        *slot = unsafe { self.slot_unchecked(aut, target.unwrap_unchecked()) };
    }

    /// The out-mask of the state in `slot` (`None` if the slot names no mask of the set).
    pub fn mask_of(&self, slot: Slot) -> Option<&'t [u32; W]> {
        self.masks.get((slot.0 >> Slot::ID_SHIFT) as usize)
    }

    /// The index of the site of the state in `slot`, if it is one. A scan: sites are states of the
    /// plants, small automata, so there are few, and the scan beats a binary search's bookkeeping.
    pub fn site(&self, slot: Slot) -> Option<usize> {
        let at = slot.record() as u32;
        self.sites.iter().position(|&s| s == at)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two states: 0 –e0→ 1, 1 –e1→ 0; masks {e0} (id 0) and {e1} (id 1); scale 2, so handle 1 is byte 2.
    static BLOCKS: [u8; 4] = [0, 1, 1, 0];
    static MASKS: [[u32; 1]; 2] = [[0b01], [0b10]];
    static AUTOMATA: [Automaton<1>; 1] =
        [Automaton { start: 0, initial: 0, scale: 2, wide: false, alphabet: [0b11] }];

    fn toggle() -> SupervisorSet<'static, 1> {
        SupervisorSet {
            controllable: [0b01],
            plants: 1,
            automata: &AUTOMATA,
            blocks: &BLOCKS,
            masks: &MASKS,
            holders: &[1, 1],
            plant_events: &[[0b01]],
            sites: &[],
        }
    }

    #[test]
    fn step_follows_handles() {
        let t = toggle();
        assert_eq!(t.check(1), Ok(()));
        assert_eq!(t.step(0, 0, 0), Some(1));
        assert_eq!(t.step(0, 1, 1), Some(0));
        assert_eq!(t.step(0, 0, 1), None);
        assert!(t.is_state(0, 1));
        assert!(!t.is_state(0, 2));
    }

    #[test]
    fn out_of_table_is_none_not_panic() {
        let t = toggle();
        assert_eq!(t.step(0, 200, 0), None);
        assert_eq!(t.step(3, 0, 0), None);
        assert_eq!(t.step(0, 0, 255), None);
    }

    #[test]
    fn check_refuses_broken_blocks() {
        let bad_target = [0u8, 3, 1, 0];
        let mut t = toggle();
        t.blocks = &bad_target;
        assert_eq!(t.check(1), Err(TableError::Block(0)));
        let bad_id = [2u8, 1, 1, 0];
        t.blocks = &bad_id;
        assert_eq!(t.check(1), Err(TableError::Block(0)));
        let short = [0u8, 1, 1];
        t.blocks = &short;
        assert_eq!(t.check(1), Err(TableError::Block(0)));
        let mut t = toggle();
        t.holders = &[1, 2];
        assert_eq!(t.check(1), Err(TableError::Events));
        assert_eq!(toggle().check(2), Err(TableError::Automata));
    }
}
