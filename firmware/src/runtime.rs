//! The decision loop of the design notes (§4), one step at a time: apply the buffered uncontrollable
//! events, compute the enabled controllable events, choose one, check the inexact-synchronisation guard,
//! fire it.
//!
//! The three levels of de Queiroz & Cury meet here: the *plants* (product system) generate the
//! controllable events they can physically take and track the uncontrollable ones, the *supervisors*
//! only disable, and the *interface* (the caller: [`crate::link`] or a board's pin layer) turns input
//! signals into [`Runtime::apply`] calls and fired events into outputs.
//!
//! One runtime reads every layout of [`crate::table`], the layout its `LAYOUT` const parameter. In the
//! default ones cost does not depend on the set's state count: a state is held as the offset of its
//! record in the tables' block, so taking a transition is a mask test, a rank (in the `indexed` layout,
//! the event's place from its holder list) and one load; `offset` searches the state's record, `compact`
//! skips at most 15 states from a directory entry, and `memory-safe` walks to the target's record as the
//! reference tool does (O(state index)). An event touches only the automata that hold it
//! ([`SupervisorSet::holders`], or its holder list). The enabled set is the controllable events masked,
//! automaton by automaton, by what the current state allows (kept in RAM with the state): one mask per
//! automaton, no scan.
//!
//! The runtime takes only a [`CheckedSet`] (tables that passed [`SupervisorSet::check`] — for the
//! firmware, on the host by its build script, [`crate::table::image`] — with the field and mask widths,
//! layout and position type the runtime is compiled for); the hot path then reads them without bounds
//! checks. Everything from outside — input events, restored states — is checked where it enters.
//!
//! What a decision or an input does besides reading the tables — the counters, the guard, the fault
//! policy, the choice — is the [`crate::shell`], which the state-based runtime shares.
//!
//! # Examples
//!
//! ```
//! use firmware::choice::First;
//! use firmware::fault::FaultPolicy;
//! use firmware::rng::SeedEntropy;
//! use firmware::runtime::{Config, Decision, Runtime};
//! use firmware::table::{layout, Automaton, CheckedSet, SupervisorSet};
//!
//! // One plant: state 0 –start(0)→ state 1 –done(1)→ state 0; start is controllable. Out-masks {start}
//! // (id 0) and {done} (id 1); records [id][target], one byte each, so state 1 is handle 2.
//! static SET: SupervisorSet<'static, 1> = SupervisorSet {
//!     controllable: [0b01],
//!     plants: 1,
//!     automata: &[Automaton { alphabet: [0b11], start: 0, scale: 1 }],
//!     block: &[0, 2, 1, 0],
//!     wide: false,
//!     // Masks {start} and {done}, a byte each, packed into words, and padding to read a word.
//!     masks: &[0x0201, 0],
//!     mask_bytes: 1,
//!     layout: layout::RANKED,
//!     initials: &[],
//!     holder_lists: &[],
//!     holders: &[1, 1],
//!     plant_events: &[[0b01]],
//!     sites: &[],
//! };
//! let config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 0 };
//! // Checked (on the host; a firmware's build script checks its tables, `firmware::table::image`). One
//! // event word, one automaton, 1-byte fields, 1-byte masks, `ranked` layout, 16-bit positions.
//! let checked = CheckedSet::<1, 1, false, 1, { layout::RANKED }>::new(&SET).unwrap();
//! let mut rt = Runtime::new(checked, config, First, SeedEntropy::new(1));
//! assert_eq!(rt.decide(|| false), Decision::Fired(0));
//! assert_eq!(rt.decide(|| false), Decision::Idle);
//! rt.apply(1);
//! assert_eq!(rt.decide(|| false), Decision::Fired(0));
//! ```

use crate::choice::{Choose, View};
use crate::event_set::EventSet;
use crate::rng::Entropy;
use crate::shell::{Core, Shell};
use crate::table::layout::{has_pool, INDEXED};
use crate::table::{bit, holder_bytes, CheckedSet, Event, Position, SupervisorSet, TableError};

pub use crate::shell::{Applied, Config, Counters, Decide, Decision};

/// The runtime over a set of `N` automata and events in `W`-word bitsets, with the field and mask
/// widths `WIDE` and `MASK`, the layout `LAYOUT` and positions of type `Q` ([`CheckedSet`],
/// [`crate::table::layout`], [`crate::table::Position`]), choosing with policy `P` and drawing entropy
/// from `E`: one runtime for every layout, each build compiled with its own reader.
pub struct Runtime<
    't,
    P,
    E,
    const W: usize,
    const N: usize,
    const WIDE: bool,
    const MASK: usize,
    const LAYOUT: u8,
    Q = u16,
