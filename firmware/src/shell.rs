//! This module is the home of the shell both runtimes share: the loop's steps around the tables — an
//! input counted, refused when it is no input, a fault on an unexpected one; the enabled set, the
//! choice by the policy, the inexact-synchronisation guard, the firing; the counters, the fault policy
//! and the random generator — over a [`Core`], which is all a runtime's tables add: the supervisor
//! tables ([`crate::runtime::Runtime`]) or the state feedback ([`crate::state::StateRuntime`]).
//!
//! Each runtime holds its core and a [`Shell`] side by side and answers the event loop ([`Decide`])
//! through the shell, so that what a decision or an input does besides reading the tables is written
//! once.

use crate::choice::{Choose, View};
use crate::event_set::EventSet;
use crate::fault::FaultPolicy;
use crate::rng::{Entropy, Rng};

/// Run-time options (manifest `[runtime]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    /// Inexact-synchronisation guard: drop a chosen event when an input arrived while choosing.
    pub guard: bool,
    /// What a fault does.
    pub on_fault: FaultPolicy,
    /// Random draws between two reseeds of the generator (0: never reseed).
    pub reseed_every: u16,
}

/// The counters the link's STATUS answer reports, in that order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Uncontrollable events applied.
    pub events_in: u32,
    /// Controllable events fired.
    pub commands_out: u32,
    /// Events some automaton holding them could not take.
    pub unexpected: u32,
    /// Input bytes lost to a full buffer.
    pub overflows: u32,
    /// Choices dropped by the inexact-synchronisation guard.
    pub guard_redecisions: u32,
    /// Link bytes that are neither a known control byte nor an uncontrollable event of the set.
    pub unknown_bytes: u32,
}

impl Counters {
    /// The six counters in STATUS order.
    pub fn to_array(&self) -> [u32; 6] {
        [
            self.events_in,
            self.commands_out,
            self.unexpected,
            self.overflows,
            self.guard_redecisions,
            self.unknown_bytes,
        ]
    }
}

/// What applying an input did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Applied {
    /// Every automaton holding the event took it.
    Taken,
    /// Automaton `automaton` holds the event but had no transition for it in its current state (it stays
    /// where it is; the others moved).
    Unexpected {
        /// Index of the first such automaton.
        automaton: u8,
    },
    /// Not an uncontrollable event of the set: ignored.
    Unknown,
}

/// What one decision did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decision {
    /// This controllable event was fired: the caller runs its output action.
    Fired(u8),
    /// Nothing is enabled: sleep until the next input.
    Idle,
    /// An input arrived while choosing; the choice was dropped: apply the input, then decide again.
    Redecide,
    /// A fault put the runtime in the safe state: no more decisions until a reset.
    Halted,
}

/// What the event loop ([`crate::event_loop`]) asks of a decider: the supervisor runtime
/// ([`crate::runtime::Runtime`]) or the state-based one ([`crate::state::StateRuntime`]). The loop's
/// input handling, link protocol and fault reporting are the same for both; only how inputs are taken
/// and a decision is made differ.
pub trait Decide {
    /// Takes uncontrollable `event` (step 1 of the loop).
    fn apply(&mut self, event: u8) -> Applied;
    /// Steps 2–6: the enabled set, the choice, the guard (`pending` says whether an input is waiting),
    /// the firing.
    fn decide(&mut self, pending: impl FnOnce() -> bool) -> Decision;
    /// Back to the initial state, counters to zero, policy to its boot state, safe state left.
    fn reset(&mut self);
    /// The counters.
    fn counters(&self) -> &Counters;
    /// Whether a fault put the decider in the safe state.
    fn is_safe(&self) -> bool;
    /// Counts a link byte that means nothing and applies the fault policy.
    fn note_unknown_byte(&mut self);
    /// Takes the input buffer's total overflow count; any growth is counted and is a fault.
    fn note_overflows(&mut self, total: u32);
}

/// What a runtime's tables give the [`Shell`]: inputs taken, the enabled set, the policies' view, a
/// command fired. Over `W`-word event bitsets.
pub trait Core<const W: usize> {
    /// How the view names a plant's state.
    type State: Copy + Eq;

    /// What taking an input needs of the tables (the automata holding it, what it writes).
    type Input;

    /// Uncontrollable `event` as an input of the tables, or `None` when it is none.
    fn input(&self, event: u8) -> Option<Self::Input>;

