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
//! [mask id: 1 byte, or 2 bytes little-endian when SupervisorSet::wide_ids]
//! [target handle, for every event of the mask in increasing id order: 1 byte, or 2 bytes
//!  little-endian when Automaton::wide]
//! ```
//!
//! A state is named by its *handle* `h`: its record starts at byte `h · scale` of the block
//! ([`Automaton::scale`]); records start on multiples of `scale` and the bytes between two records are
//! padding. The target of event `e` from a state is its `r`-th target, `r` the number of mask bits
//! below `e` (its rank). So a step is a mask test, a rank and one load, whatever the state count; the
//! out-mask also gives at once which controllable events the automaton allows (those of its mask and
//! those outside its alphabet), so the enabled set costs one mask per automaton, not a scan.
//! `codegen` picks, per automaton, 1-byte handles with the smallest scale that makes them fit, else
//! 2-byte handles.
//!
//! Limits: at most 256 events and [`MAX_AUTOMATA`] automata, 65 536 masks, 65 536 handles per automaton.
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
//! ([`SupervisorSet::state_unchecked`]); the checked readers ([`SupervisorSet::state`],
//! [`SupervisorSet::step`]) serve host tools and tests.

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
    /// Target handles take 2 bytes (little-endian) instead of 1.
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
    /// Mask ids take 2 bytes (little-endian) instead of 1.
    pub wide_ids: bool,
    /// Per global event id (its length is the event count): bit `a` set when automaton `a` has the
    /// event in its alphabet.
    pub holders: &'t [u32],
    /// Per plant: the controllable events it generates (those of its alphabet no earlier plant holds).
    /// Every controllable event belongs to exactly one plant.
    pub plant_events: &'t [[u32; W]],
    /// The choice sites with two or more controllable out-events, sorted by automaton then state.
    pub sites: &'t [Site],
}

/// A choice site: a state of a plant where two or more controllable events it generates leave.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Site {
    /// Index of the plant in [`SupervisorSet::automata`].
    pub automaton: u8,
    /// The state, as its handle.
    pub state: u16,
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
    /// Automaton `0` has a block that is out of order, a scale of 0, a record outside its block or naming
    /// no mask, an out-event outside its alphabet, or a target or initial handle that starts no record.
    Block(u8),
    /// A site names no plant or is out of order.
    Sites,
}

/// A state's record, located: its out-mask and where its targets start.
#[derive(Clone, Copy, Debug)]
pub struct State<'t, const W: usize> {
    /// The events leaving the state.
    pub mask: &'t [u32; W],
    /// Byte offset of the first target in [`SupervisorSet::blocks`].
    targets: usize,
    /// Targets are 2 bytes.
    wide: bool,
}

impl<const W: usize> State<'_, W> {
    /// Whether `event` leaves the state.
    #[inline(always)]
    pub fn has(&self, event: u8) -> bool {
        bit(self.mask, event)
    }

    /// Position of `event`'s target among the state's targets: the mask bits below it.
    #[inline(always)]
    fn rank(&self, event: u8) -> usize {
        let word = usize::from(event / 32);
        let below = (1u32 << (event % 32)) - 1;
        let mut r = 0;
        for (w, &m) in self.mask.iter().enumerate() {
            if w < word {
                r += ones(m);
            } else if w == word {
                r += ones(m & below);
            }
        }
        r
    }
}

/// Set bits of `x`, one loop turn per bit: cheaper than a full population count for the few bits below
/// an event in a state's mask.
#[inline(always)]
fn ones(mut x: u32) -> usize {
    let mut n = 0;
    while x != 0 {
        x &= x - 1;
        n += 1;
    }
    n
}

