//! State feedback control on the microcontroller (design notes §10): no supervisor tables and no event
//! tracked. The plant's signals are one packed word; per controllable event σ the tables hold F_σ as
//! cubes, `(mask, value)` pairs over the word (a cube holds when `word & mask == value`), and a decision
//! evaluates every F_σ on the current word, chooses among the events whose formula holds with the
//! policies of [`crate::choice`], and writes the chosen command's outputs into the word, so that the next
//! decision sees them: two decisions firing σ1 then σ2 are the trace σ1σ2 of the closed loop.
//!
//! Inputs: a board samples its pins into the word's input bits; under QEMU the virtual plant sends its
//! sensor events over the link as for the event-based firmware, and [`StateRuntime::apply`] writes each
//! event's *virtual pins* (its target state's input literals, the same whatever the source state: codegen
//! refuses a plant where they are not) into the word.
//!
//! The choice policies read a [`View`]: the controllable events, one "plant" per state-vector component
//! with the commands it owns, and the choice sites (component states with two or more commands
//! leaving); each decision reads every component's state off the word ([`StateTables::readings`]) for
//! the local policies' sites. Counters, guard, faults and the choice itself are the
//! [`crate::shell`] the supervisor runtime shares.
//!
//! Everything read from the tables goes through checked accessors: tables inconsistent with themselves
//! disable events, never panic.

use crate::choice::{Choose, View};
use crate::event_set::EventSet;
use crate::rng::Entropy;
use crate::shell::{Applied, Config, Core, Counters, Decide, Decision, Shell};

/// A product of literals over the signal word: the signals of `mask` at the values of `value`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cube {
    /// The signals the cube fixes (bit `i`: signal `i`).
    pub mask: u32,
    /// Their values (bits outside `mask` are 0).
    pub value: u32,
}

impl Cube {
    /// Whether the cube holds on `word`.
    #[inline(always)]
    pub const fn holds(self, word: u32) -> bool {
        word & self.mask == self.value
    }

    /// `word` with the cube's signals set to its values (a command's outputs, a sensor's inputs).
    #[inline(always)]
    pub const fn write(self, word: u32) -> u32 {
        (word & !self.mask) | self.value
    }
}

/// One controllable event's formula: the event, and the end of its cubes in [`StateTables::cubes`] (they
/// start where the previous rule's end, the first at 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rule {
    /// The controllable event.
    pub event: u8,
    /// One past its last cube in [`StateTables::cubes`].
    pub end: u16,
}

/// How one state of a state-vector component reads off the word, for the local choice policies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reading<const W: usize> {
    /// The state's formula.
    pub cube: Cube,
    /// The events that leave it: its commands (physically possible there) and its sensor events (what
    /// the plant may do next; the cost harness's plant reads them).
    pub leaving: [u32; W],
    /// Its code, an entry of the choice view's `sites` when it is a choice site.
    pub code: u16,
}

/// The state-based tables `codegen emit` writes for `[runtime] mode = "state"`.
#[derive(Clone, Copy, Debug)]
pub struct StateTables<'t, const W: usize> {
    /// The word in the initial state: the initial states' literals, every other signal 0.
    pub initial: u32,
    /// Per controllable event, in id order: its formula's cubes in [`StateTables::cubes`].
    pub rules: &'t [Rule],
    /// Every rule's cubes, back to back.
    pub cubes: &'t [Cube],
    /// Per event id, what it writes into the word: a controllable event its command's outputs, an
    /// uncontrollable one its virtual pins (the inputs its target state fixes).
    pub writes: &'t [Cube],
    /// Per event id, the components whose plant has it (bit `c`: component `c`; at most 32 components).
    pub holders: &'t [u32],
    /// Per component, one past its last state in [`StateTables::readings`] (the first starts at 0).
    pub components: &'t [u16],
    /// Every component's states, component after component.
    pub readings: &'t [Reading<W>],
    /// The controllable events that have a rule.
    pub controllable: [u32; W],
    /// Per component: the commands it owns (the choice policies' plants).
    pub plant_events: &'t [[u32; W]],
    /// The choice sites: codes of the readings of component states with two or more commands leaving.
    pub sites: &'t [u16],
}

