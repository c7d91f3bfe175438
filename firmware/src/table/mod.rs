//! This module is the home of the tables the runtime reads: one [`SupervisorSet`], emitted by `codegen`
//! as `static` data in flash, in one of five record layouts ([`layout`]): `ranked` (small and fast on
//! the Cortex-M3), `indexed` (the faster on a core without unaligned loads), and the three of the size
//! report that trade speed for compatibility or size — `memory-safe` (the reference tool's vector, to
//! the byte, stepped by its walk to state k), `offset` (the same records with targets as offsets: no
//! walk) and `compact` (bit-packed over local alphabets), described in [`records`] and [`compact`].
//!
//! # The `ranked` layout
//!
//! A state's *out-mask* is the bitset over global event ids of the events leaving it. The set keeps one
//! pool of distinct out-masks ([`SupervisorSet::masks`], `⌈events / 8⌉` bytes each), shared by all
//! automata. All
//! records of all automata lie in one byte block ([`SupervisorSet::block`]), each automaton's from its
//! start ([`Automaton::start`]) up to the next automaton's start (the block's end for the last), one
//! record per state:
//!
//! ```text
//! [mask id]
//! [target handle, for every event of the mask in increasing id order]
//! ```
//!
//! A state is named by its *handle* `h`: its record starts at byte `start + h · scale` of the block
//! ([`Automaton::scale`]); records start on multiples of `scale` from the start and the bytes between
//! two records are padding. Handle 0, the first record, is the initial state. The target of event `e`
//! from a state is its `r`-th target, `r` the number of mask bits below `e` (its rank). Mask ids and
//! handles take 1 byte each, or 2 (little-endian) in a *wide* set ([`SupervisorSet::wide`]). So a
//! step is a mask test, a rank and one load, whatever the state count; the out-mask also gives at once
//! which controllable events the automaton allows (those of its mask and those outside its alphabet),
//! so the enabled set costs one mask per automaton, not a scan. The encoder (`firmware::build`, feature
//! `build`) chooses the field width and the scales. The runtime knows the field and mask widths at
//! compile time ([`CheckedSet`]'s `WIDE` and `MASK`), so its steps read the tables without testing them.
//!
//! # The `indexed` layout
//!
//! The same pool, block, handles and scales, with two differences that take the bit arithmetic out of
//! a step ([`SupervisorSet::layout`] [`layout::INDEXED`]):
//!
//! ```text
//! [mask id]
//! [target handle, for every event of the automaton's alphabet in increasing id order]
//! ```
//!
//! The target of event `e` is the one at `e`'s *place* in the alphabet (the alphabet's events below
//! it), which a side table holds per event in a list of the automata holding it
//! ([`SupervisorSet::holder_lists`]: the runtime walks that list rather than searching the holder bits); the
//! targets of events that do not leave the state are 0 and never read. The pool holds each state's *allowed set*
//! rather than its out-mask — the out-mask and every event outside the automaton's alphabet, what the
//! runtime keeps for the enabled set (the out-mask is its part within the alphabet) — and every entry
//! takes a whole number of words (`4 · ⌈events / 32⌉` bytes), so that it is read with aligned word loads
//! and as it is. Records are as long
//! as the alphabet: the layout is larger, and made for the Cortex-M0+ (Thumb-1 has no unaligned loads
//! and no bit-scan instruction, so the rank's loop and the assembly of a 3-byte mask there cost more
//! than the rest of a step).
//!
//! In every layout the runtime holds a state as its *position*: the byte offset of its record in the
//! block (the bit offset of its mask in `compact`), so that choice sites ([`SupervisorSet::sites`]) are
//! positions too. A state's *handle* is its position from its automaton's start (in scale units in
//! `ranked` and `indexed`); [`SupervisorSet::initials`] holds the initial states'. Positions take 16 bits
//! ([`Position`] `u16`) while every one is below 65 536 — the tables' first 64 KiB (8 KiB of `compact`
//! bits) — and 32 bits (`u32`) beyond: the encoder chooses, one width per set, and the runtime is
//! compiled for it (its `Q` parameter), so a set that fits 16 bits keeps its RAM and its steps.
//!
//! Limits: at most 256 events and [`MAX_AUTOMATA`] automata, 65 536 handles per automaton and 65 536
//! masks (`ranked`, `indexed`), every position within its [`Position`] type.
//!
//! # Side tables
//!
//! Per event the automata that hold it ([`SupervisorSet::holders`], so an event touches only those),
//! per plant the controllable events it generates ([`SupervisorSet::plant_events`]) and the *choice
//! sites* of the local-queue policies ([`SupervisorSet::sites`]; see [`crate::choice`]).
//!
//! # Checked once, then trusted
//!
//! [`SupervisorSet::check`] proves everything the hot path relies on: every record lies in its
//! automaton's part of the block, every mask id in the pool, every target handle is the start of a
//! record, every holder bit names an automaton with the event in its alphabet, every place is the
//! event's in the alphabet, every position fits its type. It runs where it is cheap, never in the
//! firmware and never at compile time: the emitted tables are one [`image`] of bytes, which `codegen`
//! checks when it writes them and the application's build script checks again on the host, as the
//! firmware compiles them — a build whose tables were not checked does not compile
//! ([`image::checked`]). The runtime only takes a [`CheckedSet`] and then reads the tables without
//! bounds checks ([`read`]); the checked readers ([`SupervisorSet::mask`], [`SupervisorSet::step`])
//! serve host tools and tests.

