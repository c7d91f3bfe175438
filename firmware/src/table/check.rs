//! The check that makes the runtime's unchecked reads sound, as a `const fn`: the emitted tables run it
//! at compile time, host tools at run time.

use super::{Automaton, SupervisorSet, TableError, MAX_AUTOMATA, MAX_BLOCK, MAX_EVENTS, MAX_MASKS};

/// A set that passed [`SupervisorSet::check`] for `N` automata: the only form the runtime takes. The
/// emitted tables build theirs in a `static`, so the check runs in the compiler and a set that fails it
/// does not build; host tools build theirs at run time.
#[derive(Clone, Copy, Debug)]
pub struct CheckedSet<'t, const W: usize, const N: usize>(&'t SupervisorSet<'t, W>);

impl<'t, const W: usize, const N: usize> CheckedSet<'t, W, N> {
    /// `set`, if it passes the check for `N` automata.
    pub const fn new(set: &'t SupervisorSet<'t, W>) -> Result<Self, TableError> {
        match set.check(N) {
            Ok(()) => Ok(Self(set)),
            Err(e) => Err(e),
        }
    }

    /// The set.
    pub const fn set(&self) -> &'t SupervisorSet<'t, W> {
        self.0
    }
}

/// Field `i` of the record at byte `at` of `block` (the mask id, then the targets), 1 or 2 bytes
/// little-endian, if it lies in `block`.
pub(super) const fn field(block: &[u8], wide: bool, at: usize, i: usize) -> Option<u16> {
    if wide {
        let p = at + 2 * i;
        if p + 1 < block.len() {
            return Some(u16::from_le_bytes([block[p], block[p + 1]]));
        }
    } else if at + i < block.len() {
        return Some(block[at + i] as u16);
    }
    None
}

/// Whether handle `h` is below `handles` and, when in the 256 handles from `base`, marked in `starts`.
const fn marked(starts: &[u32; 8], base: usize, handles: usize, h: usize) -> bool {
    let i = h.wrapping_sub(base);
    h < handles && (i >= 256 || starts[i / 32] & (1 << (i % 32)) != 0)
}

/// Bytes of one event's holder mask in a set of `automata` automata: one bit per automaton, at least one
/// byte.
pub const fn holder_bytes(automata: usize) -> usize {
    if automata <= 8 {
        1
    } else {
        automata.div_ceil(8)
    }
}

/// The little-endian holder mask of `width` bytes at `at` of `holders`, if it lies there.
pub(super) const fn holder_mask(holders: &[u8], at: usize, width: usize) -> Option<u32> {
    if at + width > holders.len() || width > 4 {
        return None;
    }
    let mut mask = 0;
    let mut i = 0;
    while i < width {
        mask |= (holders[at + i] as u32) << (8 * i);
        i += 1;
    }
    Some(mask)
}

impl<'t, const W: usize> SupervisorSet<'t, W> {
    /// Bytes of one event's holder mask: [`holder_bytes`] of the automaton count.
    pub const fn holder_bytes(&self) -> usize {
        holder_bytes(self.automata.len())
    }

    /// Number of events (ids `0..events`).
    pub const fn events(&self) -> usize {
        self.holders.len() / self.holder_bytes()
    }

    /// The bytes of automaton `a`'s records: from its start to the next automaton's (the block's end for
    /// the last). Empty when the starts are out of order or beyond the block.
    pub(super) const fn part(&self, a: usize) -> (usize, usize) {
        let start = self.automata[a].start as usize;
        let end =
            if a + 1 < self.automata.len() { self.automata[a + 1].start as usize } else { self.block.len() };
        if start < end && end <= self.block.len() {
            (start, end)
        } else {
            (0, 0)
        }
    }