impl<const W: usize> StateTables<'_, W> {
    /// The events whose formula holds on `word`. Every cube of every rule is evaluated, none skipped, so
    /// the time does not depend on the word (a PLC scan's property); a rule whose end lies before its
    /// start takes no cube, one past the cubes the cubes there are.
    #[inline(never)]
    pub fn enabled(&self, word: u32) -> EventSet<W> {
        let mut enabled = EventSet::EMPTY;
        // Rules past the cubes end with them.
        let (mut at, last) = (0, self.cubes.len());
        for rule in self.rules {
            let end = usize::from(rule.end).min(last);
            let mut holds = false;
            while at < end {
                holds |= self.cubes.get(at).is_some_and(|c| c.holds(word));
                at += 1;
            }
            if holds {
                enabled.insert(rule.event);
            }
        }
        enabled.and(&EventSet(self.controllable))
    }

    /// The reading of component `c`'s state on `word`: the first of its states whose formula holds.
    pub fn reading(&self, c: usize, word: u32) -> Option<&Reading<W>> {
        self.states(c)?.iter().find(|r| r.cube.holds(word))
    }

    /// Component `c`'s states.
    fn states(&self, c: usize) -> Option<&[Reading<W>]> {
        let start = if c == 0 { 0 } else { usize::from(*self.components.get(c - 1)?) };
        let end = usize::from(*self.components.get(c)?);
        self.readings.get(start..end)
    }

    /// Whether uncontrollable `event` may happen at `word`: every component holding it reads as a state
    /// it leaves. The first holder that does not, if any.
    pub fn unexpected(&self, event: u8, word: u32) -> Option<u8> {
        let mut holders = self.holders.get(usize::from(event)).copied().unwrap_or(0);
        while holders != 0 {
            let c = holders.trailing_zeros();
            holders &= holders - 1;
            if !self.reading(c as usize, word).is_some_and(|r| EventSet(r.leaving).contains(event)) {
                // Below 32.
                return Some(c as u8);
            }
        }
        None
    }
}

/// The state-based runtime over `C` components and events in `W`-word bitsets, choosing with policy `P`
/// and drawing entropy from `E`. It answers the event loop as [`crate::runtime::Runtime`] does
/// ([`Decide`]), through the same [`Shell`].
pub struct StateRuntime<'t, P, E, const W: usize, const C: usize> {
    core: Word<'t, W, C>,
    shell: Shell<P, E>,
}

/// The state tables and the signal word: the state runtime's [`Core`].
struct Word<'t, const W: usize, const C: usize> {
    tables: &'t StateTables<'t, W>,
    /// The signals: inputs as last sampled (or written by a sensor event), outputs as last commanded.
    word: u32,
    /// Per component, its state's code at the last decision (`u16::MAX`: none reads).
    records: [u16; C],
    /// Per component, the events leaving its state at the last decision (the choice view keeps its
    /// commands).
    allowed: [[u32; W]; C],
}

impl<'t, P: Choose<W>, E: Entropy, const W: usize, const C: usize> StateRuntime<'t, P, E, W, C> {
    /// A runtime with the word in its initial state.
    pub fn new(tables: &'t StateTables<'t, W>, config: Config, policy: P, entropy: E) -> Self {
        let core = Word { tables, word: tables.initial, records: [u16::MAX; C], allowed: [[0; W]; C] };
        let mut rt = Self { core, shell: Shell::new(config, policy, entropy) };
        Decide::reset(&mut rt);
        rt
    }

    /// The signal word.
    pub fn word(&self) -> u32 {
        self.core.word
    }

    /// Puts the word at `word` (a board's sampled inputs, or a checkpoint a host tool restores).
    pub fn set_word(&mut self, word: u32) {
        self.core.word = word;
    }

    /// The controllable events whose formula holds on the current word.
    pub fn enabled(&self) -> EventSet<W> {
        self.core.enabled()
    }

    /// The counters.
    pub fn counters(&self) -> &Counters {
        self.shell.counters()
    }

    /// The tables.
    pub fn tables(&self) -> &'t StateTables<'t, W> {
        self.core.tables
    }
}

