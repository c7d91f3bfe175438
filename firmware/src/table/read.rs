//! Reading the tables: checked readers for host tools and tests, and the runtime's hot path, which
//! reads without bounds checks what [`SupervisorSet::check`] proved in bounds.

use super::check::field;
use super::{rank, Automaton, Event, Slot, SupervisorSet};

/// Field `i` of the record at byte `at` (the mask id, then the targets), read without bounds checks.
///
/// # Safety
///
/// The field lies in `blocks`.
#[inline(always)]
unsafe fn field_unchecked(blocks: &[u8], wide: bool, at: usize, i: usize) -> u16 {
    // SAFETY: the caller's promise.
    unsafe {
        if wide {
            let p = at + 2 * i;
            u16::from_le_bytes([*blocks.get_unchecked(p), *blocks.get_unchecked(p + 1)])
        } else {
            u16::from(*blocks.get_unchecked(at + i))
        }
    }
}

impl<'t, const W: usize> SupervisorSet<'t, W> {
    /// Byte offset in [`SupervisorSet::blocks`] of the record of `aut`'s state `handle`.
    #[inline(always)]
    pub(super) fn record(aut: &Automaton<W>, handle: u16) -> usize {
        aut.start as usize + usize::from(handle) * usize::from(aut.scale)
    }

    /// The out-mask of automaton `a`'s state `handle`, or `None` when it lies outside the tables. (A
    /// handle that starts no record gives a meaningless but harmless answer.)
    pub fn mask(&self, a: usize, handle: u16) -> Option<&'t [u32; W]> {
        let aut = self.automata.get(a)?;
        let id = field(self.blocks, aut.wide, Self::record(aut, handle), 0)?;
        self.masks.get(usize::from(id))
    }

    /// The handle reached from automaton `a`'s state `handle` by `event`, or `None` when the state has
    /// no such transition (or the handle lies outside the tables).
    pub fn step(&self, a: usize, handle: u16, event: u8) -> Option<u16> {
        let mask = self.mask(a, handle)?;
        let event = Event::new(event);
        if !event.in_set(mask) {
            return None;
        }
        let aut = self.automata.get(a)?;
        field(self.blocks, aut.wide, Self::record(aut, handle), rank(mask, event) + 1)
    }

    /// The out-mask of the state in `slot` (`None` if the slot names no mask of the set).
    pub fn mask_of(&self, slot: Slot) -> Option<&'t [u32; W]> {
        self.masks.get(slot.mask_id())
    }

    /// The index of the site of the state in `slot`, if it is one. A scan: sites are states of the
    /// plants, small automata, so there are few, and the scan beats a binary search's bookkeeping.
    pub fn site(&self, slot: Slot) -> Option<usize> {
        let at = slot.record() as u32;
        self.sites.iter().position(|&s| s == at)
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
        unsafe { self.masks.get_unchecked(slot.mask_id()) }
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
        // SAFETY: the check proved every state's record in the blocks and its id in the pool, both
        // within a slot's fields.
        Slot::new(at, unsafe { field_unchecked(self.blocks, aut.wide, at, 0) })
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
        // SAFETY: the record holds a target per mask bit, and the target of a checked set's record is one
        // of its states.
        unsafe {
            let target = field_unchecked(self.blocks, aut.wide, slot.record(), rank(mask, event) + 1);
            *slot = self.slot_unchecked(aut, target);
        }
    }
}