    /// Checks everything the runtime's unchecked reads rely on, for a runtime of `automata` automata:
    /// sizes, every holder holding the event in its alphabet, every automaton's records (see the module
    /// documentation) and every choice site a plant's state.
    /// Linear in the size of the tables (times the handle count / 256 for automata of more than 256
    /// handle units).
    pub const fn check(&self, automata: usize) -> Result<(), TableError> {
        let plants = self.plants as usize;
        if self.automata.len() != automata || automata > MAX_AUTOMATA || plants > automata {
            return Err(TableError::Automata);
        }
        if self.masks.len() > MAX_MASKS {
            return Err(TableError::Size);
        }
        let width = holder_bytes(automata);
        let events = self.holders.len() / width;
        if self.holders.len() % width != 0
            || events > MAX_EVENTS
            || events > 32 * W
            || self.plant_events.len() != plants
        {
            return Err(TableError::Events);
        }
        // Controllable events are events of the set: the runtime fires them through their holders.
        let mut w = 0;
        while w < W {
            let below = if 32 * w >= events {
                0
            } else if events - 32 * w >= 32 {
                u32::MAX
            } else {
                (1u32 << (events - 32 * w)) - 1
            };
            if self.controllable[w] & !below != 0 {
                return Err(TableError::Events);
            }
            w += 1;
        }
        let all = if automata == MAX_AUTOMATA { u32::MAX } else { (1u32 << automata) - 1 };
        let mut e = 0;
        while e < events {
            let Some(holders) = holder_mask(self.holders, e * width, width) else {
                return Err(TableError::Events);
            };
            if holders & !all != 0 {
                return Err(TableError::Events);
            }
            // A holder has the event in its alphabet: the runtime steps it only on such events.
            let mut a = 0;
            while a < automata {
                if holders & (1 << a) != 0 && self.automata[a].alphabet[e / 32] & (1 << (e % 32)) == 0 {
                    return Err(TableError::Events);
                }
                a += 1;
            }
            e += 1;
        }
        let mut a = 0;
        while a < automata {
            if !self.part_sound(a) {
                // At most MAX_AUTOMATA automata: the index fits a byte.
                return Err(TableError::Block(a as u8));
            }
            a += 1;
        }
        let mut i = 0;
        while i < self.sites.len() {
            if !self.is_plant_record(self.sites[i] as usize) {
                return Err(TableError::Sites);
            }
            i += 1;
        }
        Ok(())
    }

    /// The record of `aut` at byte `at`, if it ends by `end` and names a mask: mask id, target count and
    /// the byte after it.
    pub(super) const fn record_at(
        &self,
        aut: &Automaton<W>,
        at: usize,
        end: usize,
    ) -> Option<(usize, usize, usize)> {
        let id = match field(self.block, aut.wide, at, 0) {
            Some(id) => id as usize,
            None => return None,
        };
        if id >= self.masks.len() {
            return None;
        }
        let mut n = 0;
        let mut w = 0;
        while w < W {
            n += self.masks[id][w].count_ones() as usize;
            w += 1;
        }
        let next = at + (n + 1) * if aut.wide { 2 } else { 1 };
        if next <= end {
            Some((id, n, next))
        } else {
            None
        }
    }

    /// One automaton: the records tile its part of the block, name masks within the alphabet, start in
    /// the first 64 KiB, and every target handle starts one — checked 256 handles at a time with a
    /// bitmap: a first pass marks the record starts, a second checks the targets.
    const fn part_sound(&self, a: usize) -> bool {
        let aut = &self.automata[a];
        let (start, end) = self.part(a);
        let scale = aut.scale as usize;
        // Handles are 16-bit; an empty part has no initial state.
        if scale == 0 || start == end || (end - start).div_ceil(scale) > 1 << 16 {
            return false;
        }
        let mut base = 0;
        loop {
            let mut starts = [0u32; 8];
            let mut handles = 0;
            let mut pass = 0;
            while pass < 2 {
                let mut at = start;
                while at < end {
                    let Some((id, n, next)) = self.record_at(aut, at, end) else { return false };
                    if pass == 0 {
                        if at >= MAX_BLOCK {
                            return false;
                        }
                        let h = (at - start) / scale;
                        let i = h.wrapping_sub(base);
                        if i < 256 {
                            starts[i / 32] |= 1 << (i % 32);
                        }
                        handles = h + 1;
                        let mut w = 0;
                        while w < W {
                            if self.masks[id][w] & !aut.alphabet[w] != 0 {
                                return false;
                            }
                            w += 1;
                        }
                    } else {
                        let mut r = 0;
                        while r < n {
                            // In the part: `record_at` bounded the record by its end.
                            let Some(t) = field(self.block, aut.wide, at, r + 1) else { return false };
                            if !marked(&starts, base, handles, t as usize) {
                                return false;
                            }
                            r += 1;
                        }
                    }
                    at = start + (next - start).div_ceil(scale) * scale;
                }
                pass += 1;
            }
            base += 256;
            if base >= handles {
                return true;
            }
        }
    }