impl<const W: usize, const C: usize> Core<W> for Word<'_, W, C> {
    type State = u16;
    /// What the input writes into the word.
    type Input = Cube;

    #[inline(always)]
    fn input(&self, event: u8) -> Option<Cube> {
        let &write = self.tables.writes.get(usize::from(event))?;
        (!EventSet(self.tables.controllable).contains(event)).then_some(write)
    }

    /// Writes the virtual pins of uncontrollable `event` into the word; an event no state of a component
    /// holding it leaves as the word reads is unexpected, as in the supervisor runtime.
    #[inline(always)]
    fn take(&mut self, event: u8, write: Cube) -> Option<u8> {
        let unexpected = self.tables.unexpected(event, self.word);
        // The sensor changed whatever the tables expected: the word follows the plant.
        self.word = write.write(self.word);
        unexpected
    }

    #[inline(always)]
    fn enabled(&self) -> EventSet<W> {
        self.tables.enabled(self.word)
    }

    /// Reads every component's state off the word when the policy reads the plants' states.
    #[inline(always)]
    fn view(&mut self, sites: bool) -> View<'_, W, u16> {
        if sites {
            let all = self.records.iter_mut().zip(&mut self.allowed).enumerate();
            for (c, (code, leaving)) in all {
                match self.tables.reading(c, self.word) {
                    Some(r) => (*code, *leaving) = (r.code, r.leaving),
                    None => (*code, *leaving) = (u16::MAX, [0; W]),
                }
            }
        }
        View {
            controllable: &self.tables.controllable,
            plant_events: self.tables.plant_events,
            sites: self.tables.sites,
            records: &self.records,
            allowed: &self.allowed,
        }
    }

    #[inline(always)]
    fn fire(&mut self, c: u8) -> bool {
        let Some(&write) = self.tables.writes.get(usize::from(c)) else {
            return false;
        };
        self.word = write.write(self.word);
        true
    }

    fn reset(&mut self) {
        self.word = self.tables.initial;
    }
}

