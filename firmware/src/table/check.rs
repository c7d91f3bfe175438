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

impl<'t, const W: usize> SupervisorSet<'t, W> {
    /// Number of events (ids `0..events`).
    pub const fn events(&self) -> usize {
        self.holders.len()
    }

    /// Checks everything the runtime's unchecked reads rely on, for a runtime of `automata` automata:
    /// sizes, every holder holding the event in its alphabet, and every block (see the module
    /// documentation).
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
        let events = self.events();
        if events > MAX_EVENTS || events > 32 * W || self.plant_events.len() != plants {
            return Err(TableError::Events);
        }
        let all = if automata == MAX_AUTOMATA { u32::MAX } else { (1u32 << automata) - 1 };
        let mut e = 0;
        while e < events {
            let holders = self.holders[e];
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
            if !self.block_sound(a) {
                // At most MAX_AUTOMATA automata: the index fits a byte.
                return Err(TableError::Block(a as u8));
            }
            a += 1;
        }
        Ok(())
    }

    /// The record of `aut` at byte `at`, if it lies in the block and names a mask: mask id, target count
    /// and the byte after it.
    pub(super) const fn record_at(&self, aut: &Automaton<'t, W>, at: usize) -> Option<(usize, usize, usize)> {
        let id = match field(aut.block, aut.wide, at, 0) {
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
        if next <= aut.block.len() {
            Some((id, n, next))
        } else {
            None
        }
    }

    /// One automaton: the records tile the block, name masks within the alphabet, and every target and
    /// the initial handle start one — checked 256 handles at a time with a bitmap: a first pass marks
    /// the record starts, a second checks the targets.
    const fn block_sound(&self, a: usize) -> bool {
        let aut = &self.automata[a];
        let end = aut.block.len();
        let scale = aut.scale as usize;
        // Handles are 16-bit, record offsets too.
        if scale == 0 || end.div_ceil(scale) > 1 << 16 {
            return false;
        }
        let mut base = 0;
        loop {
            let mut starts = [0u32; 8];
            let mut handles = 0;
            let mut pass = 0;
            while pass < 2 {
                if pass == 1 && !marked(&starts, base, handles, aut.initial as usize) {
                    return false;
                }
                let mut at = 0;
                while at < end {
                    let Some((id, n, next)) = self.record_at(aut, at) else { return false };
                    if pass == 0 {
                        if at >= MAX_BLOCK {
                            return false;
                        }
                        let h = at / scale;
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
                            // In the block: `record_at` bounded the record by the block's end.
                            let Some(t) = field(aut.block, aut.wide, at, r + 1) else { return false };
                            if !marked(&starts, base, handles, t as usize) {
                                return false;
                            }
                            r += 1;
                        }
                    }
                    at = next.div_ceil(scale) * scale;
                }
                pass += 1;
            }
            base += 256;
            if base >= handles {
                return true;
            }
        }
    }

    /// Whether `handle` starts a record of automaton `a` (a state of it).
    pub fn is_state(&self, a: usize, handle: u16) -> bool {
        let Some(aut) = self.automata.get(a) else { return false };
        let scale = usize::from(aut.scale).max(1);
        let wanted = usize::from(handle) * scale;
        let mut at = 0;
        while at < wanted {
            let Some((_, _, next)) = self.record_at(aut, at) else { return false };
            at = next.div_ceil(scale) * scale;
        }
        at == wanted && self.record_at(aut, at).is_some()
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
            let automata = [Automaton { block: bad, ..toggle().automata[0] }];
            let t = SupervisorSet { automata: &automata, ..toggle() };
            assert_eq!(t.check(1), Err(TableError::Block(0)), "{bad:?}");
        }
        let mut t = toggle();
        t.holders = &[1, 2];
        assert_eq!(t.check(1), Err(TableError::Events));
        // Event 1 held by an automaton whose alphabet lacks it.
        let automata = [Automaton { alphabet: [0b01], ..toggle().automata[0] }];
        let t = SupervisorSet { automata: &automata, masks: &[[0b01], [0b01]], ..toggle() };
        assert_eq!(t.check(1), Err(TableError::Events));
        assert_eq!(toggle().check(2), Err(TableError::Automata));
        assert!(CheckedSet::<1, 2>::new(&super::super::tests::TOGGLE).is_err());
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
