//! Reading the tables: checked readers for host tools and tests, and the runtime's hot path, which
//! reads without bounds checks what [`SupervisorSet::check`] proved in bounds.

use super::checked::field;
use super::layout::{COMPACT, INDEXED, MEMORY_SAFE, OFFSET, RANKED};
use super::{place, rank, Automaton, Event, Position, SupervisorSet};

/// Field `i` of the record at byte `at` (the mask id, then the targets), of 2 bytes when `WIDE`, read
/// without bounds checks.
///
/// # Safety
///
/// The field lies in `block`.
#[inline(always)]
unsafe fn field_unchecked<const WIDE: bool>(block: &[u8], at: usize, i: usize) -> u16 {
    // SAFETY: the caller's promise.
    unsafe {
        if WIDE {
            let p = at + 2 * i;
            u16::from_le_bytes([*block.get_unchecked(p), *block.get_unchecked(p + 1)])
        } else {
            u16::from(*block.get_unchecked(at + i))
        }
    }
}

impl<'t, const W: usize, Q: Position> SupervisorSet<'t, W, Q> {
    /// Byte offset in the block of the record of `aut`'s state `handle`.
    #[inline(always)]
    pub(crate) fn record(aut: &Automaton<W, Q>, handle: usize) -> usize {
        aut.start.get() + handle * usize::from(aut.scale)
    }

    /// The automata holding `event` (bit `a` for automaton `a`), holder masks taking `width` bytes
    /// ([`SupervisorSet::holder_bytes`]; the runtime passes the constant of its automaton count), or
    /// `None` when `event` is no event of the set.
    #[inline(always)]
    pub fn holders_of(&self, event: u8, width: usize) -> Option<u32> {
        let at = usize::from(event) * width;
        // Inlined with the runtime's constant width, this is one load.
        let mut mask = [0; 4];
        mask.get_mut(..width)?.copy_from_slice(self.holders.get(at..at + width)?);
        Some(u32::from_le_bytes(mask))
    }

    /// The position of `aut`'s state `handle` (see the module documentation of [`super`]): in `ranked`
    /// and `indexed` its record's byte offset, in `memory-safe` and `offset` too, in `compact` its mask's
    /// bit offset in the block.
    pub fn position(&self, aut: &Automaton<W, Q>, handle: Q) -> usize {
        self.position_in(self.layout, aut, handle)
    }

    /// [`SupervisorSet::position`] in layout `layout`: the runtime passes its constant, so that its build
    /// carries its own layout's arm only.
    #[inline(always)]
    pub fn position_in(&self, layout: u8, aut: &Automaton<W, Q>, handle: Q) -> usize {
        match layout {
            RANKED | INDEXED => Self::record(aut, handle.get()),
            COMPACT => self.compact_stream(aut).unwrap_or(0) + handle.get(),
            _ => aut.start.get() + handle.get(),
        }
    }

    /// The out-mask of automaton `a`'s state `handle`, or `None` when it lies outside the tables. (A
    /// handle that is no state gives a meaningless but harmless answer.)
    pub fn mask(&self, a: usize, handle: Q) -> Option<[u32; W]> {
        let aut = self.automata.get(a)?;
        let at = self.position(aut, handle);
        match self.layout {
            RANKED | INDEXED => {}
            COMPACT => return self.compact_events(aut, at),
            _ => return self.record_events(at),
        }
        let id = field(self.block, self.wide, at, 0)?;
        let mut mask = self.mask_of(usize::from(id))?;
        if self.layout == INDEXED {
            // The pool holds what the state allows: its out-events are those of the alphabet.
            for (m, al) in mask.iter_mut().zip(&aut.alphabet) {
                *m &= al;
            }
        }
        Some(mask)
    }

    /// The handle reached from automaton `a`'s state `handle` by `event`, or `None` when the state has
    /// no such transition (or the handle lies outside the tables).
    pub fn step(&self, a: usize, handle: Q, event: u8) -> Option<Q> {
        let aut = self.automata.get(a)?;
        let at = self.position(aut, handle);
        match self.layout {
            RANKED | INDEXED => {}
            COMPACT => return self.compact_step(aut, at, event),
            _ => return self.record_step(aut, at, event),
        }
        let mask = self.mask(a, handle)?;
        let id = Event::new(event);
        if !id.in_set(&mask) {
            return None;
        }
        let i =
            if self.layout == INDEXED { place(&aut.alphabet, usize::from(event)) } else { rank(&mask, id) };
        field(self.block, self.wide, at, i + 1).map(|t| Q::at(usize::from(t)))
    }

    /// The handle of `aut`'s state at position `at` (see [`SupervisorSet::position`]).
    pub fn handle_of(&self, aut: &Automaton<W, Q>, at: Q) -> Q {
        let from = |base: usize| Q::at(at.get().wrapping_sub(base));
        match self.layout {
            RANKED | INDEXED => Q::at(at.get().wrapping_sub(aut.start.get()) / usize::from(aut.scale.max(1))),
            COMPACT => from(self.compact_stream(aut).unwrap_or(0)),
            _ => from(aut.start.get()),
        }
    }

