//! How the virtual plant steers the closed loop towards the supervisor transitions a run has not taken
//! yet: the expected number of events from each closed-loop state to the next new one, when the plant
//! plays its best and the controller chooses at random.
//!
//! The closed loop is a game between two players. In a state where the supervisors enable controllable
//! events, the controller fires one of them as soon as it has read the plant's events — which one is up to
//! its choice policy, whose chances the monitor's [`Choices`](super::choice_model::Choices) model gives.
//! The plant may instead produce one of its uncontrollable events first (in a burst the controller reads
//! whole), or, where only uncontrollable events are possible, must. So each state has a value: with
//! `wait` the expectation over the enabled commands (zero for a command that takes a new transition),
//! with each uncontrollable `u` the value after `u`, each plus one event; the state's value is the best
//! of them. Who has the initiative matters: right after a command, a controller with another command
//! enabled fires it at once, before the plant can answer; so a state has a second value, reached by a
//! command, in which only the controller moves while it can. Value iteration from the breadth-first
//! distance (a lower bound) converges to both; after a change it starts again from the previous values.
//!
//! The plant asks two things: how good each of its events is ([`Steering::rank_after`]) and who should
//! move next ([`Steering::next_move`]): the controller (the plant holds its events back), or the plant —
//! before the controller decides, when the controller has a choice there ([`Move::PlantFirst`]: the plant
//! sends its events in one held burst), or simply because the controller has nothing to do.

use super::coverage::Graph;

/// Most sweeps of value iteration per refresh; values are used as a ranking, so near convergence is
/// enough.
const MAX_SWEEPS: usize = 400;
/// Largest change in a sweep (in events) at which the values count as converged.
const EPSILON: f32 = 0.01;
/// Value of a state from which no target can be reached.
const UNREACHABLE: f32 = 1.0e9;
/// Least chance given to a target command, as a share of a uniform choice among the state's commands.
const TARGET_FLOOR: f32 = 0.5;
/// Fixed-point scale of [`Steering::rank_after`]: ranks in sixteenths of an event.
const RANK_SCALE: f32 = 16.0;

/// Who should move next in a closed-loop state, for the fastest way to a new transition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Move {
    /// Let the controller choose among its commands.
    Controller,
    /// The controller could choose, but one of the plant's events leads faster: produce it before the
    /// controller decides.
    PlantFirst,
    /// Only the plant can move, or nothing is left to steer to.
    Plant,
}

/// One transition out of a closed-loop state, as the steering sees it.
#[derive(Clone, Copy, Debug, Default)]
struct Step {
    /// A command (the controller's) rather than one of the plant's events.
    command: bool,
    /// A command that takes a transition not taken yet.
    target: bool,
    /// For a command, the chance the controller fires it there.
    chance: f32,
}

/// Expected events to the next new transition, per closed-loop state number; see the module docs.
#[derive(Clone, Debug, Default)]
pub struct Steering {
    /// Per state, reached by one of the plant's events: the plant may move first.
    values: Vec<f32>,
    /// Per state, reached by a command: the controller moves again while it has a command.
    after_command: Vec<f32>,
    /// Per state, its outgoing transitions in the graph's order.
    steps: Vec<Vec<Step>>,
    /// Whether any target is left (false: coverage is complete and the plant is left to itself).
    targets_left: bool,
    fresh: bool,
}

impl Steering {
    /// Values to be computed on first use.
    pub fn new() -> Self {
        Steering::default()
    }

    /// The targets or the controller's chances changed: recompute before the next use.
    pub fn invalidate(&mut self) {
        self.fresh = false;
    }

