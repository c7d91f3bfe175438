//! Supervisor memory as literals: where the plant state does not decide the feedback, the kept
//! supervisors' states ([`super::sfbc::Memory`]) become further variables — each kept supervisor's state
//! in binary, ⌈log2 states⌉ bits, least significant first — numbered after the signals, so F_σ is a
//! formula over signals and memory bits alike. How a program keeps these bits up to date is the
//! program's (`plc::state_based::memory`); the firmware keeps no supervisor state.

use crate::config::{Cube, MAX_SIGNALS};
use crate::pack::PackSet;

use super::sfbc::bits;
use super::FeedbackError;

/// Where the kept supervisors' state bits are among the variables of F_σ.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Layout {
    /// Member indices of the kept supervisors.
    pub kept: Vec<usize>,
    /// Per kept supervisor, its state code's bits: their indices among the variables, least significant
    /// first.
    pub bits: Vec<Vec<usize>>,
    /// The index of the first memory bit (the number of signals).
    pub base: usize,
}

impl Layout {
    /// The bits of the supervisors `kept` of `set`, numbered from `signals` (the signals' count); at most
    /// [`MAX_SIGNALS`] variables in all.
    pub fn new(set: &PackSet, kept: &[usize], signals: usize) -> Result<Layout, FeedbackError> {
        let mut index = signals;
        let mut all = Vec::new();
        for &s in kept {
            let n = bits(set.members()[s].state_count()) as usize;
            all.push((index..index + n).collect());
            index += n;
        }
        if index > MAX_SIGNALS {
            return Err(FeedbackError::Vector {
                key: "state".into(),
                message: format!("signals and memory bits exceed {MAX_SIGNALS}"),
            });
        }
        Ok(Layout { kept: kept.to_vec(), bits: all, base: signals })
    }

    /// The memory bits in all.
    pub fn count(&self) -> usize {
        self.bits.iter().map(Vec::len).sum()
    }

    /// The literals of the kept supervisors in `states` (one per kept supervisor, in order): each
    /// state's binary code on its supervisor's bits.
    pub fn cube(&self, states: &[u32]) -> Cube {
        let mut c = Cube::default();
        for (k, &q) in states.iter().enumerate() {
            for (i, &bit) in self.bits[k].iter().enumerate() {
                c.mask |= 1 << bit;
                c.value |= u64::from(q >> i & 1) << bit;
            }
        }
        c
    }
}
