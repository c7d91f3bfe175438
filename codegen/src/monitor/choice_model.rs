//! What the monitor expects the controller to choose: the chance of each enabled command, for the
//! steering.
//!
//! A controller's choice is not uniform. The default policy, `random-local-queue`, draws a plant
//! uniformly among those with an enabled command, then takes the plant's current state's events once
//! per *round* in random order (firmware `choice.rs`): a command already taken in the current round is
//! not taken again until the round is over. A plant that always leads the closed loop along the same
//! cycle can meet that round in the same phase every time and never see a command it is waiting for. So
//! the monitor mirrors every site's round from the commands it sees (the same rule as the firmware's,
//! with the physical state standing for the controller's) and gives the steering the chances that
//! follow. `first` is deterministic: the lowest enabled event id, always — a command with a lower one
//! enabled beside it is never fired, and coverage does not count it ([`ChoiceModel::fires`]).
//! `local-queue` is deterministic too, given its cursors: the plants in a fixed cyclic order from the
//! plant cursor (the first with an enabled command), then at that plant's choice site the first of its
//! enabled commands at or after the site's cursor, cyclically; both cursors move past the command fired.
//! The monitor mirrors the cursors from the commands it sees and gives the command they pick the whole
//! chance, in every state as the cursors stand now (the plant's events do not move them, so what the
//! plant can bring about before the controller's next decision is judged exactly). Modelled as a
//! uniform choice, a fixed round looks as if it could take any enabled command while it keeps taking
//! the same one in the same state — the steering would hold the plant back for a target command the
//! round never reaches there. Other policies are modelled as uniform.

use std::collections::HashMap;

use super::steering::{Round, Site};
use crate::config::ChoicePolicy;
use crate::model::{Composition, EventId};

/// The controller's choice policy as far as the monitor models it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ChoiceModel {
    /// Every enabled command equally likely.
    #[default]
    Uniform,
    /// A uniform plant, then the plant's state's round (the firmware's `random-local-queue`).
    RandomLocalQueue,
    /// The lowest enabled event id (the firmware's `first`).
    First,
    /// A plant cursor and a cursor per choice site (the firmware's `local-queue`, the PLC program's).
    LocalQueue,
}

impl ChoiceModel {
    /// The model of a controller running `policy`.
    pub fn of(policy: ChoicePolicy) -> Self {
        match policy {
            ChoicePolicy::RandomLocalQueue => ChoiceModel::RandomLocalQueue,
            ChoicePolicy::First => ChoiceModel::First,
            ChoicePolicy::LocalQueue => ChoiceModel::LocalQueue,
            _ => ChoiceModel::Uniform,
        }
    }

    /// Whether a controller of this model can fire `command` where `enabled` are the enabled commands:
    /// always, but under `first` only the lowest id.
    pub fn fires(self, enabled: &[u32], command: u32) -> bool {
        self != ChoiceModel::First || enabled.iter().min() == Some(&command)
    }
}

/// The rounds of every choice site, mirrored; see the module documentation.
#[derive(Clone, Debug)]
pub struct Choices {
    model: ChoiceModel,
    /// Per global event: the plant that generates it (the first plant with it in its alphabet).
    owner: Vec<Option<usize>>,
    /// Per (plant, local state) that is a site: the events of the current round not taken yet.
    rounds: HashMap<(usize, u32), Vec<u32>>,
    /// The number of plants.
    plants: usize,
    /// `local-queue`: the plant the next choice starts at.
    plant_cursor: usize,
    /// `local-queue`: per (plant, local state) that is a site, the event id its next choice starts at.
    cursors: HashMap<(usize, u32), u32>,
}

impl Choices {
    /// A model of `policy` for the closed loop `closed`, whose first `plants` members are the plants.
    pub fn new(model: ChoiceModel, closed: &Composition, plants: usize, controllable: &[bool]) -> Self {
        let owner = (0..controllable.len())
            .map(|e| {
                let id = EventId::from_u32(e as u32);
                controllable[e].then(|| (0..plants).find(|&p| closed.has_event(p, id))).flatten()
            })
            .collect();
        Choices { model, owner, rounds: HashMap::new(), plants, plant_cursor: 0, cursors: HashMap::new() }
    }