impl<P: Choose<W>, E: Entropy, const W: usize, const C: usize> Decide for StateRuntime<'_, P, E, W, C> {
    #[inline(never)]
    fn apply(&mut self, event: u8) -> Applied {
        self.shell.apply(&mut self.core, event)
    }

    #[inline(never)]
    fn decide(&mut self, pending: impl FnOnce() -> bool) -> Decision {
        self.shell.decide(&mut self.core, pending)
    }

    fn reset(&mut self) {
        self.shell.reset(&mut self.core);
    }

    fn counters(&self) -> &Counters {
        self.shell.counters()
    }

    fn is_safe(&self) -> bool {
        self.shell.is_safe()
    }

    fn note_unknown_byte(&mut self) {
        self.shell.note_unknown();
    }

    fn note_overflows(&mut self, total: u32) {
        self.shell.note_overflows(total);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::choice::First;
    use crate::fault::FaultPolicy;
    use crate::rng::SeedEntropy;

    // One component, input X (bit 0), output Y (bit 1): idle (!Y !X) –go(0)→ busy (Y !X) –done(1)→
    // ended (Y X) –off(2)→ idle'(!Y X) –reset(3)→ idle. go when !Y !X, off when Y X.
    static RULES: [Rule; 2] = [Rule { event: 0, end: 1 }, Rule { event: 2, end: 2 }];
    static CUBES: [Cube; 2] = [Cube { mask: 0b11, value: 0b00 }, Cube { mask: 0b11, value: 0b11 }];
    static WRITES: [Cube; 4] = [
        Cube { mask: 0b10, value: 0b10 },
        Cube { mask: 0b01, value: 0b01 },
        Cube { mask: 0b10, value: 0b00 },
        Cube { mask: 0b01, value: 0b00 },
    ];
    static READINGS: [Reading<1>; 1] =
        [Reading { cube: Cube { mask: 0, value: 0 }, leaving: [0b1111], code: 0 }];
    static TABLES: StateTables<'static, 1> = StateTables {
        initial: 0,
        rules: &RULES,
        cubes: &CUBES,
        writes: &WRITES,
        holders: &[0, 1, 0, 1],
        components: &[1],
        readings: &READINGS,
        controllable: [0b101],
        plant_events: &[[0b101]],
        sites: &[],
    };

    fn config(on_fault: FaultPolicy) -> Config {
        Config { guard: true, on_fault, reseed_every: 0 }
    }

    fn runtime(
        tables: &'static StateTables<'static, 1>,
        on_fault: FaultPolicy,
    ) -> StateRuntime<'static, First, SeedEntropy, 1, 1> {
        StateRuntime::new(tables, config(on_fault), First, SeedEntropy::new(1))
    }

    #[test]
    fn a_cycle_fires_each_command_where_its_cube_holds_and_writes_its_outputs() {
        let mut rt = runtime(&TABLES, FaultPolicy::Continue);
        assert_eq!(rt.decide(|| false), Decision::Fired(0));
        assert_eq!(rt.word(), 0b10);
        assert_eq!(rt.decide(|| false), Decision::Idle, "busy: nothing until the sensor");
        assert_eq!(rt.apply(1), Applied::Taken);
        assert_eq!(rt.word(), 0b11);
        assert_eq!(rt.decide(|| true), Decision::Redecide, "the guard drops a choice made under an input");
        assert_eq!(rt.decide(|| false), Decision::Fired(2));
        assert_eq!(rt.apply(3), Applied::Taken);
        assert_eq!(rt.word(), 0);
        let c = rt.counters();
        assert_eq!((c.events_in, c.commands_out, c.guard_redecisions), (2, 2, 1));
    }

    #[test]
    fn a_command_or_an_unknown_byte_as_input_is_a_fault_and_reset_restores_the_word() {
        let mut rt = runtime(&TABLES, FaultPolicy::SafeState);
        assert_eq!(rt.decide(|| false), Decision::Fired(0));
        assert_eq!(rt.apply(0), Applied::Unknown, "a command is no input");
        assert_eq!(rt.apply(9), Applied::Unknown, "no such event");
        assert_eq!(rt.counters().unknown_bytes, 2);
        assert!(rt.is_safe());
        assert_eq!(rt.decide(|| false), Decision::Halted);
        rt.note_overflows(3);
        assert_eq!(rt.counters().overflows, 3);
        Decide::reset(&mut rt);
        assert_eq!((rt.word(), rt.is_safe(), rt.counters().unknown_bytes), (0, false, 0));
        assert_eq!(rt.decide(|| false), Decision::Fired(0));
    }

    #[test]
    fn a_sensor_event_the_state_does_not_leave_is_unexpected_and_still_written() {
        // The component reads as idle (!X) or ended (X); `done` (1) leaves idle only, `reset` (3) ended only.
        static TWO: [Reading<1>; 2] = [
            Reading { cube: Cube { mask: 0b01, value: 0b00 }, leaving: [0b0011], code: 0 },
            Reading { cube: Cube { mask: 0b01, value: 0b01 }, leaving: [0b1100], code: 1 },
        ];
        static T: StateTables<'static, 1> = StateTables { components: &[2], readings: &TWO, ..TABLES };
        let mut rt = runtime(&T, FaultPolicy::Continue);
        assert_eq!(rt.apply(3), Applied::Unexpected { automaton: 0 });
        assert_eq!(rt.apply(1), Applied::Taken);
        assert_eq!(rt.word(), 0b01);
        assert_eq!(rt.apply(1), Applied::Unexpected { automaton: 0 });
        assert_eq!((rt.counters().events_in, rt.counters().unexpected), (3, 2));
    }

    #[test]
    fn rules_past_the_cubes_and_components_past_the_readings_disable_never_panic() {
        static BAD_RULES: [Rule; 2] = [Rule { event: 0, end: 7 }, Rule { event: 2, end: 1 }];
        static BAD: StateTables<'static, 1> = StateTables { rules: &BAD_RULES, components: &[5], ..TABLES };
        let mut rt = runtime(&BAD, FaultPolicy::Continue);
        // Rule 0 takes both cubes there are, rule 2 (ending before it starts) none; the component reads
        // as no state, so its sensor event is unexpected (and still written).
        assert_eq!(rt.decide(|| false), Decision::Fired(0));
        assert_eq!(rt.apply(1), Applied::Unexpected { automaton: 0 });
        assert_eq!(rt.decide(|| false), Decision::Fired(0));
        assert_eq!(BAD.enabled(0b11), EventSet([0b001]));
        assert_eq!(BAD.reading(0, 0), None);
        assert_eq!(BAD.reading(3, 0), None);
    }
}