    /// Recomputes the values over `graph` unless they are fresh. `target(state, event)` says whether
    /// firing controllable `event` in closed-loop state number `state` takes a transition not taken yet;
    /// `chances(state, commands)` the chance of each of the enabled `commands` there.
    pub fn refresh(
        &mut self,
        graph: &Graph,
        controllable: &[bool],
        target: impl Fn(u32, u32) -> bool,
        chances: impl Fn(u32, &[u32]) -> Vec<f32>,
    ) {
        if self.fresh {
            return;
        }
        self.fresh = true;
        let n = graph.len();
        self.steps = (0..n as u32)
            .map(|s| {
                let commands: Vec<u32> =
                    graph.edges(s).map(|(e, _)| e).filter(|&e| controllable[e as usize]).collect();
                let mut chance = chances(s, &commands).into_iter();
                let floor = TARGET_FLOOR / commands.len().max(1) as f32;
                graph
                    .edges(s)
                    .map(|(e, _)| {
                        if !controllable[e as usize] {
                            return Step::default();
                        }
                        let (target, chance) = (target(s, e), chance.next().unwrap_or(0.0));
                        // A target the controller's round excludes now comes back when the round is over;
                        // without a chance it would look unreachable and the plant would stop steering.
                        Step {
                            command: true,
                            target,
                            chance: if target { chance.max(floor) } else { chance },
                        }
                    })
                    .collect()
            })
            .collect();
        self.targets_left = self.steps.iter().flatten().any(|step| step.target);
        if !self.targets_left {
            return;
        }
        // Only what can happen counts: the plant's events, and commands the controller may fire.
        let possible = |s: u32, k: usize| {
            let step = self.steps[s as usize][k];
            !step.command || step.chance > 0.0
        };
        let lower = graph.distances(|s, k| self.steps[s as usize][k].target && possible(s, k), possible);
        if self.values.len() != n {
            self.values = vec![0.0; n];
            self.after_command = vec![0.0; n];
        }
        for (s, &d) in lower.iter().enumerate() {
            for v in [&mut self.values[s], &mut self.after_command[s]] {
                *v = if d == u32::MAX { UNREACHABLE } else { v.max(d as f32) };
            }
        }
        // Gauss-Seidel in order of distance to a target: a state's successors on its way are updated
        // before it, so values travel outwards in few sweeps.
        let mut order: Vec<u32> = (0..n as u32).filter(|&s| lower[s as usize] != u32::MAX).collect();
        order.sort_by_key(|&s| lower[s as usize]);
        for _ in 0..MAX_SWEEPS {
            let mut change = 0.0f32;
            for &s in &order {
                let (wait, own) = self.options(graph, s);
                let best = wait.map_or(own, |w| w.min(own)).min(UNREACHABLE);
                let forced = wait.unwrap_or(own).min(UNREACHABLE);
                let s = s as usize;
                change =
                    change.max((best - self.values[s]).abs()).max((forced - self.after_command[s]).abs());
                self.values[s] = best;
                self.after_command[s] = forced;
            }
            if change < EPSILON {
                break;
            }
        }
    }

    /// In state `s`: the value of waiting for the controller (`None` when it has no command to choose)
    /// and the best value of the plant's own events.
    fn options(&self, graph: &Graph, s: u32) -> (Option<f32>, f32) {
        let (mut wait, mut total, mut own) = (0.0f32, 0.0f32, UNREACHABLE);
        for ((_, t), step) in graph.edges(s).zip(&self.steps[s as usize]) {
            if step.command {
                let after = if step.target { 0.0 } else { self.after_command[t as usize] };
                wait += step.chance * after;
                total += step.chance;
            } else {
                own = own.min(1.0 + self.values[t as usize]);
            }
        }
        ((total > 0.0).then(|| 1.0 + wait / total), own)
    }

    /// The plant's rank of taking its event to closed-loop state `next`: lower is better; `None` once no
    /// target is left (or `next` cannot reach one).
    pub fn rank_after(&self, next: u32) -> Option<u32> {
        let v = *self.values.get(next as usize)?;
        (self.targets_left && v < UNREACHABLE).then(|| (v * RANK_SCALE).round() as u32)
    }

