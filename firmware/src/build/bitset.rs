//! Sets of global event ids as `u32` words of any length, the host's form of the runtime's bitsets
//! ([`crate::event_set`]): bit `e % 32` of word `e / 32` stands for event `e`; a set over `n` events
//! takes `⌈n / 32⌉` words.

use alloc::vec;
use alloc::vec::Vec;

/// The words of the set holding `ids`, sized for a table of `len` events.
pub fn from_ids(ids: impl IntoIterator<Item = usize>, len: usize) -> Vec<u32> {
    let mut words = vec![0u32; len.div_ceil(32)];
    for id in ids {
        words[id / 32] |= 1 << (id % 32);
    }
    words
}

/// Whether `id` is in the set `words`.
pub fn contains(words: &[u32], id: usize) -> bool {
    words.get(id / 32).is_some_and(|w| w & (1 << (id % 32)) != 0)
}

/// The ids in the set, in increasing order.
pub fn ids(words: &[u32]) -> impl Iterator<Item = usize> + '_ {
    (0..words.len() * 32).filter(move |&id| contains(words, id))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_across_word_boundaries() {
        let set = from_ids([0, 31, 32, 40], 41);
        assert_eq!(set, [0x8000_0001, 0x101]);
        assert_eq!(ids(&set).collect::<Vec<_>>(), [0, 31, 32, 40]);
        assert!(!contains(&set, 1));
        assert!(!contains(&set, 200));
    }
}