use crate::event_set::ones;

mod checked;
pub mod compact;
pub mod image;
pub mod layout;
pub mod read;
pub mod records;

pub use checked::{holder_bytes, CheckedSet};

// The runtime reads the mask pool's words as the bytes the encoder packed into them, little-endian.
const _: () = assert!(cfg!(target_endian = "little"), "the tables are read as little-endian words");

/// Most automata in one set: one bit each in a `u32` of [`SupervisorSet::holders`].
pub const MAX_AUTOMATA: usize = 32;
/// Most events in one set: an event id is one byte.
pub const MAX_EVENTS: usize = 256;
/// Most masks in one set: a mask id is at most 2 bytes.
pub const MAX_MASKS: usize = 1 << 16;

/// How the runtime holds a state's position (the module documentation): `u16`, for tables whose
/// positions are all below 65 536, or `u32`. One width per set, the runtime's `Q` parameter.
pub trait Position: Copy + Eq + core::fmt::Debug + 'static {
    /// Bits of a position.
    const BITS: u32;
    /// Largest position.
    const MAX: usize;
    /// Position `at`, truncated to the type: the callers pass positions the check proved at most
    /// [`Position::MAX`].
    fn at(at: usize) -> Self;
    /// The position as an index.
    fn get(self) -> usize;
}

impl Position for u16 {
    const BITS: u32 = 16;
    const MAX: usize = u16::MAX as usize;

    #[inline(always)]
    fn at(at: usize) -> Self {
        at as u16
    }

    #[inline(always)]
    fn get(self) -> usize {
        usize::from(self)
    }
}

impl Position for u32 {
    const BITS: u32 = 32;
    const MAX: usize = u32::MAX as usize;

    #[inline(always)]
    fn at(at: usize) -> Self {
        at as u32
    }

    #[inline(always)]
    fn get(self) -> usize {
        self as usize
    }
}

/// One automaton of the set: where its records are and how to read them. Laid out as C lays it out
/// (the alphabet's words, the start, the scale, padding), as the tables' [`image`] holds it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Automaton<const W: usize, Q = u16> {
    /// Bitset over global event ids (bit `e % 32` of word `e / 32`): the automaton's alphabet. An event
    /// outside it never moves or blocks the automaton.
    pub alphabet: [u32; W],
    /// Byte offset in the set's block of its first record, the initial state's (handle 0) in `ranked`
    /// and `indexed`.
    pub start: Q,
    /// Bytes per handle unit: a state's record starts at byte `start + handle · scale` (≥ 1; 1 in the
    /// `memory-safe`, `offset` and `compact` layouts).
    pub scale: u8,
}

/// The whole set the firmware runs: plants and supervisors over one event numbering, events in
/// `W`-word bitsets, positions of type `Q` ([`Position`]). On the target every slice lies in flash
/// (`'t = 'static`); on the host the tables may be borrowed from owned data.
#[derive(Clone, Copy, Debug)]
pub struct SupervisorSet<'t, const W: usize, Q = u16> {
    /// Bitset over global event ids: the controllable ones.
    pub controllable: [u32; W],
    /// The first `plants` automata are the plants (the product system), the others supervisors.
    pub plants: u8,
    /// Plants first, then supervisors, in manifest order; their starts ascending.
    pub automata: &'t [Automaton<W, Q>],
    /// The records of every automaton, in automaton order (see the module documentation).
    pub block: &'t [u8],
    /// Wide fields: mask ids and target handles take 2 bytes (little-endian) instead of 1 in every
    /// record (`ranked`, `indexed`); record targets take 4 bytes instead of 2 (`offset`).
    pub wide: bool,
    /// The pool of distinct out-masks (allowed sets in the `indexed` layout) that records name by id,
    /// as bytes packed little-endian into
    /// words (so that masks of whole words are read with aligned loads): mask `id` is the bitset of the
    /// [`SupervisorSet::mask_bytes`] bytes from byte `id · mask_bytes`, little-endian. The runtime reads
    /// `W` whole words from there, so the pool ends with at least `4 · W − mask_bytes` bytes of
    /// padding; the bits read beyond a mask's own bytes are never events.
    pub masks: &'t [u32],
    /// Bytes per mask in the pool: enough for the event count (`⌈events / 8⌉`, at most `4 · W`).
    pub mask_bytes: u8,
    /// The record layout, one of [`layout`]'s ids: how the block is read.
    pub layout: u8,
    /// Per automaton, its initial state's handle: its record's offset from its start in `memory-safe`
    /// and `offset`, its mask's bit offset in its stream in `compact`. Empty in `ranked` and `indexed`,
    /// whose initial state's record comes first (handle 0), so that their tables carry nothing more.
    pub initials: &'t [Q],
    /// The `indexed` layout's holder lists: first, per global event id and one more, the index in this
    /// table where the event's list starts (the last: the table's length); then the lists, one entry per
    /// automaton holding the event, in index order: the automaton in the low byte, the event's place in
    /// its alphabet (the number of its events below it) in the high byte. Empty in a `ranked` set.
    pub holder_lists: &'t [u16],
    /// Per global event id, [`SupervisorSet::holder_bytes`] bytes, little-endian: bit `a` set when
    /// automaton `a` has the event in its alphabet. Its length is the event count times that width.
    pub holders: &'t [u8],
    /// Per plant: the controllable events it generates (those of its alphabet no earlier plant holds).
    /// Every controllable event belongs to exactly one plant.
    pub plant_events: &'t [[u32; W]],
    /// The *choice sites*, states of a plant where two or more controllable events it generates leave,
    /// each as its position, ascending.
    pub sites: &'t [Q],
}