    /// Takes `event`, whose input is `input`: the first automaton (or component) that holds it and
    /// could not take it, if any.
    fn take(&mut self, event: u8, input: Self::Input) -> Option<u8>;

    /// The controllable events enabled now.
    fn enabled(&self) -> EventSet<W>;

    /// What the choice policies see; `sites` says whether the policy reads the plants' states.
    fn view(&mut self, sites: bool) -> View<'_, W, Self::State>;

    /// Fires controllable `c`, which is enabled; whether the tables could (they name its effect).
    fn fire(&mut self, c: u8) -> bool;

    /// Back to the initial state.
    fn reset(&mut self);
}

/// The shell: counters, the fault policy's state, the guard, the choice policy `P` and the generator
/// drawing entropy from `E`.
pub struct Shell<P, E> {
    counters: Counters,
    overflow_mark: u32,
    safe: bool,
    guard: bool,
    on_fault: FaultPolicy,
    policy: P,
    rng: Rng<E>,
}

impl<P, E: Entropy> Shell<P, E> {
    /// A shell after boot: counters at zero, out of the safe state.
    pub fn new(config: Config, policy: P, entropy: E) -> Self {
        Self {
            counters: Counters::default(),
            overflow_mark: 0,
            safe: false,
            guard: config.guard,
            on_fault: config.on_fault,
            policy,
            rng: Rng::new(entropy, config.reseed_every),
        }
    }

    /// Step 1 of the loop for one input: `core` takes uncontrollable `event`, counted; an event that is
    /// no input of the tables, or that an automaton holding it cannot take, is a fault.
    #[inline(always)]
    pub fn apply<const W: usize, C: Core<W>>(&mut self, core: &mut C, event: u8) -> Applied {
        let Some(input) = core.input(event) else {
            return self.note_unknown();
        };
        self.counters.events_in = self.counters.events_in.wrapping_add(1);
        match core.take(event, input) {
            None => Applied::Taken,
            Some(automaton) => {
                self.counters.unexpected = self.counters.unexpected.wrapping_add(1);
                self.fault();
                Applied::Unexpected { automaton }
            }
        }
    }

    /// Steps 2–6 of the loop over `core`: the enabled set, the choice, the guard (`pending` says whether
    /// an input is waiting), the firing.
    #[inline(always)]
    pub fn decide<const W: usize, C: Core<W>>(
        &mut self,
        core: &mut C,
        pending: impl FnOnce() -> bool,
    ) -> Decision
    where
        P: Choose<W>,
    {
        if self.safe {
            return Decision::Halted;
        }
        let enabled = core.enabled();
        if enabled.is_empty() {
            return Decision::Idle;
        }
        let Some(c) = self.policy.choose(core.view(P::READS_SITES), &enabled, &mut self.rng) else {
            return Decision::Idle;
        };
        if self.guard && pending() {
            self.counters.guard_redecisions = self.counters.guard_redecisions.wrapping_add(1);
            return Decision::Redecide;
        }
        if !enabled.contains(c) || !core.fire(c) {
            return Decision::Idle;
        }
        self.counters.commands_out = self.counters.commands_out.wrapping_add(1);
        Decision::Fired(c)
    }

    /// `core` to its initial state, counters to zero, policy to its boot state, safe state left.
    pub fn reset<const W: usize, C: Core<W>>(&mut self, core: &mut C)
    where
        P: Choose<W>,
    {
        core.reset();
        self.counters = Counters::default();
        self.safe = false;
        self.policy.reset();
    }

    /// The counters.
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// Whether a fault put the runtime in the safe state.
    pub fn is_safe(&self) -> bool {
        self.safe
    }

    /// Counts a link byte that means nothing and applies the fault policy.
    pub fn note_unknown(&mut self) -> Applied {
        self.counters.unknown_bytes = self.counters.unknown_bytes.wrapping_add(1);
        self.fault();
        Applied::Unknown
    }

    /// Takes the input buffer's total overflow count; any growth is counted and is a fault.
    pub fn note_overflows(&mut self, total: u32) {
        let new = total.wrapping_sub(self.overflow_mark);
        if new != 0 {
            self.overflow_mark = total;
            self.counters.overflows = self.counters.overflows.wrapping_add(new);
            self.fault();
        }
    }

    fn fault(&mut self) {
        if self.on_fault == FaultPolicy::SafeState {
            self.safe = true;
        }
    }
}