    /// Whether byte `at` of the block starts a record of a plant.
    const fn is_plant_record(&self, at: usize) -> bool {
        let mut p = 0;
        while p < self.plants as usize {
            let (start, end) = self.part(p);
            if start <= at && at < end {
                let scale = self.automata[p].scale as usize;
                return scale != 0
                    && (at - start) % scale == 0
                    && self.is_state(p, ((at - start) / scale) as u16);
            }
            p += 1;
        }
        false
    }

    /// Whether `handle` starts a record of automaton `a` (a state of it).
    pub const fn is_state(&self, a: usize, handle: u16) -> bool {
        if a >= self.automata.len() {
            return false;
        }
        let aut = &self.automata[a];
        let (start, end) = self.part(a);
        let scale = if aut.scale == 0 { 1 } else { aut.scale as usize };
        let wanted = start + handle as usize * scale;
        let mut at = start;
        while at < wanted {
            let Some((_, _, next)) = self.record_at(aut, at, end) else { return false };
            at = start + (next - start).div_ceil(scale) * scale;
        }
        at == wanted && self.record_at(aut, at, end).is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::toggle;
    use super::*;

    /// The cell-sized check runs in the compiler: this `static` is the proof.
    static CHECKED: CheckedSet<'static, 1, 1> = match CheckedSet::new(&super::super::tests::TOGGLE) {
        Ok(set) => set,
        Err(_) => panic!("the toggle fails the check"),
    };

    #[test]
    fn check_runs_at_compile_time() {
        assert_eq!(CHECKED.set().events(), 2);
    }

    #[test]
    fn check_refuses_broken_blocks() {
        for bad in [&[0u8, 3, 1, 0][..], &[2, 1, 1, 0], &[0, 1, 1]] {
            let t = SupervisorSet { block: bad, ..toggle() };
            assert_eq!(t.check(1), Err(TableError::Block(0)), "{bad:?}");
        }
        // A start beyond the block, and starts out of order.
        let automata = [Automaton { start: 4, ..toggle().automata[0] }];
        assert_eq!(SupervisorSet { automata: &automata, ..toggle() }.check(1), Err(TableError::Block(0)));
        let g = toggle().automata[0];
        let automata = [Automaton { start: 2, ..g }, Automaton { start: 0, ..g }];
        let t = SupervisorSet {
            automata: &automata,
            block: &[0, 1, 1, 0, 0, 1, 1, 0],
            holders: &[3, 3],
            ..toggle()
        };
        assert_eq!(t.check(2), Err(TableError::Block(0)));
        let mut t = toggle();
        t.holders = &[1, 2];
        assert_eq!(t.check(1), Err(TableError::Events));
        // Event 1 held by an automaton whose alphabet lacks it.
        let automata = [Automaton { alphabet: [0b01], ..toggle().automata[0] }];
        let t = SupervisorSet { automata: &automata, masks: &[[0b01], [0b01]], ..toggle() };
        assert_eq!(t.check(1), Err(TableError::Events));
        // A controllable event beyond the event count.
        assert_eq!(SupervisorSet { controllable: [0b101], ..toggle() }.check(1), Err(TableError::Events));
        // Sites are record starts of plants.
        assert_eq!(SupervisorSet { sites: &[2], ..toggle() }.check(1), Ok(()));
        assert_eq!(SupervisorSet { sites: &[1], ..toggle() }.check(1), Err(TableError::Sites));
        assert_eq!(
            SupervisorSet { sites: &[2], plants: 0, plant_events: &[], ..toggle() }.check(1),
            Err(TableError::Sites)
        );
        assert_eq!(toggle().check(2), Err(TableError::Automata));
        assert!(CheckedSet::<1, 2>::new(&super::super::tests::TOGGLE).is_err());
    }

    #[test]
    fn holder_masks_take_a_byte_per_eight_automata() {
        assert_eq!((holder_bytes(0), holder_bytes(8), holder_bytes(9), holder_bytes(32)), (1, 1, 2, 4));
        assert_eq!(holder_mask(&[0x34, 0x12, 0x56], 0, 2), Some(0x1234));
        assert_eq!(holder_mask(&[0x34, 0x12, 0x56], 2, 2), None);
    }

    #[test]
    fn states_are_record_starts() {
        let t = toggle();
        assert!(t.is_state(0, 0));
        assert!(t.is_state(0, 1));
        assert!(!t.is_state(0, 2));
        assert!(!t.is_state(1, 0));
    }
}