/// Why a set cannot run: sizes of another build, or tables that break the layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableError {
    /// The automaton count differs from the runtime's, exceeds [`MAX_AUTOMATA`], or the plant count
    /// exceeds it.
    Automata,
    /// More events than `W` words or [`MAX_EVENTS`] hold, a holder table of another width, a holder bit
    /// naming no automaton or one without the event in its alphabet, a controllable event beyond the
    /// event count, a per-plant table of another length, or holder lists (`indexed` layout) that are not
    /// each event's holders in index order with its places, or lie outside their table.
    Events,
    /// A choice site that starts no record of a plant.
    Sites,
    /// The set's field or mask width, position type or record layout is not the one the runtime was
    /// built for, or a layout id the runtime does not know.
    Shape,
    /// More than [`MAX_MASKS`] masks, a mask width that does not fit the events and `W` words, or (in
    /// the `indexed` layout) masks of other than whole words.
    Size,
    /// Automaton `0` starts out of order or beyond the block, has a scale of 0, a record outside its part
    /// of the block or naming no mask, an out-event outside its alphabet (an allowed set without an event
    /// outside it, in the `indexed` layout), a target handle that starts no record, or a position beyond
    /// the set's [`Position`] type.
    Block(u8),
}

/// The place of event `e` in `alphabet`: the number of its events below `e`.
const fn place<const W: usize>(alphabet: &[u32; W], e: usize) -> usize {
    let mut n = 0;
    let mut w = 0;
    while w < e / 32 {
        n += alphabet[w].count_ones() as usize;
        w += 1;
    }
    n + (alphabet[e / 32] & ((1u32 << (e % 32)) - 1)).count_ones() as usize
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

    /// The event's id, as an index.
    #[inline(always)]
    pub fn index(self) -> usize {
        usize::from(self.0)
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

/// Whether bit `event` is set in `words`.
#[inline(always)]
pub fn bit<const W: usize>(words: &[u32; W], event: u8) -> bool {
    Event::new(event).in_set(words)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Two states: 0 –e0→ 1, 1 –e1→ 0; masks {e0} (id 0) and {e1} (id 1); scale 2, so handle 1 is byte 2.
    pub(crate) static TOGGLE: SupervisorSet<'static, 1> = SupervisorSet {
        controllable: [0b01],
        plants: 1,
        automata: &[Automaton { alphabet: [0b11], start: 0, scale: 2 }],
        block: &[0, 1, 1, 0],
        wide: false,
        // Masks {e0} and {e1}, a byte each, then padding to read a word from the last.
        masks: &[0x0201, 0],
        mask_bytes: 1,
        layout: layout::RANKED,
        initials: &[],
        holder_lists: &[],
        holders: &[1, 1],
        plant_events: &[[0b01]],
        sites: &[],
    };

    pub(crate) fn toggle() -> SupervisorSet<'static, 1> {
        TOGGLE
    }

    #[test]
    fn step_follows_handles() {
        let t = toggle();
        assert_eq!(t.step(0, 0, 0), Some(1));
        assert_eq!(t.step(0, 1, 1), Some(0));
        assert_eq!(t.step(0, 0, 1), None);
        assert_eq!(t.mask(0, 1), Some([0b10]));
    }

    #[test]
    fn out_of_table_is_none_not_panic() {
        let t = toggle();
        assert_eq!(t.step(0, 200, 0), None);
        assert_eq!(t.step(3, 0, 0), None);
        assert_eq!(t.step(0, 0, 255), None);
    }

    #[test]
    fn records_and_what_they_allow() {
        let t = toggle();
        let aut = &t.automata[0];
        assert_eq!(t.handle_of(aut, 2), 1);
        assert_eq!(t.holders_of(1, t.holder_bytes()), Some(1));
        assert_eq!(t.holders_of(2, t.holder_bytes()), None);
        // SAFETY: the toggle passes the check (see `check`'s tests) and byte 2 starts its state 1.
        let allowed = unsafe { t.allowed_at::<false, 1, { layout::RANKED }>(aut, 2) };
        assert_eq!(allowed, [!0b01]);
    }
}
