//! Limits and hooks of one synthesis run.

use std::fmt;
use std::sync::Arc;

use super::SynthError;
use crate::model::Dfa;

/// Receives progress reports of long walks (a CLI draws them as a progress bar).
pub trait Observer: Send + Sync {
    /// `what` (an automaton being built) has reached `states` states so far.
    fn states(&self, what: &str, states: usize);
    /// A new stage starts (for example the supervisor of one specification).
    fn stage(&self, what: &str);
}

/// A nonblocking check of a synchronous product done by another engine (the symbolic one), so that the
/// conflict check of a modular or local modular set need not build the product state by state.
pub trait NonblockingCheck: Send + Sync {
    /// States the explicit check may build first (the `auto` engine: small products are decided faster
    /// explicitly); only when the product passes them does this engine run. `0`: it runs right away.
    fn explicit_states(&self) -> usize;
    /// Whether the synchronous product of `dfas` (over one event table) is nonblocking; `what` names
    /// the product in progress reports and errors.
    fn nonblocking(&self, dfas: &[&Dfa], cfg: &Config, what: &str) -> Result<bool, SynthError>;
}

/// Settings shared by every synthesis function.
#[derive(Clone)]
pub struct Config {
    /// Largest number of states any product or supervisor may reach before the run stops with
    /// [`SynthError::StateLimit`](super::SynthError::StateLimit).
    pub state_limit: usize,
    /// Largest resident size of the process, in bytes, a product may grow it to before the run stops
    /// with [`SynthError::MemoryLimit`](super::SynthError::MemoryLimit); checked as products grow.
    /// `None`: no limit.
    pub memory_limit: Option<u64>,
    /// Whether modular and local modular synthesis merge conflicting specifications until the set is
    /// nonconflicting (`true`, the default) or only report the conflict.
    pub merge_conflicting: bool,
    /// Progress reports, if anyone listens.
    pub observer: Option<Arc<dyn Observer>>,
    /// The engine of the conflict check of modular and local modular sets; `None`: the explicit product.
    pub nonblocking: Option<Arc<dyn NonblockingCheck>>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            state_limit: 100_000_000,
            memory_limit: None,
            merge_conflicting: true,
            observer: None,
            nonblocking: None,
        }
    }
}

impl Config {
    pub(crate) fn stage(&self, what: &str) {
        if let Some(o) = &self.observer {
            o.stage(what);
        }
    }
}

impl fmt::Debug for Config {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Config")
            .field("state_limit", &self.state_limit)
            .field("memory_limit", &self.memory_limit)
            .field("merge_conflicting", &self.merge_conflicting)
            .field("observer", &self.observer.is_some())
            .field("nonblocking", &self.nonblocking.is_some())
            .finish()
    }
}