    /// Back to the controller's initial state (a reset also resets its policy).
    pub fn reset(&mut self) {
        self.rounds.clear();
        self.plant_cursor = 0;
        self.cursors.clear();
    }

    /// `local-queue`: the number of plants and where the plant cursor stands (the steering keeps the
    /// cursor in its state, [`Steering::queue_at`](super::steering::Steering::queue_at)).
    pub fn queue(&self) -> Option<(usize, usize)> {
        (self.model == ChoiceModel::LocalQueue).then_some((self.plants, self.plant_cursor))
    }

    /// `local-queue`: the command picked among `enabled` in `state` with the plant cursor at `cursor`
    /// and the site cursors as they stand, as the firmware's `LocalQueue` and the PLC program's choice
    /// section pick it; and the plant cursor after it.
    pub fn queued(
        &self,
        closed: &Composition,
        state: &[u32],
        enabled: &[u32],
        cursor: usize,
    ) -> Option<(u32, usize)> {
        (0..self.plants).map(|i| (cursor + i) % self.plants).find_map(|p| {
            let mut mine: Vec<u32> =
                enabled.iter().copied().filter(|&e| self.owner.get(e as usize) == Some(&Some(p))).collect();
            mine.sort_unstable();
            let site = self.offered(closed, p, state[p]).len() >= 2;
            let cursor = if site { self.cursors.get(&(p, state[p])).copied().unwrap_or(0) } else { 0 };
            let pick = mine.iter().find(|&&e| e >= cursor).or(mine.first()).copied();
            pick.map(|e| (e, (p + 1) % self.plants))
        })
    }

    /// The controllable events plant `p` generates out of its local state `local`: the site's events.
    fn offered(&self, closed: &Composition, p: usize, local: u32) -> Vec<u32> {
        (0..self.owner.len() as u32)
            .filter(|&e| {
                self.owner[e as usize] == Some(p)
                    && closed.local_step(p, local, EventId::from_u32(e)).is_some()
            })
            .collect()
    }

    /// The choice site `command` is chosen at in `state`, under a policy with rounds: its plant in its
    /// current state, when that state offers two or more commands.
    pub fn site(&self, closed: &Composition, state: &[u32], command: u32) -> Option<Site> {
        if self.model != ChoiceModel::RandomLocalQueue {
            return None;
        }
        let p = (*self.owner.get(command as usize)?)?;
        (self.offered(closed, p, state[p]).len() >= 2).then_some((p, state[p]))
    }

    /// Where the round of `site` stands.
    pub fn round(&self, closed: &Composition, (p, local): Site) -> Round {
        Round {
            offered: self.offered(closed, p, local),
            left: self.rounds.get(&(p, local)).cloned().unwrap_or_default(),
        }
    }

    /// The controller fired `command` in `state`, where `enabled` were the enabled commands; returns the
    /// site whose round changed, if any.
    pub fn fired(
        &mut self,
        closed: &Composition,
        state: &[u32],
        enabled: &[u32],
        command: u32,
    ) -> Option<(usize, u32)> {
        if self.model == ChoiceModel::LocalQueue {
            // The plant cursor moves past the plant; at a site, the site's cursor past the command (the
            // site is returned: what it picks next changed).
            let p = (*self.owner.get(command as usize)?)?;
            self.plant_cursor = (p + 1) % self.plants.max(1);
            let site = (p, state[p]);
            let moved = self.offered(closed, p, state[p]).len() >= 2
                && self.cursors.insert(site, command + 1) != Some(command + 1);
            return moved.then_some(site);
        }
        if self.model != ChoiceModel::RandomLocalQueue {
            return None;
        }
        let p = (*self.owner.get(command as usize)?)?;
        let site = (p, state[p]);
        let offered = self.offered(closed, p, state[p]);
        if offered.len() < 2 {
            return None;
        }
        let round = self.rounds.entry(site).or_default();
        let mut candidates = enabled.iter().filter(|&&e| self.owner.get(e as usize) == Some(&Some(p)));
        // A new round starts when no candidate is left in it — and, where the mirror lost step (a
        // choice the controller dropped for its guard, or made in a state the monitor did not see), when
        // the command fired is not in it.
        if !round.contains(&command) || !candidates.any(|e| round.contains(e)) {
            *round = offered;
        }
        round.retain(|&e| e != command);
        Some(site)
    }

