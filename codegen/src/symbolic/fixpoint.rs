//! The symbolic fixed points: reachability and co-reachability within a set, and supC as the greatest
//! fixed point of "no bad state, no uncontrollable step out of the set, every state reaches a marked
//! one" (the Ramadge–Wonham fixed point ESCET and Supremica compute).
//!
//! Each walk chains the events (the image of one event feeds the next within a round), which reaches
//! the fixed point in fewer rounds than a breadth-first walk. After every round the progress observer
//! hears the phase and the BDD node counts, and the process's resident size is checked against
//! [`Config::memory_limit`].

use biodivine_lib_bdd::Bdd;

use super::encoding::{EventRelation, Space};
use crate::synth::memory::resident_bytes;
use crate::synth::{Config, SynthError};

/// One fixed-point computation on a space, with its limits and reports.
pub(crate) struct Walk<'a> {
    /// The encoded automata.
    pub space: &'a Space,
    cfg: &'a Config,
    what: &'a str,
    /// The largest BDD (nodes) seen after any round.
    pub peak_nodes: usize,
}

impl<'a> Walk<'a> {
    /// A walk over `space` reporting as `what`.
    pub(crate) fn new(space: &'a Space, cfg: &'a Config, what: &'a str) -> Self {
        Walk { space, cfg, what, peak_nodes: 0 }
    }

    /// Reports a finished round and checks the memory limit.
    fn round(&mut self, phase: &str, round: usize, set: &Bdd) -> Result<(), SynthError> {
        let nodes = set.size();
        self.peak_nodes = self.peak_nodes.max(nodes);
        self.cfg.stage(&format!("{}: {phase}, round {round}: {nodes} BDD nodes", self.what));
        if let (Some(limit), Some(resident)) = (self.cfg.memory_limit, resident_bytes()) {
            if resident > limit {
                return Err(SynthError::BddMemoryLimit {
                    what: self.what.to_owned(),
                    nodes,
                    resident,
                    limit,
                });
            }
        }
        Ok(())
    }

    /// The states reached from `from` by steps of `events` without leaving `within`.
    pub(crate) fn forward(&mut self, from: &Bdd, within: &Bdd, phase: &str) -> Result<Bdd, SynthError> {
        let events: Vec<&EventRelation> = self.space.events.iter().collect();
        self.closure(from, within, &events, phase, Space::image)
    }

    /// The states of `within` that reach `to` by steps of `events` without leaving `within`.
    pub(crate) fn backward(
        &mut self,
        to: &Bdd,
        within: &Bdd,
        events: &[&EventRelation],
        phase: &str,
    ) -> Result<Bdd, SynthError> {
        self.closure(to, within, events, phase, Space::preimage)
    }

    fn closure(
        &mut self,
        seed: &Bdd,
        within: &Bdd,
        events: &[&EventRelation],
        phase: &str,
        step: fn(&Space, &EventRelation, &Bdd) -> Bdd,
    ) -> Result<Bdd, SynthError> {
        let mut set = seed.and(within);
        for round in 1.. {
            let mut grew = false;
            for e in events {
                let new = step(self.space, e, &set).and(within).and_not(&set);
                if !new.is_false() {
                    set = set.or(&new);
                    grew = true;
                }
            }
            self.round(phase, round, &set)?;
            if !grew {
                break;
            }
        }
        Ok(set)
    }

    /// The states where the plant (the first `plants` components) can take an uncontrollable event
    /// that the specification (the others) refuses.
    pub(crate) fn bad(&self, plants: usize) -> Bdd {
        let space = self.space;
        let mut bad = space.vars.mk_false();
        for e in space.events.iter().filter(|e| !e.controllable) {
            let (plant, spec): (Vec<_>, Vec<_>) = e.parts.iter().partition(|(c, _)| *c < plants);
            if plant.is_empty() || spec.is_empty() {
                continue;
            }
            let all = |parts: &[&(usize, Bdd)]| {
                parts.iter().fold(space.vars.mk_true(), |acc, (c, r)| acc.and(&space.enabled(r, *c)))
            };
            bad = bad.or(&all(&plant).and_not(&all(&spec)));
        }
        bad
    }

    /// supC over the space whose first `plants` components are the plant: the reachable part of the
    /// greatest set of valid, good states from which no uncontrollable step leaves the set and from
    /// which a marked state is reachable within it.
    pub(crate) fn supc(&mut self, plants: usize) -> Result<Bdd, SynthError> {
        let space = self.space;
        let uncontrollable: Vec<&EventRelation> = space.events.iter().filter(|e| !e.controllable).collect();
        let all: Vec<&EventRelation> = space.events.iter().collect();
        let mut good = space.valid.and_not(&self.bad(plants));
        loop {
            let outside = space.valid.and_not(&good);
            let pushed =
                self.backward(&outside, &space.valid, &uncontrollable, "uncontrollable predecessors")?;
            let controllable = good.and_not(&pushed);
            let nonblocking = self.backward(&space.marked, &controllable, &all, "co-reachable")?;
            if good.and_not(&nonblocking).is_false() {
                break;
            }
            good = nonblocking;
        }
        self.forward(&space.initial, &good, "reachable")
    }

    /// Whether every state reachable in the product can reach a marked state.
    pub(crate) fn nonblocking(&mut self) -> Result<bool, SynthError> {
        let space = self.space;
        let all: Vec<&EventRelation> = space.events.iter().collect();
        let reach = self.forward(&space.initial, &space.valid, "reachable")?;
        let co = self.backward(&space.marked, &reach, &all, "co-reachable")?;
        Ok(reach.and_not(&co).is_false())
    }

    /// The number of transitions between states of `set`: per event, the states of `set` whose step
    /// stays in `set` (the automata are deterministic, so one step per state and event).
    pub(crate) fn transitions(&self, set: &Bdd) -> num_bigint::BigUint {
        self.space.events.iter().map(|e| self.space.count(&set.and(&self.space.preimage(e, set)))).sum()
    }
}
