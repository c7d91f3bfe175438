//! The virtual plant proper: the product system G1..Gn as the physical world the controller drives.

use super::Rng;
use crate::model::{Automaton, Composition, EventId, EventTable, ModelError};

/// How the virtual plant produces its uncontrollable events. Every draw comes from one [`Rng`] seeded
/// with [`PlantConfig::seed`], so the same seed and the same commands give the same events.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlantConfig {
    /// Seed of every random draw.
    pub seed: u64,
    /// Delay before the next uncontrollable event, in microseconds, drawn uniformly from `min..=max`
    /// (fixed when `min == max`).
    pub delay_us: (u64, u64),
    /// Per command (by name): the delay before the plant's answer to it, in place of `delay_us` — the
    /// plant's devices answering at rates of their own. A name that is not a command of the set is
    /// refused by [`VirtualPlant::new`].
    pub answer_delay_us: Vec<(String, (u64, u64))>,
    /// Chance (per mille) that an emission is a burst of several events sent back to back, so that they
    /// reach the controller between two of its reads (simultaneity).
    pub burst_per_mille: u32,
    /// Longest burst.
    pub burst_max: usize,
    /// Chance (per mille) that the plant answers a command at once instead of after a delay, so its event
    /// races the controller's next decision (inexact synchronisation).
    pub race_per_mille: u32,
    /// Chance (per mille) that the plant picks its next event by the rank the caller gives (the monitor's
    /// expected events to a transition not covered yet) rather than by its activities' durations; once
    /// the caller ranks nothing (coverage complete), the durations decide anyway.
    pub guide_per_mille: u32,
}

impl Default for PlantConfig {
    fn default() -> Self {
        PlantConfig {
            seed: 1,
            delay_us: (0, 100),
            answer_delay_us: Vec::new(),
            burst_per_mille: 100,
            burst_max: 4,
            race_per_mille: 100,
            guide_per_mille: 1000,
        }
    }
}

/// Why the plant refused a command.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Refusal {
    /// The id is not a controllable event of the set.
    #[error("event #{0} is not a controllable event")]
    NotControllable(u32),
    /// The plant cannot take the command in its current state.
    #[error("'{event}' is not physically possible now (refused by {})", refusers.join(", "))]
    NotPossible {
        /// Event name.
        event: String,
        /// The plant subsystems that have no transition for it.
        refusers: Vec<String>,
    },
}

/// The plant subsystems run as one physical system; see the module documentation.
///
/// # Examples
///
/// ```
/// use codegen::model::{Automaton, EventTable, Kind};
/// use codegen::plant::{PlantConfig, VirtualPlant};
///
/// let mut m = Automaton::new("M", Kind::Plant);
/// let idle = m.add_state("idle", true).unwrap();
/// let busy = m.add_state("busy", false).unwrap();
/// let start = m.add_event("start", true).unwrap();
/// let done = m.add_event("done", false).unwrap();
/// m.initial = Some(idle);
/// m.add_transition(idle, start, busy);
/// m.add_transition(busy, done, idle);
/// let table = EventTable::build([&m]).unwrap();
///
/// let mut plant = VirtualPlant::new(&[&m], &table, PlantConfig::default()).unwrap();
/// assert!(plant.emit().is_empty(), "an idle machine finishes nothing");
/// plant.command(table.id("start").unwrap()).unwrap();
/// assert_eq!(plant.emit(), [table.id("done").unwrap()]);
/// ```
#[derive(Clone, Debug)]
pub struct VirtualPlant {
    plants: Composition,
    controllable: Vec<bool>,
    names: Vec<String>,
    state: Vec<u32>,
    rng: Rng,
    config: PlantConfig,
    /// Plant time, in emitted events.
    clock: u64,
    /// Chance (per mille) that a guided pick ignores the guide after all (see [`VirtualPlant::explore`]).
    explore_per_mille: u32,
    /// Per global event: when the uncontrollable event, enabled since some time, is due.
    due: Vec<Option<u64>>,
    /// Per global event: the delay range of the answer to it when it is a command with a rate of its own
    /// ([`PlantConfig::answer_delay_us`]).
    answer_delay: Vec<Option<(u64, u64)>>,
    /// Per global event: another part of the loop raises it, never the plant ([`VirtualPlant::withhold`]).
    withheld: Vec<bool>,
}

