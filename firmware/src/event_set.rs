//! A fixed-size set of event ids as a bitset: the runtime's enabled sets, alphabets and site rounds.
//!
//! Bit `e % 32` of word `e / 32` stands for event `e`, the same convention as the alphabets and the
//! controllability vector of [`crate::table`], so a table slice of `W` words becomes a set in one copy.
//!
//! # Examples
//!
//! ```
//! use firmware::event_set::EventSet;
//!
//! let mut s = EventSet::<1>::EMPTY;
//! s.insert(3);
//! s.insert(7);
//! assert_eq!(s.first(), Some(3));
//! assert_eq!(s.len(), 2);
//! assert_eq!(s.nth(1), Some(7));
//! ```

/// A set of event ids below `32 * W`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EventSet<const W: usize>(pub [u32; W]);

impl<const W: usize> EventSet<W> {
    /// The empty set.
    pub const EMPTY: Self = Self([0; W]);

    /// Adds `event`; ids beyond the set's range are ignored (they cannot be table events).
    pub fn insert(&mut self, event: u8) {
        if let Some(w) = self.0.get_mut(usize::from(event / 32)) {
            *w |= 1 << (event % 32);
        }
    }

    /// Removes `event`.
    pub fn remove(&mut self, event: u8) {
        if let Some(w) = self.0.get_mut(usize::from(event / 32)) {
            *w &= !(1 << (event % 32));
        }
    }

    /// Whether `event` is in the set.
    pub fn contains(&self, event: u8) -> bool {
        self.0.get(usize::from(event / 32)).is_some_and(|w| w & (1 << (event % 32)) != 0)
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.0.iter().fold(0, |any, &w| any | w) == 0
    }

    /// Whether the set holds two events or more (cheaper than counting them).
    pub fn several(&self) -> bool {
        let mut seen = false;
        for &w in &self.0 {
            if w != 0 {
                if seen || w & (w - 1) != 0 {
                    return true;
                }
                seen = true;
            }
        }
        false
    }

    /// Number of events in the set.
    pub fn len(&self) -> u32 {
        self.0.iter().map(|&w| ones(w)).sum()
    }

    /// The lowest event of the set.
    pub fn first(&self) -> Option<u8> {
        self.nth(0)
    }

    /// The `n`-th lowest event of the set (counting from 0).
    pub fn nth(&self, mut n: u32) -> Option<u8> {
        // Walks the bits rather than counting each word: no popcount instruction on a Cortex-M, and the
        // sets the policies draw from hold a few events.
        for (i, &word) in self.0.iter().enumerate() {
            let mut w = word;
            while w != 0 {
                if n == 0 {
                    return u8::try_from(i * 32 + w.trailing_zeros() as usize).ok();
                }
                n -= 1;
                w &= w - 1;
            }
        }
        None
    }

    /// The lowest event of the set at or above `from`, wrapping around to the lowest of all.
    pub fn next_cyclic(&self, from: u8) -> Option<u8> {
        let mut upper = *self;
        for (i, w) in upper.0.iter_mut().enumerate() {
            let base = i * 32;
            let from = usize::from(from);
            if from >= base + 32 {
                *w = 0;
            } else if from > base {
                *w &= u32::MAX << (from - base);
            }
        }
        upper.first().or_else(|| self.first())
    }

    /// The intersection of both sets.
    #[must_use]
    pub fn and(mut self, other: &Self) -> Self {
        for (a, b) in self.0.iter_mut().zip(other.0.iter()) {
            *a &= b;
        }
        self
    }

    /// The union of both sets.
    #[must_use]
    pub fn or(mut self, other: &Self) -> Self {
        for (a, b) in self.0.iter_mut().zip(other.0.iter()) {
            *a |= b;
        }
        self
    }

    /// The events of `self` that are not in `other`.
    #[must_use]
    pub fn and_not(mut self, other: &Self) -> Self {
        for (a, b) in self.0.iter_mut().zip(other.0.iter()) {
            *a &= !b;
        }
        self
    }

    /// The events in order, lowest first.
    pub fn iter(&self) -> impl Iterator<Item = u8> + '_ {
        self.0.iter().enumerate().flat_map(|(i, &word)| {
            let mut w = word;
            core::iter::from_fn(move || {
                if w == 0 {
                    return None;
                }
                let bit = w.trailing_zeros() as usize;
                w &= w - 1;
                u8::try_from(i * 32 + bit).ok()
            })
        })
    }
}

/// Set bits of `x`, one loop turn per bit: cheaper than a full population count on the few bits of
/// the sets a decision handles (and of the part of a state's mask below an event).
#[inline(always)]
pub(crate) fn ones(mut x: u32) -> u32 {
    let mut n = 0;
    while x != 0 {
        x &= x - 1;
        n += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::BTreeSet;

    fn set_of(events: &BTreeSet<u8>) -> EventSet<8> {
        let mut s = EventSet::EMPTY;
        for &e in events {
            s.insert(e);
        }
        s
    }

    proptest! {
        #[test]
        fn agrees_with_btreeset(a in proptest::collection::btree_set(any::<u8>(), 0..40),
                                b in proptest::collection::btree_set(any::<u8>(), 0..40),
                                from in any::<u8>(), n in 0u32..50) {
            let (sa, sb) = (set_of(&a), set_of(&b));
            prop_assert_eq!(sa.iter().collect::<Vec<_>>(), a.iter().copied().collect::<Vec<_>>());
            prop_assert_eq!(sa.len() as usize, a.len());
            prop_assert_eq!(sa.several(), a.len() >= 2);
            prop_assert_eq!(sa.is_empty(), a.is_empty());
            prop_assert_eq!(sa.nth(n), a.iter().nth(n as usize).copied());
            prop_assert_eq!(sa.and(&sb).iter().collect::<BTreeSet<_>>(), &a & &b);
            prop_assert_eq!(sa.or(&sb).iter().collect::<BTreeSet<_>>(), &a | &b);
            prop_assert_eq!(sa.and_not(&sb).iter().collect::<BTreeSet<_>>(), &a - &b);
            let cyclic = a.range(from..).next().or_else(|| a.iter().next()).copied();
            prop_assert_eq!(sa.next_cyclic(from), cyclic);
            for e in 0..=255u8 {
                prop_assert_eq!(sa.contains(e), a.contains(&e));
            }
        }
    }

    #[test]
    fn insert_remove_and_out_of_range() {
        let mut s = EventSet::<1>::EMPTY;
        s.insert(40);
        assert!(s.is_empty());
        s.insert(31);
        assert!(s.contains(31));
        s.remove(31);
        assert!(s.is_empty());
    }
}
