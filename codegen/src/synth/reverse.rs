//! Predecessor lists of a [`Dfa`], for the backward walks of trimming and supC.

use crate::model::Dfa;

/// Predecessor lists of a [`Dfa`] in compressed sparse rows: for each state, the (source, event) pairs
/// of the transitions entering it.
pub(crate) struct Reverse {
    offsets: Vec<usize>,
    sources: Vec<u32>,
    events: Vec<u32>,
}

impl Reverse {
    /// Builds the predecessor lists of `dfa` with a counting sort on targets.
    pub(crate) fn new(dfa: &Dfa) -> Self {
        let n = dfa.state_count();
        let mut offsets = vec![0usize; n + 1];
        for &t in &dfa.targets {
            offsets[t as usize + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut sources = vec![0u32; dfa.targets.len()];
        let mut events = vec![0u32; dfa.targets.len()];
        for s in 0..n {
            for i in dfa.offsets[s]..dfa.offsets[s + 1] {
                let t = dfa.targets[i] as usize;
                sources[fill[t]] = s as u32;
                events[fill[t]] = dfa.events[i];
                fill[t] += 1;
            }
        }
        Reverse { offsets, sources, events }
    }

    /// The bytes [`Reverse::new`] takes for `dfa`, with the masks of the backward walk beside it (for
    /// [`admit`](super::memory::admit)).
    pub(crate) fn bytes(dfa: &Dfa) -> u64 {
        let (n, t) = (dfa.state_count() as u64, dfa.transition_count() as u64);
        2 * 8 * (n + 1) + 8 * t + 4 * n
    }

    /// The (source, event) pairs of the transitions entering `s`.
    pub(crate) fn preds(&self, s: u32) -> impl Iterator<Item = (u32, u32)> + '_ {
        let r = self.offsets[s as usize]..self.offsets[s as usize + 1];
        self.sources[r.clone()].iter().copied().zip(self.events[r].iter().copied())
    }
}