/// Longest activity duration, in plant events, as a power of two: a duration is drawn uniformly below
/// `2^k` with `k` itself uniform in `0..=MAX_SCALE_LOG2`, so short and long activities mix.
const MAX_SCALE_LOG2: u64 = 5;

impl VirtualPlant {
    /// A plant made of `plants` over the global numbering of `table`, in its initial state.
    pub fn new(plants: &[&Automaton], table: &EventTable, config: PlantConfig) -> Result<Self, ModelError> {
        let plants = Composition::new(plants, table)?;
        let mut answer_delay = vec![None; table.len()];
        for (name, range) in &config.answer_delay_us {
            match table.id(name).filter(|&e| table.is_controllable(e)) {
                Some(e) => answer_delay[e.index()] = Some(*range),
                None => return Err(ModelError::UnknownEvent(format!("{name} (not a command of the set)"))),
            }
        }
        Ok(VirtualPlant {
            answer_delay,
            state: plants.initial(),
            plants,
            controllable: table.ids().map(|e| table.is_controllable(e)).collect(),
            names: table.ids().map(|e| table.name(e).to_owned()).collect(),
            rng: Rng::new(config.seed),
            clock: 0,
            explore_per_mille: 0,
            due: vec![None; table.len()],
            withheld: vec![false; table.len()],
            config,
        })
    }

    /// The configuration it runs with.
    pub fn config(&self) -> &PlantConfig {
        &self.config
    }

    /// The current local state of every plant subsystem.
    pub fn state(&self) -> &[u32] {
        &self.state
    }

    /// Puts the plant in `state` (after the monitor re-ordered a raced command). `state` must come from
    /// this plant's composition.
    pub fn set_state(&mut self, state: &[u32]) {
        self.state.copy_from_slice(state);
    }

    /// Back to the initial state (the random stream goes on: a reset is part of the run).
    pub fn reset(&mut self) {
        self.state = self.plants.initial();
        self.due.fill(None);
    }

    /// Takes a command from the controller when it is a controllable event the plant can take now.
    pub fn command(&mut self, event: EventId) -> Result<(), Refusal> {
        if !self.controllable.get(event.index()).copied().unwrap_or(false) {
            return Err(Refusal::NotControllable(event.as_u32()));
        }
        if self.plants.step(&mut self.state, event) {
            Ok(())
        } else {
            Err(Refusal::NotPossible {
                event: self.names[event.index()].clone(),
                refusers: self.plants.refusers(&self.state, event).into_iter().map(str::to_owned).collect(),
            })
        }
    }

    /// The uncontrollable events the plant can produce now, in id order (never a withheld one).
    pub fn enabled_uncontrollable(&self) -> Vec<EventId> {
        let own = |e: &EventId| !self.controllable[e.index()] && !self.withheld[e.index()];
        self.plants.enabled(&self.state).into_iter().filter(own).collect()
    }

    /// The plant never produces `events`: they are uncontrollable events of its automata that the
    /// target raises itself — a timer's timeout (`[[timers]]`), which the target reports and the plant
    /// then takes through [`VirtualPlant::set_state`].
    pub fn withhold(&mut self, events: impl IntoIterator<Item = EventId>) {
        for e in events {
            if let Some(w) = self.withheld.get_mut(e.index()) {
                *w = true;
            }
        }
    }

    /// Produces the next emission and takes it: one uncontrollable event, or with the configured chance a
    /// burst of several, each enabled after the ones before it. Empty when no uncontrollable event is
    /// possible.
    pub fn emit(&mut self) -> Vec<EventId> {
        let len = self.burst_len();
        let mut out = Vec::with_capacity(len);
        while out.len() < len {
            match self.emit_one(|_| None) {
                Some(e) => out.push(e),
                None => break,
            }
        }
        out
    }