    /// The chance that the controller fires each of `enabled` (the enabled commands) in `state`, in the
    /// same order.
    pub fn chances(&self, closed: &Composition, state: &[u32], enabled: &[u32]) -> Vec<f32> {
        let uniform = || vec![1.0 / enabled.len() as f32; enabled.len()];
        if self.model == ChoiceModel::First {
            return enabled.iter().map(|&e| if self.model.fires(enabled, e) { 1.0 } else { 0.0 }).collect();
        }
        if self.model == ChoiceModel::LocalQueue {
            let next = self.queued(closed, state, enabled, self.plant_cursor).map(|(e, _)| e);
            return enabled.iter().map(|&e| if Some(e) == next { 1.0 } else { 0.0 }).collect();
        }
        if self.model != ChoiceModel::RandomLocalQueue || enabled.is_empty() {
            return uniform();
        }
        let owners: Vec<Option<usize>> =
            enabled.iter().map(|&e| self.owner.get(e as usize).copied().flatten()).collect();
        let mut plants: Vec<usize> = owners.iter().flatten().copied().collect();
        plants.sort_unstable();
        plants.dedup();
        if plants.is_empty() {
            return uniform();
        }
        let mut out = vec![0.0; enabled.len()];
        for &p in &plants {
            let mine: Vec<usize> = (0..enabled.len()).filter(|&k| owners[k] == Some(p)).collect();
            let round = self.rounds.get(&(p, state[p]));
            let in_round: Vec<usize> =
                mine.iter().copied().filter(|&k| round.is_none_or(|r| r.contains(&enabled[k]))).collect();
            let pool = if in_round.is_empty() || self.offered(closed, p, state[p]).len() < 2 {
                mine
            } else {
                in_round
            };
            for &k in &pool {
                out[k] = 1.0 / (plants.len() * pool.len()) as f32;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::automaton;
    use crate::model::{EventTable, Kind};

    /// One machine whose rest state offers three commands (a site), and a second plant with one.
    fn site() -> (Composition, Vec<bool>, EventTable) {
        let m = automaton(
            "M",
            Kind::Plant,
            2,
            &[0],
            &["a", "b", "c"],
            &[(0, "a", 1), (0, "b", 1), (0, "c", 1), (1, "done", 0)],
        );
        let n = automaton("N", Kind::Plant, 2, &[0], &["x"], &[(0, "x", 1), (1, "y", 0)]);
        let table = EventTable::build([&m, &n]).unwrap();
        let closed = Composition::new(&[&m, &n], &table).unwrap();
        let controllable = table.ids().map(|e| table.is_controllable(e)).collect();
        (closed, controllable, table)
    }

    #[test]
    fn a_round_takes_each_offered_command_once_as_the_firmware_does() {
        let (closed, controllable, t) = site();
        let id = |e: &str| t.id(e).unwrap().as_u32();
        let mut choices = Choices::new(ChoiceModel::RandomLocalQueue, &closed, 2, &controllable);
        let rest = [0, 1];
        let (a, b, c) = (id("a"), id("b"), id("c"));
        assert_eq!(choices.chances(&closed, &rest, &[a, b]), [0.5, 0.5], "a fresh round holds both");
        choices.fired(&closed, &rest, &[a, b], a);
        assert_eq!(choices.chances(&closed, &rest, &[a, b]), [0.0, 1.0], "a was taken this round");
        choices.fired(&closed, &rest, &[a, b], b);
        assert_eq!(choices.chances(&closed, &rest, &[a, b]), [0.5, 0.5], "only c is left: a new round");
        assert_eq!(choices.chances(&closed, &rest, &[a, b, c]), [0.0, 0.0, 1.0]);
        // A plant is drawn first: with N's x enabled too, M's pool shares half the chance.
        let both = [0, 0];
        let x = id("x");
        assert_eq!(choices.chances(&closed, &both, &[c, x]), [0.5, 0.5]);
        choices.reset();
        assert_eq!(choices.chances(&closed, &rest, &[a, b, c]), [1.0 / 3.0; 3]);
    }

    #[test]
    fn a_command_the_mirror_did_not_expect_starts_a_new_round() {
        let (closed, controllable, t) = site();
        let id = |e: &str| t.id(e).unwrap().as_u32();
        let mut choices = Choices::new(ChoiceModel::RandomLocalQueue, &closed, 2, &controllable);
        let rest = [0, 1];
        choices.fired(&closed, &rest, &[id("a"), id("b")], id("a"));
        // The controller fired a again (say it decided where the monitor did not look): the firmware's
        // round must have been new, so only a is gone from it.
        choices.fired(&closed, &rest, &[id("a"), id("b")], id("a"));
        assert_eq!(choices.chances(&closed, &rest, &[id("a"), id("b"), id("c")]), [0.0, 0.5, 0.5]);
    }

    #[test]
    fn a_local_queue_is_mirrored_from_its_cursors_as_the_firmware_picks() {
        let (closed, controllable, t) = site();
        let id = |e: &str| t.id(e).unwrap().as_u32();
        let mut choices = Choices::new(ChoiceModel::of(ChoicePolicy::LocalQueue), &closed, 2, &controllable);
        let (both, (a, b, x)) = ([0, 0], (id("a"), id("b"), id("x")));
        let enabled = [a, b, x];
        assert_eq!(choices.chances(&closed, &both, &enabled), [1.0, 0.0, 0.0], "plant M first, its lowest");
        assert_eq!(choices.fired(&closed, &both, &enabled, a), Some((0, 0)), "M's site cursor moved");
        assert_eq!(choices.queue(), Some((2, 1)));
        assert_eq!(choices.chances(&closed, &both, &enabled), [0.0, 0.0, 1.0], "then N, whatever M offers");
        assert_eq!(choices.fired(&closed, &both, &enabled, x), None, "N's state is no site");
        assert_eq!(choices.chances(&closed, &both, &enabled), [0.0, 1.0, 0.0], "M again, past a");
        // With the plant cursor elsewhere, the same state picks another command.
        assert_eq!(choices.queued(&closed, &both, &enabled, 1), Some((x, 0)));
        choices.reset();
        assert_eq!(choices.chances(&closed, &both, &enabled), [1.0, 0.0, 0.0]);
    }

    #[test]
    fn first_fires_only_the_lowest_enabled_id() {
        let (closed, controllable, t) = site();
        let id = |e: &str| t.id(e).unwrap().as_u32();
        let choices = Choices::new(ChoiceModel::of(ChoicePolicy::First), &closed, 2, &controllable);
        let (a, b, x) = (id("a"), id("b"), id("x"));
        assert_eq!(choices.chances(&closed, &[0, 0], &[b, a, x]), [0.0, 1.0, 0.0]);
        assert!(ChoiceModel::First.fires(&[b, a], a) && !ChoiceModel::First.fires(&[b, a], b));
        assert!(ChoiceModel::Uniform.fires(&[a, b], b));
    }

    #[test]
    fn other_policies_are_uniform() {
        let (closed, controllable, t) = site();
        let id = |e: &str| t.id(e).unwrap().as_u32();
        let mut choices = Choices::new(ChoiceModel::of(ChoicePolicy::GlobalQueue), &closed, 2, &controllable);
        assert_eq!(choices.fired(&closed, &[0, 1], &[id("a"), id("b")], id("a")), None);
        assert_eq!(choices.chances(&closed, &[0, 1], &[id("a"), id("b")]), [0.5, 0.5]);
    }
}
