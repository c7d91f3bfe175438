//! The controller of a simulated run: the firmware's own choice policies (`firmware::choice`) deciding
//! on the closed loop's enabled commands, as the runtime does on its tables.
//!
//! The runtime hands a policy a [`View`] of its plants (the events each generates, where each is, what
//! it allows there, its choice sites) and the enabled set; here the same view is read off the
//! composition plants ‖ supervisors, over the set's global event ids — the ids the firmware's tables
//! use. The policies are the shipped code, compiled for the host with the widest bitset the link's
//! one-byte event ids allow.

use firmware::choice::{
    Choose, First, GlobalQueue, LocalQueue, Random, RandomGlobalQueue, RandomLocalQueue, View,
};
use firmware::event_set::EventSet;
use firmware::rng::{Rng, SeedEntropy};

use crate::config::{ChoicePolicy, RuntimeConfig};
use crate::model::{Composition, EventId, EventTable};

/// Words of the bitsets: 256 events, every id a byte can name.
const W: usize = 8;
/// Choice sites the queue policies keep a cursor or round for; a site beyond them falls back to its
/// first event, as a table without that site does.
const SITES: usize = 256;

/// One of the six policies, as the emitted tables would name it.
enum Policy {
    First(First),
    Random(Random),
    GlobalQueue(GlobalQueue),
    RandomGlobalQueue(Box<RandomGlobalQueue<W>>),
    LocalQueue(Box<LocalQueue<SITES>>),
    RandomLocalQueue(Box<RandomLocalQueue<W, SITES>>),
}

/// The controller: a policy, its generator, and the view's fixed parts.
pub struct Controller {
    policy: Policy,
    rng: Rng<SeedEntropy>,
    controllable: [u32; W],
    /// Per plant: the controllable events it generates (the first plant with the event in its alphabet).
    plant_events: Vec<[u32; W]>,
    /// First site code of each plant: a plant's state `s` is `offset[p] + s`.
    offset: Vec<u32>,
    /// The codes of the choice sites, ascending.
    sites: Vec<u32>,
    plants: usize,
    events: usize,
}

fn set_bit(words: &mut [u32; W], e: usize) {
    if let Some(w) = words.get_mut(e / 32) {
        *w |= 1 << (e % 32);
    }
}

impl Controller {
    /// The controller of `runtime` for the closed loop `closed`, whose first `plants` members are the
    /// plants; `None` when the set has more events than a byte names (no firmware runs it either).
    pub fn new(
        runtime: &RuntimeConfig,
        closed: &Composition,
        plants: usize,
        table: &EventTable,
    ) -> Option<Self> {
        let events = table.len();
        if events > W * 32 {
            return None;
        }
        let is_controllable = |e: usize| table.is_controllable(EventId::from_u32(e as u32));
        let mut controllable = [0; W];
        let mut plant_events = vec![[0; W]; plants];
        for e in (0..events).filter(|&e| is_controllable(e)) {
            set_bit(&mut controllable, e);
            let id = EventId::from_u32(e as u32);
            if let Some(p) = (0..plants).find(|&p| closed.has_event(p, id)) {
                set_bit(&mut plant_events[p], e);
            }
        }
        let mut offset = Vec::with_capacity(plants);
        let mut sites = Vec::new();
        let mut next = 0u32;
        for (p, generated) in plant_events.iter().enumerate() {
            offset.push(next);
            let states = closed.dfas()[p].state_count() as u32;
            for s in 0..states {
                let out = (0..events)
                    .filter(|&e| bit(generated, e))
                    .filter(|&e| closed.local_step(p, s, EventId::from_u32(e as u32)).is_some())
                    .count();
                if out >= 2 {
                    sites.push(next + s);
                }
            }
            next += states;
        }
        let policy = match runtime.policy {
            ChoicePolicy::First => Policy::First(First),
            ChoicePolicy::Random => Policy::Random(Random),
            ChoicePolicy::GlobalQueue => Policy::GlobalQueue(GlobalQueue::default()),
            ChoicePolicy::RandomGlobalQueue => Policy::RandomGlobalQueue(Box::default()),
            ChoicePolicy::LocalQueue => Policy::LocalQueue(Box::default()),
            ChoicePolicy::RandomLocalQueue => Policy::RandomLocalQueue(Box::default()),
        };
        Some(Controller {
            policy,
            rng: Rng::new(SeedEntropy::new(runtime.seed), runtime.reseed_every),
            controllable,
            plant_events,
            offset,
            sites,
            plants,
            events,
        })
    }