    /// Who should move next in closed-loop state `s`.
    pub fn next_move(&self, graph: &Graph, s: u32) -> Move {
        if !self.targets_left || self.steps.len() != graph.len() {
            return Move::Plant;
        }
        match self.options(graph, s) {
            (Some(wait), own) if wait <= own => Move::Controller,
            (Some(_), _) => Move::PlantFirst,
            (None, _) => Move::Plant,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::automaton;
    use crate::model::{Composition, EventTable, Kind};

    /// A plant that, from its rest state 0, goes by the plant's own `left` to 1 or by `right` to 2; in
    /// 1 the controller can only `c1`, in 2 only `c2`, both back to 0. A supervisor watching both.
    fn fork() -> (Graph, Vec<bool>, EventTable) {
        let m = automaton(
            "M",
            Kind::Plant,
            3,
            &[0],
            &["c1", "c2"],
            &[(0, "left", 1), (0, "right", 2), (1, "c1", 0), (2, "c2", 0)],
        );
        let table = EventTable::build([&m]).unwrap();
        let closed = Composition::new(&[&m], &table).unwrap();
        let controllable = table.ids().map(|e| table.is_controllable(e)).collect();
        (Graph::explore(&closed, 100).unwrap(), controllable, table)
    }

    fn uniform(_: u32, commands: &[u32]) -> Vec<f32> {
        vec![1.0 / commands.len() as f32; commands.len()]
    }

    #[test]
    fn the_plant_heads_for_the_target_and_then_lets_the_controller_take_it() {
        let (g, controllable, t) = fork();
        let c1 = t.id("c1").unwrap().as_u32();
        let mut steering = Steering::new();
        steering.refresh(&g, &controllable, |_, e| e == c1, uniform);
        let after = |e: &str| g.next(0, t.id(e).unwrap()).unwrap();
        let (left, right) =
            (steering.rank_after(after("left")).unwrap(), steering.rank_after(after("right")).unwrap());
        assert!(left < right, "left leads to c1 at once ({left}), right only after a round ({right})");
        assert_eq!(steering.next_move(&g, 0), Move::Plant, "the controller has nothing to choose at rest");
        assert_eq!(steering.next_move(&g, after("left")), Move::Controller);

        // Once c1 is taken there is nothing to steer to: the plant is left to its own timing.
        steering.invalidate();
        steering.refresh(&g, &controllable, |_, _| false, uniform);
        assert_eq!(steering.rank_after(after("left")), None);
        assert_eq!(steering.next_move(&g, after("left")), Move::Plant);
    }

    #[test]
    fn a_command_the_controller_will_not_choose_is_not_waited_for() {
        // One state with two commands: `take` (the target) back to rest, `skip` to a state from which
        // the plant's `back` returns. With the chances the controller really has, the value follows them.
        let m = automaton(
            "M",
            Kind::Plant,
            2,
            &[0],
            &["take", "skip"],
            &[(0, "take", 0), (0, "skip", 1), (1, "back", 0)],
        );
        let table = EventTable::build([&m]).unwrap();
        let closed = Composition::new(&[&m], &table).unwrap();
        let controllable: Vec<bool> = table.ids().map(|e| table.is_controllable(e)).collect();
        let g = Graph::explore(&closed, 10).unwrap();
        let take = table.id("take").unwrap().as_u32();
        let value = |p_take: f32| {
            let mut s = Steering::new();
            s.refresh(
                &g,
                &controllable,
                |_, e| e == take,
                |_, commands: &[u32]| {
                    commands.iter().map(|&c| if c == take { p_take } else { 1.0 - p_take }).collect()
                },
            );
            s.values[0]
        };
        // With chance p per visit, each miss costs `skip` and `back`: 1 + 2(1-p)/p events.
        assert!((value(1.0) - 1.0).abs() < 0.05, "{}", value(1.0));
        assert!((value(0.5) - 3.0).abs() < 0.05, "{}", value(0.5));
        // A round that excludes the target still leaves it a floor (it comes back with the next round).
        assert!(value(0.0) < UNREACHABLE);
    }
}
