//! This module is the home of [`CheckedSet`] and of the check behind it that makes the runtime's
//! unchecked reads sound. It runs on the host — in `codegen` when it writes the tables, in the build
//! script that compiles them ([`super::image`]), in host tools and tests — and costs the firmware
//! nothing; a firmware may also run it at boot ([`CheckedSet::new`]).

use super::layout::{self, COMPACT, INDEXED, OFFSET, RANKED};
use super::{place, Position, SupervisorSet, TableError, MAX_AUTOMATA, MAX_EVENTS, MAX_MASKS};

/// A set that passed [`SupervisorSet::check`] for `N` automata, with wide fields exactly when `WIDE`
/// ([`SupervisorSet::wide`]), masks of `MASK` bytes ([`SupervisorSet::mask_bytes`]; 0 in the layouts
/// without a pool), the layout `LAYOUT` ([`SupervisorSet::layout`], one of [`layout`]'s ids) and
/// positions of type `Q`: the only form the runtime takes. Host tools build theirs with
/// [`CheckedSet::new`]; the emitted tables build theirs with [`super::image::checked`], from a check
/// their build script ran. The widths, the layout and the position type are type parameters so that
/// the runtime's steps are compiled for them.
#[derive(Clone, Copy, Debug)]
pub struct CheckedSet<
    't,
    const W: usize,
    const N: usize,
    const WIDE: bool,
    const MASK: usize,
    const LAYOUT: u8,
    Q = u16,
>(&'t SupervisorSet<'t, W, Q>);

impl<'t, const W: usize, const N: usize, const WIDE: bool, const MASK: usize, const LAYOUT: u8, Q>
    CheckedSet<'t, W, N, WIDE, MASK, LAYOUT, Q>
{
    /// Whether `set` has the shape of this type: `N` automata, the widths `WIDE` and `MASK`, the layout
    /// `LAYOUT` (positions are `Q` by the set's type). Constant time.
    pub(super) const fn fits(set: &SupervisorSet<'t, W, Q>) -> bool {
        set.wide == WIDE && set.mask_bytes as usize == MASK && set.layout == LAYOUT && set.automata.len() == N
    }

    /// `set`, trusted to pass the check: what [`super::image::checked`] builds once the build script
    /// proved it.
    pub(super) const fn trusted(set: &'t SupervisorSet<'t, W, Q>) -> Self {
        Self(set)
    }

    /// The set.
    pub const fn set(&self) -> &'t SupervisorSet<'t, W, Q> {
        self.0
    }
}