    /// Makes a guided pick fall back to the activities' timing with chance `per_mille`. The caller raises
    /// it while its guide makes no progress: a guide that models the controller imperfectly can lead the
    /// closed loop around the same cycle for ever, and a little of the plant's own timing breaks it.
    pub fn explore(&mut self, per_mille: u32) {
        self.explore_per_mille = per_mille;
    }

    /// Whether the plant follows the caller's steering at all (`--guide` above 0).
    pub fn steers(&self) -> bool {
        self.config.guide_per_mille > 0
    }

    /// How many events the next emission holds: 1, or with the configured chance a burst of 2 or more.
    pub fn burst_len(&mut self) -> usize {
        if self.config.burst_max >= 2 && self.rng.chance(self.config.burst_per_mille) {
            self.rng.between(2, self.config.burst_max as u64) as usize
        } else {
            1
        }
    }

    /// Produces and takes one uncontrollable event: the one due first among those possible now.
    ///
    /// Each uncontrollable event is an activity of the plant (a machine working, a part travelling):
    /// when it becomes possible it gets a random duration, counted in plant events, drawn from a mix of
    /// short and long scales; the first to finish happens. So a long machining can see several parts
    /// arrive and leave, which a uniform draw at each step would almost never produce. Ties go to the
    /// lower event id. With the configured chance, `rank` decides first (lowest rank wins; `None` ranks
    /// last).
    pub fn emit_one(&mut self, mut rank: impl FnMut(EventId) -> Option<u32>) -> Option<EventId> {
        let enabled = self.enabled_uncontrollable();
        let mut possible = vec![false; self.due.len()];
        for &e in &enabled {
            possible[e.index()] = true;
            if self.due[e.index()].is_none() {
                let scale = 1u64 << self.rng.between(0, MAX_SCALE_LOG2);
                self.due[e.index()] = Some(self.clock + self.rng.below(scale));
            }
        }
        for (d, p) in self.due.iter_mut().zip(&possible) {
            if !p {
                *d = None;
            }
        }
        let guided = self.rng.chance(self.config.guide_per_mille) && !self.rng.chance(self.explore_per_mille);
        let e = enabled
            .into_iter()
            .map(|e| (if guided { rank(e).unwrap_or(u32::MAX) } else { 0 }, self.due[e.index()], e))
            .min()?
            .2;
        self.due[e.index()] = None;
        self.clock += 1;
        self.plants.step(&mut self.state, e);
        Some(e)
    }

    /// Microseconds to wait before the next emission; `after` is the command just taken, if any. Right
    /// after a command the plant may answer at once (a race with the controller's next decision), else
    /// after that command's own delay ([`PlantConfig::answer_delay_us`]) or the plant's.
    pub fn next_delay_us(&mut self, after: Option<EventId>) -> u64 {
        if after.is_some() && self.rng.chance(self.config.race_per_mille) {
            return 0;
        }
        let (lo, hi) = self.delay_range_us(after);
        self.rng.between(lo, hi)
    }