> {
    tables: Tables<'t, W, N, WIDE, MASK, LAYOUT, Q>,
    shell: Shell<P, E>,
}

/// The tables and where every automaton is in them: the runtime's [`Core`].
struct Tables<'t, const W: usize, const N: usize, const WIDE: bool, const MASK: usize, const LAYOUT: u8, Q> {
    set: &'t SupervisorSet<'t, W, Q>,
    /// Where every automaton is: its current state's position.
    records: [Q; N],
    /// What every automaton allows in its current state: out-mask or-ed with the events outside its
    /// alphabet, kept with `records`. The enabled set is their conjunction, read from RAM.
    allowed: [[u32; W]; N],
}

impl<
        't,
        P: Choose<W>,
        E: Entropy,
        const W: usize,
        const N: usize,
        const WIDE: bool,
        const MASK: usize,
        const LAYOUT: u8,
        Q: Position,
    > Runtime<'t, P, E, W, N, WIDE, MASK, LAYOUT, Q>
{
    /// A runtime in the initial states of `set`.
    #[inline(never)]
    pub fn new(
        set: CheckedSet<'t, W, N, WIDE, MASK, LAYOUT, Q>,
        config: Config,
        policy: P,
        entropy: E,
    ) -> Self {
        let tables = Tables { set: set.set(), records: [Q::at(0); N], allowed: [[0; W]; N] };
        let mut rt = Self { tables, shell: Shell::new(config, policy, entropy) };
        rt.reset();
        rt
    }

    /// Automata to their initial states, counters to zero, policy to its boot state, safe state left.
    pub fn reset(&mut self) {
        self.shell.reset(&mut self.tables);
    }

    /// Step 1 of the loop for one input: applies uncontrollable `event` to every automaton holding it.
    #[inline(never)]
    pub fn apply(&mut self, event: u8) -> Applied {
        self.shell.apply(&mut self.tables, event)
    }

    /// Counts a link byte that means nothing and applies the fault policy.
    pub fn note_unknown_byte(&mut self) {
        self.shell.note_unknown();
    }

    /// Takes the input buffer's total overflow count; any growth is counted and is a fault.
    pub fn note_overflows(&mut self, total: u32) {
        self.shell.note_overflows(total);
    }

    /// Steps 2–6 of the loop: computes the enabled set, chooses, checks the guard (`pending` says
    /// whether an input is waiting) and fires.
    #[inline(never)]
    pub fn decide(&mut self, pending: impl FnOnce() -> bool) -> Decision {
        self.shell.decide(&mut self.tables, pending)
    }

    /// The controllable events every automaton holding them can take now.
    pub fn enabled(&self) -> EventSet<W> {
        self.tables.enabled()
    }

    /// The counters.
    pub fn counters(&self) -> &Counters {
        self.shell.counters()
    }

    /// Whether a fault put the runtime in the safe state.
    pub fn is_safe(&self) -> bool {
        self.shell.is_safe()
    }

    /// Current state handle of every automaton.
    pub fn states(&self) -> [Q; N] {
        let t = &self.tables;
        let mut out = [Q::at(0); N];
        for ((h, aut), &at) in out.iter_mut().zip(t.set.automata).zip(&t.records) {
            *h = t.set.handle_of(aut, at);
        }
        out
    }

    /// Puts every automaton in the state with the given handle, as [`Runtime::states`] reported it (a
    /// checkpoint; host tools replay or explore from it). Counters and the policy's memory are kept.
    /// Refuses, changing nothing, a handle that is no state of its automaton.
    pub fn restore(&mut self, states: &[Q; N]) -> Result<(), TableError> {
        for (a, &h) in states.iter().enumerate() {
            if !self.tables.set.is_state(a, h) {
                // At most MAX_AUTOMATA automata: the index fits a byte.
                return Err(TableError::Block(a as u8));
            }
        }
        self.tables.enter(|a| states[a]);
        Ok(())
    }

    /// The tables.
    pub fn set(&self) -> &'t SupervisorSet<'t, W, Q> {
        self.tables.set
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
    > Tables<'t, W, N, WIDE, MASK, LAYOUT, Q>
{
    /// Puts automaton `a` in state `handle(a)`, which `new` or `restore` proved to be one.
    fn enter(&mut self, handle: impl Fn(usize) -> Q) {
        let all = self.records.iter_mut().zip(&mut self.allowed).zip(self.set.automata).enumerate();
        for (a, ((at, allowed), aut)) in all {
            let h = handle(a);
            // A checked set's positions fit `Q`.
            *at = Q::at(self.set.position_in(LAYOUT, aut, h));
            // SAFETY: `new` took a checked set, and `h` is the initial handle (checked) or was checked by
            // `restore`.
            *allowed = unsafe { self.set.allowed_at::<WIDE, MASK, LAYOUT>(aut, *at) };
        }
    }

    /// Moves every automaton of `holders` by `event`, an event of the set; the first that cannot, if
    /// any (it stays).
    #[inline(always)]
    fn move_holders(&mut self, event: u8, holders: u32) -> Option<u8> {
        let (set, records, allowed, event) =
            (self.set, &mut self.records, &mut self.allowed, Event::new(event));
        let all = every::<LAYOUT>(holders);
        let first = take_until_stuck::<W, N, WIDE, MASK, LAYOUT, Q>(set, records, allowed, event, all)?;
        // Rare: an unexpected event. The holders after the stuck one still move.
        let mut stuck = first;
        loop {
            let passed = holders & !(u32::MAX << stuck << 1);
            let rest = if LAYOUT == INDEXED { passed.count_ones() } else { holders & !passed };
            match take_until_stuck::<W, N, WIDE, MASK, LAYOUT, Q>(set, records, allowed, event, rest) {
                Some(next) => stuck = next,
                None => return Some(first),
            }
        }
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
    > Core<W> for Tables<'t, W, N, WIDE, MASK, LAYOUT, Q>
{
    type State = Q;
    /// The automata holding the input.
    type Input = u32;

    #[inline(always)]
    fn input(&self, event: u8) -> Option<u32> {
        let holders = self.set.holders_of(event, holder_bytes(N))?;
        (!bit(&self.set.controllable, event)).then_some(holders)
    }

    #[inline(always)]
    fn take(&mut self, event: u8, holders: u32) -> Option<u8> {
        self.move_holders(event, holders)
    }

    #[inline(always)]
    fn enabled(&self) -> EventSet<W> {
        let mut enabled = self.set.controllable;
        // Two automata per turn: half the loop's bookkeeping.
        let mut pairs = self.allowed.chunks_exact(2);
        for pair in &mut pairs {
            for ((e, a), b) in enabled.iter_mut().zip(&pair[0]).zip(&pair[1]) {
                *e &= a & b;
            }
        }
        for allowed in pairs.remainder() {
            for (e, a) in enabled.iter_mut().zip(allowed) {
                *e &= a;
            }
        }
        EventSet(enabled)
    }

    #[inline(always)]
    fn view(&mut self, _sites: bool) -> View<'_, W, Q> {
        let set = self.set;
        View {
            controllable: &set.controllable,
            plant_events: set.plant_events,
            sites: set.sites,
            records: &self.records,
            allowed: &self.allowed,
        }
    }

    #[inline(always)]
    fn fire(&mut self, c: u8) -> bool {
        let Some(holders) = self.set.holders_of(c, holder_bytes(N)) else {
            return false;
        };
        // `c` is enabled: every holder allows it, none gets stuck.
        take_until_stuck::<W, N, WIDE, MASK, LAYOUT, Q>(
            self.set,
            &mut self.records,
            &mut self.allowed,
            Event::new(c),
            every::<LAYOUT>(holders),
        );
        true
    }

    fn reset(&mut self) {
        // The first record in `ranked` and `indexed`, else the set's initial handle.
        let initials = self.set.initials;
        self.enter(
            |a| if has_pool(LAYOUT) { Q::at(0) } else { initials.get(a).copied().unwrap_or(Q::at(0)) },
        );
    }
}

impl<
        P: Choose<W>,
        E: Entropy,
        const W: usize,
        const N: usize,
        const WIDE: bool,
        const MASK: usize,
        const LAYOUT: u8,
        Q: Position,
    > Decide for Runtime<'_, P, E, W, N, WIDE, MASK, LAYOUT, Q>
{
    #[inline(always)]
    fn apply(&mut self, event: u8) -> Applied {
        Runtime::apply(self, event)
    }

    #[inline(always)]
    fn decide(&mut self, pending: impl FnOnce() -> bool) -> Decision {
        Runtime::decide(self, pending)
    }

    #[inline(always)]
    fn reset(&mut self) {
        Runtime::reset(self)
    }

    #[inline(always)]
    fn counters(&self) -> &Counters {
        Runtime::counters(self)
    }

    #[inline(always)]
    fn is_safe(&self) -> bool {
        Runtime::is_safe(self)
    }

    #[inline(always)]
    fn note_unknown_byte(&mut self) {
        Runtime::note_unknown_byte(self)
    }

    #[inline(always)]
    fn note_overflows(&mut self, total: u32) {
        Runtime::note_overflows(self, total)
    }
}

/// The `rest` of [`take_until_stuck`] that moves every one of `holders`: their bits, or none of the
/// holder list passed (`indexed` layout).
#[inline(always)]
const fn every<const LAYOUT: u8>(holders: u32) -> u32 {
    if LAYOUT == INDEXED {
        0
    } else {
        holders
    }
}

/// Moves the automata of `rest`, in index order, by `event` until one cannot: that one, if any.
/// `rest` is what is left to move: the holders' bits (`ranked` layout), or in the `indexed` layout how
/// many of the event's holder list are passed (the list is in index order).
/// Out of line and over the runtime's parts, so that the compiler knows the stores to `records` and
/// `allowed` leave the set alone and keeps its fields in registers.
#[inline(never)]
fn take_until_stuck<
    const W: usize,
    const N: usize,
    const WIDE: bool,
    const MASK: usize,
    const LAYOUT: u8,
    Q: Position,
>(
    set: &SupervisorSet<'_, W, Q>,
    records: &mut [Q; N],
    allowed: &mut [[u32; W]; N],
    event: Event,
    rest: u32,
) -> Option<u8> {
    if LAYOUT == INDEXED {
        // SAFETY: an indexed set's check proved a holder list for every event (`event` is one) within the
        // table, and `rest` counts holders of the list.
        let list = unsafe {
            let bound = |i: usize| usize::from(*set.holder_lists.get_unchecked(i));
            set.holder_lists.get_unchecked(bound(event.index()) + rest as usize..bound(event.index() + 1))
        };
        for &entry in list {
            // The automaton in the low byte, the event's place in its alphabet in the high byte; the check
            // proved both.
            let (a, place) = (usize::from(entry as u8), usize::from(entry >> 8));
            // SAFETY: as for `step`; `place` is the event's in `a`'s alphabet.
            if unsafe { !step::<W, N, WIDE, MASK, LAYOUT, Q>(set, records, allowed, event, a, place) } {
                // At most MAX_AUTOMATA (32) automata: the index fits a byte.
                return Some(a as u8);
            }
        }
    } else {
        let mut holders = rest;
        while holders != 0 {
            let a = holders.trailing_zeros() as usize;
            holders &= holders - 1;
            // SAFETY: as for `step`; every holder bit of a checked set names one of the N automata.
            if unsafe { !step::<W, N, WIDE, MASK, LAYOUT, Q>(set, records, allowed, event, a, 0) } {
                return Some(a as u8);
            }
        }
    }
    None
}

/// Moves automaton `a`, which holds `event`, by it, if it can (`place` is the event's place in its
/// alphabet in the `indexed` layout); whether it could.
///
/// # Safety
///
/// `Runtime::new` took a checked set of `N` automata, `a` is below `N`, `event` is in `a`'s alphabet
/// (and at `place` in it when `INDEXED`); `records[a]` is a record of `a`, the initial state's, checked
/// by `restore` or a target's set here, and `allowed[a]` what it allows (an event of the automaton's
/// alphabet is allowed exactly when it leaves the state).
#[inline(always)]
unsafe fn step<
    const W: usize,
    const N: usize,
    const WIDE: bool,
    const MASK: usize,
    const LAYOUT: u8,
    Q: Position,
>(
    set: &SupervisorSet<'_, W, Q>,
    records: &mut [Q; N],
    allowed: &mut [[u32; W]; N],
    event: Event,
    a: usize,
    place: usize,
) -> bool {
    // SAFETY: the caller's promise; event ids of a checked set are below 32 · W.
    unsafe {
        let allowed = allowed.get_unchecked_mut(a);
        if !event.in_set_unchecked(allowed) {
            return false;
        }
        set.advance::<WIDE, MASK, LAYOUT>(
            set.automata.get_unchecked(a),
            records.get_unchecked_mut(a),
            allowed,
            event,
            place,
        );
    }
    true
}