impl<
        't,
        const W: usize,
        const N: usize,
        const WIDE: bool,
        const MASK: usize,
        const LAYOUT: u8,
        Q: Position,
    > CheckedSet<'t, W, N, WIDE, MASK, LAYOUT, Q>
{
    /// `set`, if it passes the check for `N` automata and has the widths `WIDE` and `MASK` and the
    /// layout `LAYOUT`. Linear in the tables (see [`SupervisorSet::check`]).
    pub fn new(set: &'t SupervisorSet<'t, W, Q>) -> Result<Self, TableError> {
        if set.wide != WIDE || usize::from(set.mask_bytes) != MASK || set.layout != LAYOUT {
            return Err(TableError::Shape);
        }
        set.check(N)?;
        Ok(Self(set))
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
pub(super) const fn marked(starts: &[u32; 8], base: usize, handles: usize, h: usize) -> bool {
    let i = h.wrapping_sub(base);
    h < handles && (i >= 256 || starts[i / 32] & (1 << (i % 32)) != 0)
}

/// The bits of word `w` of an event bitset that stand for no event of a set of `events` events.
const fn beyond(events: usize, w: usize) -> u32 {
    if 32 * w >= events {
        u32::MAX
    } else if events - 32 * w >= 32 {
        0
    } else {
        u32::MAX << (events - 32 * w)
    }
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

/// The little-endian holder mask of `width` bytes at `at` of `holders`, if it lies there: the check's
/// reader (a `const fn`); the runtime reads through [`SupervisorSet::holders_of`], which its constant
/// width turns into one load.
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

impl<'t, const W: usize, Q: Position> SupervisorSet<'t, W, Q> {
    /// Bytes of one event's holder mask: [`holder_bytes`] of the automaton count.
    pub fn holder_bytes(&self) -> usize {
        holder_bytes(self.automata.len())
    }

    /// Number of events (ids `0..events`).
    pub fn events(&self) -> usize {
        self.holders.len() / self.holder_bytes()
    }

    /// Number of masks the pool holds with the padding that lets the runtime read `W` words of the
    /// last, if its mask width fits `W` words (and is a whole number of words in the `indexed` layout).
    /// The pool is whole words, so up to 3 bytes of padding beyond may count as masks: masks the encoder
    /// never names, read as safely as the others.
    pub fn mask_count(&self) -> Option<usize> {
        let stride = self.mask_bytes as usize;
        if stride == 0 || stride > 4 * W || (self.layout == INDEXED && !stride.is_multiple_of(4)) {
            return None;
        }
        let (bytes, pad) = (4 * self.masks.len(), 4 * W - stride);
        if bytes < pad + stride {
            return Some(0);
        }
        Some((bytes - pad) / stride)
    }

    /// Byte `i` of the mask pool (bytes are packed little-endian into its words).
    pub(super) fn pool_byte(&self, i: usize) -> u8 {
        (self.masks[i / 4] >> (8 * (i % 4))) as u8
    }

    /// Mask `id` of the pool (its own bytes only), if the pool has it.
    pub fn mask_of(&self, id: usize) -> Option<[u32; W]> {
        match self.mask_count() {
            Some(count) if id < count => {}
            _ => return None,
        }
        let stride = self.mask_bytes as usize;
        let mut mask = [0u32; W];
        let mut i = 0;
        while i < stride {
            mask[i / 4] |= (self.pool_byte(id * stride + i) as u32) << (8 * (i % 4));
            i += 1;
        }
        Some(mask)
    }

    /// The bytes of automaton `a`'s records: from its start to the next automaton's (the block's end for
    /// the last). Empty when the starts are out of order or beyond the block.
    pub(super) fn part(&self, a: usize) -> (usize, usize) {
        let start = self.automata[a].start.get();
        let end =
            if a + 1 < self.automata.len() { self.automata[a + 1].start.get() } else { self.block.len() };
        if start < end && end <= self.block.len() {
            (start, end)
        } else {
            (0, 0)
        }
    }

    /// Checks everything the runtime's unchecked reads rely on, for a runtime of `automata` automata:
    /// sizes, every holder holding the event in its alphabet, the holder lists, every automaton's records
    /// (see the module documentation) and every choice site a plant's state.
    /// Linear in the size of the tables (times the handle count / 256 for `ranked` automata of more than
    /// 256 handle units; an `indexed` automaton's records, all as long, are checked in one pass).
    pub fn check(&self, automata: usize) -> Result<(), TableError> {
        let plants = self.plants as usize;
        if self.automata.len() != automata || automata > MAX_AUTOMATA || plants > automata {
            return Err(TableError::Automata);
        }
        let width = holder_bytes(automata);
        let events = self.holders.len() / width;
        if !self.holders.len().is_multiple_of(width)
            || events > MAX_EVENTS
            || events > 32 * W
            || self.plant_events.len() != plants
        {
            return Err(TableError::Events);
        }
        if !matches!(self.layout, layout::RANKED..=layout::COMPACT) {
            return Err(TableError::Shape);
        }
        match self.mask_count() {
            // The bits the runtime reads beyond a mask's own bytes are no events.
            Some(count) if count <= MAX_MASKS && events <= 8 * self.mask_bytes as usize => {}
            // Layouts without a pool have no masks; of them only `offset` has wide fields (targets).
            _ if !layout::has_pool(self.layout)
                && self.masks.is_empty()
                && self.mask_bytes == 0
                && (!self.wide || self.layout == OFFSET) => {}
            _ => return Err(TableError::Size),
        }
        // Controllable events are events of the set: the runtime fires them through their holders.
        let mut w = 0;
        while w < W {
            if self.controllable[w] & beyond(events, w) != 0 {
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
        if !self.lists_sound(events) {
            return Err(TableError::Events);
        }
        // One initial handle per automaton where the layout has them (checked with each automaton).
        let initials = if layout::has_pool(self.layout) { 0 } else { automata };
        if self.initials.len() != initials {
            return Err(TableError::Automata);
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
            if !self.is_plant_record(self.sites[i].get()) {
                return Err(TableError::Sites);
            }
            i += 1;
        }
        Ok(())
    }

    /// Whether the holder lists fit the layout: empty in a `ranked` set; in an `indexed` one, the
    /// starts ascending from just after them to the table's end, and each event's list exactly its
    /// holders in index order, each with the event's place in its alphabet.
    fn lists_sound(&self, events: usize) -> bool {
        let (lists, width) = (self.holder_lists, holder_bytes(self.automata.len()));
        if self.layout != INDEXED {
            return lists.is_empty();
        }
        if lists.len() <= events || lists[0] as usize != events + 1 || lists[events] as usize != lists.len() {
            return false;
        }
        let mut e = 0;
        while e < events {
            let (mut i, end) = (lists[e] as usize, lists[e + 1] as usize);
            if i <= events || end < i || end > lists.len() {
                return false;
            }
            let Some(mut holders) = holder_mask(self.holders, e * width, width) else { return false };
            while holders != 0 {
                let a = holders.trailing_zeros() as usize;
                holders &= holders - 1;
                let want = a | place(&self.automata[a].alphabet, e) << 8;
                if i >= end || lists[i] as usize != want {
                    return false;
                }
                i += 1;
            }
            if i != end {
                return false;
            }
            e += 1;
        }
        true
    }

    /// The `ranked` record at byte `at`, if it ends by `end` and names a mask: mask id, target count and
    /// the byte after it.
    pub(super) fn record_at(&self, at: usize, end: usize) -> Option<(usize, usize, usize)> {
        let id = field(self.block, self.wide, at, 0)? as usize;
        let mask = self.mask_of(id)?;
        let n: usize = mask.iter().map(|word| word.count_ones() as usize).sum();
        let next = at + (n + 1) * if self.wide { 2 } else { 1 };
        if next <= end {
            Some((id, n, next))
        } else {
            None
        }
    }

    /// One automaton: the records tile its part of the block, name masks within the alphabet, start at
    /// positions the type `Q` holds, and every target handle starts one — checked 256 handles at a time with a
    /// bitmap: a first pass marks the record starts, a second checks the targets.
    fn part_sound(&self, a: usize) -> bool {
        let aut = &self.automata[a];
        let (start, end) = self.part(a);
        let scale = aut.scale as usize;
        // An empty part has no initial state; `ranked` and `indexed` handles are 16-bit.
        let units = (end - start).div_ceil(scale.max(1));
        if scale == 0 || start == end || layout::has_pool(self.layout) && units > 1 << 16 {
            return false;
        }
        // The alphabet holds events only: the runtime's mask reads are exact on them.
        let events = self.events();
        let mut w = 0;
        while w < W {
            if aut.alphabet[w] & beyond(events, w) != 0 {
                return false;
            }
            w += 1;
        }
        if !layout::has_pool(self.layout) {
            return if self.layout == COMPACT { self.compact_sound(a) } else { self.records_sound(a) };
        }
        if self.layout == INDEXED {
            return self.uniform_part_sound(a);
        }
        let mut base = 0;
        loop {
            let mut starts = [0u32; 8];
            let mut handles = 0;
            let mut pass = 0;
            while pass < 2 {
                let mut at = start;
                while at < end {
                    let Some((id, n, next)) = self.record_at(at, end) else { return false };
                    if pass == 0 {
                        if at > Q::MAX {
                            return false;
                        }
                        let h = (at - start) / scale;
                        let i = h.wrapping_sub(base);
                        if i < 256 {
                            starts[i / 32] |= 1 << (i % 32);
                        }
                        handles = h + 1;
                        if !self.entry_sound(a, id) {
                            return false;
                        }
                    } else {
                        let mut r = 0;
                        while r < n {
                            // In the part: `record_at` bounded the record by its end.
                            let Some(t) = field(self.block, self.wide, at, r + 1) else { return false };
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

    /// Whether pool entry `id` fits automaton `a`: an out-mask within its alphabet (`ranked`), or an
    /// allowed set, which holds every event outside it (`indexed`).
    fn entry_sound(&self, a: usize, id: usize) -> bool {
        let (alphabet, events) = (&self.automata[a].alphabet, self.events());
        let Some(mask) = self.mask_of(id) else { return false };
        let mut w = 0;
        while w < W {
            let outside = !alphabet[w] & !beyond(events, w);
            let indexed = self.layout == INDEXED;
            if indexed && outside & !mask[w] != 0 || !indexed && mask[w] & !alphabet[w] != 0 {
                return false;
            }
            w += 1;
        }
        true
    }

    /// An `indexed` automaton's records, all as long (a mask id and a target per event of the
    /// alphabet), start every `unit` handles: `unit`, the record count and the targets per record, if
    /// they tile its part.
    fn uniform(&self, a: usize) -> Option<(usize, usize, usize)> {
        let aut = &self.automata[a];
        let (start, end) = self.part(a);
        let scale = aut.scale as usize;
        let mut n = 0;
        let mut w = 0;
        while w < W {
            n += aut.alphabet[w].count_ones() as usize;
            w += 1;
        }
        let len = (1 + n) * if self.wide { 2 } else { 1 };
        if scale == 0 || end - start < len {
            return None;
        }
        let unit = len.div_ceil(scale);
        if (end - start - len) % (unit * scale) != 0 {
            return None;
        }
        Some((unit, (end - start - len) / (unit * scale) + 1, n))
    }

    /// One `indexed` automaton, in one pass: its records tile its part, start at positions `Q` holds and
    /// at 16-bit handles, name allowed sets that fit it, and every target is a record's handle.
    fn uniform_part_sound(&self, a: usize) -> bool {
        let Some((unit, count, n)) = self.uniform(a) else { return false };
        let (start, _) = self.part(a);
        let stride = unit * self.automata[a].scale as usize;
        let last = (count - 1) * unit;
        if last > u16::MAX as usize || start + (count - 1) * stride > Q::MAX {
            return false;
        }
        let mut k = 0;
        while k < count {
            let at = start + k * stride;
            let Some(id) = field(self.block, self.wide, at, 0) else { return false };
            if !self.entry_sound(a, id as usize) {
                return false;
            }
            // Every target of the record, in the part: `uniform` measured it.
            let mut r = 1;
            while r <= n {
                let Some(t) = field(self.block, self.wide, at, r) else { return false };
                if !(t as usize).is_multiple_of(unit) || t as usize > last {
                    return false;
                }
                r += 1;
            }
            k += 1;
        }
        true
    }

    /// Whether `at` is the position of a plant's state.
    fn is_plant_record(&self, at: usize) -> bool {
        let mut p = 0;
        while p < self.plants as usize {
            let (start, end) = self.part(p);
            if self.layout == COMPACT {
                if let Some(base) = self.compact_base(p) {
                    if base <= at && at < 8 * end {
                        return at - base <= Q::MAX && self.is_state(p, Q::at(at - base));
                    }
                }
            } else if start <= at && at < end {
                let scale = self.automata[p].scale as usize;
                return scale != 0
                    && (at - start).is_multiple_of(scale)
                    && (at - start) / scale <= Q::MAX
                    && self.is_state(p, Q::at((at - start) / scale));
            }
            p += 1;
        }
        false
    }

    /// The position of automaton `a`'s stream (its handle 0) in a `compact` set, if its header lies in
    /// the block.
    fn compact_base(&self, a: usize) -> Option<usize> {
        let start = self.part(a).0;
        if start + super::compact::HEADER > self.block.len() {
            return None;
        }
        let dir = u16::from_le_bytes([self.block[start + 6], self.block[start + 7]]) as usize;
        Some(8 * (start + super::compact::HEADER + dir))
    }

    /// Whether `handle` is a state of automaton `a` (a record's, or in `compact` a mask's).
    pub fn is_state(&self, a: usize, handle: Q) -> bool {
        if a >= self.automata.len() {
            return false;
        }
        match self.layout {
            RANKED | INDEXED => {}
            COMPACT => return self.is_compact_state(a, handle),
            _ => return self.is_record(a, handle),
        }
        if self.layout == INDEXED {
            return match self.uniform(a) {
                Some((unit, count, _)) => handle.get().is_multiple_of(unit) && handle.get() < count * unit,
                None => false,
            };
        }
        let aut = &self.automata[a];
        let (start, end) = self.part(a);
        let scale = if aut.scale == 0 { 1 } else { aut.scale as usize };
        let wanted = start + handle.get() * scale;
        let mut at = start;
        while at < wanted {
            let Some((_, _, next)) = self.record_at(at, end) else { return false };
            at = start + (next - start).div_ceil(scale) * scale;
        }
        at == wanted && self.record_at(at, end).is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::toggle;
    use super::super::Automaton;
    use super::*;

    #[test]
    fn the_toggle_passes_and_fits_its_shape_only() {
        let checked = CheckedSet::<1, 1, false, 1, RANKED>::new(&super::super::tests::TOGGLE).unwrap();
        assert_eq!(checked.set().events(), 2);
        assert!(CheckedSet::<1, 1, false, 1, RANKED>::fits(&super::super::tests::TOGGLE));
        assert!(!CheckedSet::<1, 2, false, 1, RANKED>::fits(&super::super::tests::TOGGLE));
        assert!(!CheckedSet::<1, 1, true, 1, RANKED>::fits(&super::super::tests::TOGGLE));
    }

    #[test]
    fn check_refuses_broken_blocks() {
        // Mask ids 2–4 name the pool's padding (empty masks), id 5 lies beyond it.
        for bad in [&[0u8, 3, 1, 0][..], &[5, 1, 1, 0], &[0, 1, 1]] {
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
        let t = SupervisorSet { automata: &automata, masks: &[0x0101, 0], ..toggle() };
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
        assert!(CheckedSet::<1, 2, false, 1, RANKED>::new(&super::super::tests::TOGGLE).is_err());
        assert_eq!(
            CheckedSet::<1, 1, true, 1, RANKED>::new(&super::super::tests::TOGGLE).err(),
            Some(TableError::Shape)
        );
        assert_eq!(
            CheckedSet::<1, 1, false, 4, RANKED>::new(&super::super::tests::TOGGLE).err(),
            Some(TableError::Shape)
        );
    }

    /// The toggle in the `indexed` layout: records `[mask id][target of e0][target of e1]`, scale 3,
    /// masks of a word, holder lists e0 → automaton 0 at place 0, e1 → automaton 0 at place 1.
    fn indexed_toggle() -> SupervisorSet<'static, 1> {
        static AUTOMATA: [Automaton<1>; 1] = [Automaton { alphabet: [0b11], start: 0, scale: 3 }];
        SupervisorSet {
            automata: &AUTOMATA,
            block: &[0, 1, 0, 1, 0, 0],
            masks: &[0b01, 0b10],
            mask_bytes: 4,
            layout: INDEXED,
            holder_lists: &[3, 4, 5, 0x000, 0x100],
            ..toggle()
        }
    }

    #[test]
    fn indexed_sets_are_checked_place_by_place() {
        let t = indexed_toggle();
        assert_eq!(t.check(1), Ok(()));
        assert_eq!((t.step(0, 0, 0), t.step(0, 1, 1), t.step(0, 0, 1)), (Some(1), Some(0), None));
        assert!(CheckedSet::<1, 1, false, 4, INDEXED>::new(&t).is_ok());
        assert_eq!(CheckedSet::<1, 1, false, 4, RANKED>::new(&t).err(), Some(TableError::Shape));
        // A place that is not the event's, a list of another length, starts out of the table or out of
        // order, an automaton that does not hold the event, or lists in a ranked set.
        for holder_lists in [
            &[3u16, 4, 5, 0x000, 0x000][..],
            &[3, 4, 6, 0x000, 0x100, 0x100],
            &[3, 4, 5, 0x000],
            &[3, 5, 4, 0x000, 0x100],
            &[3, 4, 9, 0x000, 0x100],
            &[2, 4, 5, 0x000, 0x100],
            &[3, 4, 5, 0x001, 0x100],
        ] {
            assert_eq!(
                SupervisorSet { holder_lists, ..t }.check(1),
                Err(TableError::Events),
                "{holder_lists:?}"
            );
        }
        assert_eq!(
            SupervisorSet { holder_lists: t.holder_lists, ..toggle() }.check(1),
            Err(TableError::Events)
        );
        // Masks of other than whole words, a record cut short, a target that starts no record.
        assert_eq!(SupervisorSet { mask_bytes: 1, ..t }.check(1), Err(TableError::Size));
        assert_eq!(SupervisorSet { block: &[0, 1, 0, 1, 0], ..t }.check(1), Err(TableError::Block(0)));
        assert_eq!(SupervisorSet { block: &[0, 1, 2, 1, 0, 0], ..t }.check(1), Err(TableError::Block(0)));
        // A third event, outside the alphabet: the pool's allowed sets must hold it.
        let holder_lists = &[4, 5, 6, 6, 0x000, 0x100];
        let three = SupervisorSet { holders: &[1, 1, 0], holder_lists, masks: &[0b101, 0b110], ..t };
        assert_eq!(three.check(1), Ok(()));
        assert_eq!(three.mask(0, 1), Some([0b10]));
        assert_eq!(SupervisorSet { masks: &[0b101, 0b010], ..three }.check(1), Err(TableError::Block(0)));
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