    /// The command the policy fires in `state` of `closed`, or `None` when no command is enabled.
    pub fn decide(&mut self, closed: &Composition, state: &[u32]) -> Option<EventId> {
        let mut enabled = [0; W];
        for e in closed.enabled(state) {
            if bit(&self.controllable, e.index()) {
                set_bit(&mut enabled, e.index());
            }
        }
        let enabled = EventSet(enabled);
        if enabled.is_empty() {
            return None;
        }
        let records: Vec<u32> = (0..self.plants).map(|p| self.offset[p] + state[p]).collect();
        let allowed: Vec<[u32; W]> = (0..self.plants)
            .map(|p| {
                let mut words = [0; W];
                for e in 0..self.events {
                    let id = EventId::from_u32(e as u32);
                    if !closed.has_event(p, id) || closed.local_step(p, state[p], id).is_some() {
                        set_bit(&mut words, e);
                    }
                }
                words
            })
            .collect();
        let view = View {
            controllable: &self.controllable,
            plant_events: &self.plant_events,
            sites: &self.sites,
            records: &records,
            allowed: &allowed,
        };
        let rng = &mut self.rng;
        let chosen = match &mut self.policy {
            Policy::First(p) => p.choose(view, &enabled, rng),
            Policy::Random(p) => p.choose(view, &enabled, rng),
            Policy::GlobalQueue(p) => p.choose(view, &enabled, rng),
            Policy::RandomGlobalQueue(p) => p.choose(view, &enabled, rng),
            Policy::LocalQueue(p) => p.choose(view, &enabled, rng),
            Policy::RandomLocalQueue(p) => p.choose(view, &enabled, rng),
        };
        chosen.map(|e| EventId::from_u32(u32::from(e)))
    }
}

fn bit(words: &[u32; W], e: usize) -> bool {
    words.get(e / 32).is_some_and(|w| w >> (e % 32) & 1 == 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_fires_the_lowest_enabled_command_and_none_when_none_is_enabled() {
        let sim = crate::sim::tests::small();
        let runtime = RuntimeConfig { policy: ChoicePolicy::First, ..RuntimeConfig::default() };
        let mut c = Controller::new(&runtime, &sim.closed, sim.plants, sim.set.events()).unwrap();
        let table = sim.set.events();
        let mut state = sim.closed.initial();
        for _ in 0..20 {
            let lowest = sim.closed.enabled(&state).into_iter().find(|&e| table.is_controllable(e));
            let chosen = c.decide(&sim.closed, &state);
            assert_eq!(chosen, lowest);
            // Move on by the choice, or by the plant's one uncontrollable event.
            let next = chosen.or_else(|| sim.closed.enabled(&state).into_iter().next()).unwrap();
            assert!(sim.closed.step(&mut state, next));
        }
    }

    #[test]
    fn every_policy_fires_only_enabled_commands() {
        let sim = crate::sim::tests::small();
        let table = sim.set.events();
        for policy in ChoicePolicy::ALL {
            let runtime = RuntimeConfig { policy, ..RuntimeConfig::default() };
            let mut c = Controller::new(&runtime, &sim.closed, sim.plants, table).unwrap();
            let mut state = sim.closed.initial();
            for _ in 0..50 {
                let enabled = sim.closed.enabled(&state);
                let next = match c.decide(&sim.closed, &state) {
                    Some(e) => {
                        assert!(enabled.contains(&e) && table.is_controllable(e), "{policy:?}: {e:?}");
                        e
                    }
                    None => {
                        assert!(enabled.iter().all(|&e| !table.is_controllable(e)), "{policy:?}");
                        enabled[0]
                    }
                };
                assert!(sim.closed.step(&mut state, next));
            }
        }
    }
}