    /// What `aut` allows in its state at position `at`: its out-mask and every event outside its
    /// alphabet (which the pool holds as it is in the `indexed` layout). Reads without bounds checks,
    /// with the widths `WIDE` and `MASK` and the layout `LAYOUT`.
    ///
    /// # Safety
    ///
    /// [`crate::table::CheckedSet::new`] returned `Ok` for this set, `WIDE`, `MASK` and `LAYOUT`, `aut`
    /// is one of its automata and `at` the position of one of its states.
    #[inline(always)]
    pub unsafe fn allowed_at<const WIDE: bool, const MASK: usize, const LAYOUT: u8>(
        &self,
        aut: &Automaton<W, Q>,
        at: Q,
    ) -> [u32; W] {
        match LAYOUT {
            RANKED | INDEXED => {}
            // SAFETY: the caller's promise.
            COMPACT => return unsafe { self.compact_allowed(aut, at) },
            // SAFETY: the caller's promise.
            _ => return unsafe { self.records_allowed::<WIDE>(aut, at) },
        }
        // SAFETY: the check proved every state's record in the block and its mask id in the pool, which
        // is padded for `W` words from the last mask.
        let mut allowed = unsafe {
            let id = usize::from(field_unchecked::<WIDE>(self.block, at.get(), 0));
            let mut mask = [0; W];
            if MASK.is_multiple_of(4) {
                // Masks of whole words: aligned loads.
                let words = self.masks.get_unchecked(id * (MASK / 4)..);
                for (w, word) in mask.iter_mut().enumerate() {
                    *word = *words.get_unchecked(w);
                }
            } else {
                // The pool's bytes, which its words hold little-endian as the targets store them.
                let bytes =
                    core::slice::from_raw_parts(self.masks.as_ptr().cast::<u8>(), 4 * self.masks.len());
                let bytes = bytes.get_unchecked(id * MASK..);
                for (w, word) in mask.iter_mut().enumerate() {
                    let b = bytes.get_unchecked(4 * w..4 * w + 4);
                    *word = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                }
            }
            mask
        };
        if LAYOUT == RANKED {
            // Bits beyond the mask's own bytes are no events, and no events are in the alphabet: allowed.
            for (m, al) in allowed.iter_mut().zip(&aut.alphabet) {
                *m |= !al;
            }
        }
        allowed
    }

    /// Moves `aut` by `event` from its state at position `at`, which allows `allowed` (holding `event`,
    /// an event of the alphabet): both become the target's. In the `indexed` layout `place` is the
    /// event's place in the alphabet; the `ranked` layout ranks the event in the state's mask instead,
    /// the others search or rank the state's record. Reads without bounds checks.
    ///
    /// # Safety
    ///
    /// As for [`SupervisorSet::allowed_at`], and `LAYOUT` is the set's layout; `allowed` is what that
    /// state allows and holds `event`, an event of `aut`'s alphabet, whose place is `place` in the
    /// `indexed` layout.
    #[inline(always)]
    pub unsafe fn advance<const WIDE: bool, const MASK: usize, const LAYOUT: u8>(
        &self,
        aut: &Automaton<W, Q>,
        at: &mut Q,
        allowed: &mut [u32; W],
        event: Event,
        place: usize,
    ) {
        // SAFETY (all arms): the caller's promise; the event leaves the state.
        let next = match LAYOUT {
            RANKED | INDEXED => None,
            MEMORY_SAFE => Some(unsafe { self.records_next::<true, WIDE>(aut, *at, event) }),
            OFFSET => Some(unsafe { self.records_next::<false, WIDE>(aut, *at, event) }),
            _ => Some(unsafe { self.compact_next(aut, *at, event) }),
        };
        if let Some(next) = next {
            *at = next;
            // SAFETY: the target is one of the automaton's states.
            *allowed = unsafe { self.allowed_at::<WIDE, MASK, LAYOUT>(aut, next) };
            return;
        }
        let i = if LAYOUT == INDEXED {
            place
        } else {
            let mut mask = *allowed;
            for (m, al) in mask.iter_mut().zip(&aut.alphabet) {
                *m &= al;
            }
            rank(&mask, event)
        };
        // SAFETY: the record holds a target per mask bit (per alphabet event when `INDEXED`); the
        // target of a checked set's record is one of its states, whose record starts at a position `Q`
        // holds.
        unsafe {
            let target = field_unchecked::<WIDE>(self.block, at.get(), i + 1);
            *at = Q::at(Self::record(aut, usize::from(target)));
            *allowed = self.allowed_at::<WIDE, MASK, LAYOUT>(aut, *at);
        }
    }
}