/// Whether bit `event` is set in `words`.
#[inline(always)]
pub fn bit<const W: usize>(words: &[u32; W], event: u8) -> bool {
    words.get(usize::from(event / 32)).is_some_and(|w| w & (1 << (event % 32)) != 0)
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

/// Reads without bounds checks. Only built by [`SupervisorSet::state_unchecked`], whose contract
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
    pub fn check(&self, automata: usize) -> Result<(), TableError> {
        let plants = usize::from(self.plants);
        if self.automata.len() != automata || automata > MAX_AUTOMATA || plants > automata {
            return Err(TableError::Automata);
        }
        let events = self.events();
        let all = if automata == MAX_AUTOMATA { u32::MAX } else { (1u32 << automata) - 1 };
        if events > MAX_EVENTS
            || events > 32 * W
            || self.plant_events.len() != plants
            || self.holders.iter().any(|h| h & !all != 0)
        {
            return Err(TableError::Events);
        }
        for a in 0..automata {
            // At most MAX_AUTOMATA automata: the index fits a byte.
            self.check_block(a).map_err(|()| TableError::Block(a as u8))?;
        }
        let ordered = self.sites.windows(2).all(|w| w[0] < w[1]);
        if !ordered || self.sites.iter().any(|s| usize::from(s.automaton) >= plants) {
            return Err(TableError::Sites);
        }
        Ok(())
    }

    /// Byte range of automaton `a`'s block in [`SupervisorSet::blocks`].
    fn block(&self, a: usize) -> Option<(usize, usize)> {
        let start = self.automata.get(a)?.start as usize;
        let end = self.automata.get(a + 1).map_or(self.blocks.len(), |n| n.start as usize);
        (start <= end && end <= self.blocks.len()).then_some((start, end))
    }

    /// One automaton: the records tile the block, and every target and the initial handle start one.
    fn check_block(&self, a: usize) -> Result<(), ()> {
        let aut = self.automata.get(a).ok_or(())?;
        let (start, end) = self.block(a).ok_or(())?;
        let scale = usize::from(aut.scale);
        if scale == 0 || (end - start).div_ceil(scale) > 1 << 16 {
            return Err(());
        }
        // Every record: in the block, a known mask within the alphabet.
        let mut handles = 0;
        self.walk(a, |h, state| {
            let inside = state.mask.iter().zip(&aut.alphabet).all(|(m, al)| m & !al == 0);
            handles = handles.max(h + 1);
            if inside {
                Ok(())
            } else {
                Err(())
            }
        })?;
        // Every handle met is a record start, checked 256 handles at a time with a bitmap on the stack.
        let is_start = |h: u16, starts: &[u32; 8], base: usize| {
            let i = usize::from(h).wrapping_sub(base);
            i >= 256 || starts[i / 32] & (1 << (i % 32)) != 0
        };
        for base in (0..handles).step_by(256) {
            let mut starts = [0u32; 8];
            self.walk(a, |h, _| {
                let i = h.wrapping_sub(base);
                if i < 256 {
                    starts[i / 32] |= 1 << (i % 32);
                }
                Ok(())
            })?;
            let in_range = |h: u16| usize::from(h) >= base && usize::from(h) < base + 256;
            if in_range(aut.initial) && !is_start(aut.initial, &starts, base) {
                return Err(());
            }
            self.walk(a, |_, state| {
                let n = state.mask.iter().map(|m| m.count_ones() as usize).sum();
                for r in 0..n {
                    let t = self.target(&Checked(self.blocks), &state, r).ok_or(())?;
                    if usize::from(t) >= handles || (in_range(t) && !is_start(t, &starts, base)) {
                        return Err(());
                    }
                }
                Ok(())
            })?;
        }
        if usize::from(aut.initial) >= handles {
            return Err(());
        }
        Ok(())
    }

    /// Calls `f` with the handle and record of every state of automaton `a`, in block order; fails when
    /// a record leaves the block or names no mask, or `f` fails.
    fn walk(&self, a: usize, mut f: impl FnMut(usize, State<'t, W>) -> Result<(), ()>) -> Result<(), ()> {
        let aut = self.automata.get(a).ok_or(())?;
        let (start, end) = self.block(a).ok_or(())?;
        let scale = usize::from(aut.scale).max(1);
        let mut at = start;
        while at < end {
            let h = (at - start) / scale;
            let state = self.locate(&Checked(self.blocks), aut, at).ok_or(())?;
            let n: usize = state.mask.iter().map(|m| m.count_ones() as usize).sum();
            let next = state.targets + n * if aut.wide { 2 } else { 1 };
            if next > end {
                return Err(());
            }
            f(h, state)?;
            at = start + next.saturating_sub(start).div_ceil(scale) * scale;
        }
        Ok(())
    }

    /// The record at byte `at` of [`SupervisorSet::blocks`] (of automaton `aut`).
    #[inline(always)]
    fn locate<B: Bytes>(&self, read: &B, aut: &Automaton<W>, at: usize) -> Option<State<'t, W>> {
        let (id, targets) = if self.wide_ids {
            (u16::from_le_bytes([read.byte(at)?, read.byte(at + 1)?]), at + 2)
        } else {
            (u16::from(read.byte(at)?), at + 1)
        };
        let mask = read.mask(self.masks, usize::from(id))?;
        Some(State { mask, targets, wide: aut.wide })
    }

    /// The `r`-th target handle of `state`.
    #[inline(always)]
    fn target<B: Bytes>(&self, read: &B, state: &State<'t, W>, r: usize) -> Option<u16> {
        if state.wide {
            let at = state.targets + 2 * r;
            Some(u16::from_le_bytes([read.byte(at)?, read.byte(at + 1)?]))
        } else {
            Some(u16::from(read.byte(state.targets + r)?))
        }
    }

    #[inline(always)]
    fn state_with<B: Bytes>(&self, read: &B, aut: &Automaton<W>, handle: u16) -> Option<State<'t, W>> {
        self.locate(read, aut, aut.start as usize + usize::from(handle) * usize::from(aut.scale))
    }

    #[inline(always)]
    fn step_with<B: Bytes>(&self, read: &B, state: &State<'t, W>, event: u8) -> Option<u16> {
        if !state.has(event) {
            return None;
        }
        self.target(read, state, state.rank(event))
    }

    /// The record of automaton `a`'s state `handle`, or `None` when it lies outside the tables. (A
    /// handle that starts no record gives a meaningless but harmless answer.)
    pub fn state(&self, a: usize, handle: u16) -> Option<State<'t, W>> {
        self.state_with(&Checked(self.blocks), self.automata.get(a)?, handle)
    }

    /// The handle reached from automaton `a`'s state `handle` by `event`, or `None` when the state has
    /// no such transition (or the handle lies outside the tables).
    pub fn step(&self, a: usize, handle: u16, event: u8) -> Option<u16> {
        let read = Checked(self.blocks);
        let state = self.state_with(&read, self.automata.get(a)?, handle)?;
        self.step_with(&read, &state, event)
    }

    /// Whether `handle` starts a record of automaton `a` (a state of it).
    pub fn is_state(&self, a: usize, handle: u16) -> bool {
        let mut found = false;
        let walked = self.walk(a, |h, _| {
            found |= h == usize::from(handle);
            Ok(())
        });
        walked.is_ok() && found
    }

    /// The record of automaton `aut`'s state `handle`, read without bounds checks.
    ///
    /// # Safety
    ///
    /// [`SupervisorSet::check`] returned `Ok` for this set, `aut` is one of its automata and `handle` is
    /// its initial handle or a target handle read from one of its records.
    #[inline(always)]
    pub unsafe fn state_unchecked(&self, aut: &Automaton<W>, handle: u16) -> State<'t, W> {
        let read = Unchecked(self.blocks);
        let located = self.state_with(&read, aut, handle);
        // SAFETY: `Unchecked` never answers `None`, so neither does `state_with`.
        unsafe { located.unwrap_unchecked() }
    }

    /// The handle `state` (from [`SupervisorSet::state_unchecked`]) reaches by `event`, which must leave
    /// it, read without bounds checks.
    ///
    /// # Safety
    ///
    /// As for [`SupervisorSet::state_unchecked`], and `state.has(event)`.
    #[inline(always)]
    pub unsafe fn target_unchecked(&self, state: &State<'t, W>, event: u8) -> u16 {
        let target = self.target(&Unchecked(self.blocks), state, state.rank(event));
        // SAFETY: `Unchecked` never answers `None`, so neither does `target`.
        unsafe { target.unwrap_unchecked() }
    }

    /// The index of the site of plant `automaton` in state `state`, if it is one.
    pub fn site(&self, automaton: u8, state: u16) -> Option<usize> {
        self.sites.binary_search(&Site { automaton, state }).ok()
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
            wide_ids: false,
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