    /// The range [`VirtualPlant::next_delay_us`] draws from after `after` (a command with a delay of its
    /// own, or none): its upper end is the latest the plant's next emission may come.
    pub fn delay_range_us(&self, after: Option<EventId>) -> (u64, u64) {
        let own = after.and_then(|e| self.answer_delay.get(e.index()).copied().flatten());
        own.unwrap_or(self.config.delay_us)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::machine;
    use proptest::prelude::*;

    fn two_machines(config: PlantConfig) -> (VirtualPlant, EventTable) {
        let m1 = machine("M1", "a1", "b1");
        let m2 = machine("M2", "a2", "b2");
        let table = EventTable::build([&m1, &m2]).unwrap();
        (VirtualPlant::new(&[&m1, &m2], &table, config).unwrap(), table)
    }

    #[test]
    fn commands_are_checked_against_the_physical_state() {
        let (mut p, t) = two_machines(PlantConfig::default());
        let a1 = t.id("a1").unwrap();
        p.command(a1).unwrap();
        let err = p.command(a1).unwrap_err();
        assert_eq!(err.to_string(), "'a1' is not physically possible now (refused by M1)");
        assert_eq!(p.command(t.id("b1").unwrap()), Err(Refusal::NotControllable(1)));
        assert_eq!(p.command(EventId::from_u32(99)), Err(Refusal::NotControllable(99)));
    }

    #[test]
    fn bursts_take_several_enabled_events_back_to_back() {
        let config = PlantConfig { burst_per_mille: 1000, burst_max: 4, ..PlantConfig::default() };
        let (mut p, t) = two_machines(config);
        p.command(t.id("a1").unwrap()).unwrap();
        p.command(t.id("a2").unwrap()).unwrap();
        let mut burst = p.emit();
        burst.sort();
        assert_eq!(burst, [t.id("b1").unwrap(), t.id("b2").unwrap()], "both finish, then nothing is left");
        assert!(p.enabled_uncontrollable().is_empty());
    }

    #[test]
    fn races_answer_at_once_only_after_commands() {
        let config = PlantConfig { race_per_mille: 1000, delay_us: (10, 20), ..PlantConfig::default() };
        let (mut p, t) = two_machines(config);
        assert_eq!(p.next_delay_us(t.id("a1")), 0);
        assert!((10..=20).contains(&p.next_delay_us(None)));
    }

    #[test]
    fn a_command_with_a_rate_of_its_own_is_answered_after_its_delay() {
        let config = PlantConfig {
            race_per_mille: 0,
            delay_us: (10, 20),
            answer_delay_us: vec![("a1".into(), (5_000, 5_000)), ("a2".into(), (300, 400))],
            ..PlantConfig::default()
        };
        let (mut p, t) = two_machines(config);
        for _ in 0..50 {
            assert_eq!(p.next_delay_us(t.id("a1")), 5_000);
            assert!((300..=400).contains(&p.next_delay_us(t.id("a2"))));
            assert!((10..=20).contains(&p.next_delay_us(None)));
        }
    }

    #[test]
    fn a_withheld_event_is_never_produced() {
        let (mut p, t) = two_machines(PlantConfig { burst_per_mille: 0, ..PlantConfig::default() });
        p.withhold([t.id("b1").unwrap()]);
        p.command(t.id("a1").unwrap()).unwrap();
        p.command(t.id("a2").unwrap()).unwrap();
        assert_eq!(p.enabled_uncontrollable(), [t.id("b2").unwrap()]);
        assert_eq!(p.emit(), [t.id("b2").unwrap()]);
        assert!(p.emit().is_empty(), "M1 waits for its b1 from elsewhere");
    }

    #[test]
    fn an_answer_delay_for_an_event_that_is_no_command_is_refused() {
        for name in ["b1", "nope"] {
            let config =
                PlantConfig { answer_delay_us: vec![(name.into(), (1, 2))], ..PlantConfig::default() };
            let m1 = machine("M1", "a1", "b1");
            let table = EventTable::build([&m1]).unwrap();
            let Err(err) = VirtualPlant::new(&[&m1], &table, config) else { panic!("{name}: taken") };
            assert!(err.to_string().contains(name), "{err}");
        }
    }

    proptest! {
        /// Same seed, same commands ⇒ same emissions; and every emitted event was possible when emitted.
        #[test]
        fn replayable_and_physically_possible(seed in any::<u64>(), script in proptest::collection::vec(0u8..4, 0..60)) {
            let config = PlantConfig { seed, burst_per_mille: 300, ..PlantConfig::default() };
            let run = || {
                let (mut p, t) = two_machines(config.clone());
                let reference = p.plants.clone();
                let mut shadow = reference.initial();
                let mut log = Vec::new();
                for &s in &script {
                    let name = ["a1", "a2", "a1", "a2"][usize::from(s)];
                    if p.command(t.id(name).unwrap()).is_ok() {
                        assert!(reference.step(&mut shadow, t.id(name).unwrap()));
                        log.push(t.id(name).unwrap());
                    }
                    for e in p.emit() {
                        assert!(reference.step(&mut shadow, e), "emitted an impossible event");
                        log.push(e);
                    }
                    log.push(EventId::from_u32(p.next_delay_us(Some(t.id(name).unwrap())) as u32));
                    assert_eq!(p.state(), &shadow[..]);
                }
                log
            };
            prop_assert_eq!(run(), run());
        }
    }
}
