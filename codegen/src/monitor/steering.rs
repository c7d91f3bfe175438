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
//! of them. Who has the initiative matters: right after a command, a controller deciding freely with
//! another command enabled fires it at once, before the plant can answer; so a state has a second value,
//! reached by a command, in which only the controller moves while it can. A session in steps (the
//! firmware decides once per STEP, [`Steering::plant_answers_commands`]) gives the plant its turn after
//! every command, and the two values are one: against a controller that never runs out of commands the
//! other model would never let the plant move, and every target behind one of its events would look
//! unreachable.
//!
//! A local queue's choice depends on its history: a command already taken in the current round of its
//! choice site is not taken again before the round is over, so a plant that brings the closed loop to a
//! target along a path that takes the target's command elsewhere first would find it excluded every time.
//! The *focus* site — the choice site holding the most targets — therefore has its round in the state:
//! values are kept per (closed-loop state, round of the focus site), and firing a command there moves the
//! round as the firmware does. Other sites' chances are those of their current rounds (and a target they
//! exclude keeps a floor, for it comes back with the next round).
//!
//! A `local-queue` controller is deterministic given its cursors: a plant cursor that moves past the
//! plant of every command fired, and a cursor per choice site. The plant cursor is part of the state in
//! its stead ([`Steering::queue_at`]): values are kept per (closed-loop state, plant cursor), each
//! command is fired only at the cursors that pick it ([`Command::picked_at`]) and moves the cursor past
//! its plant. A model of a fixed round that forgot where the round stands would promise, after each
//! command, the target the round would take were it still where it was — and the plant, holding back
//! for that promise at every step, would never move.
//!
//! Value iteration from the breadth-first distance (a lower bound) converges to the values; after a
//! change it starts again from the previous ones.
//!
//! The plant asks two things: how good each of its events is ([`Steering::rank_after`]) and who should
//! move next ([`Steering::next_move`]): the controller (the plant holds its events back), or the plant —
//! before the controller decides, when the controller has a choice there ([`Move::PlantFirst`]: the plant
//! sends its events in one held burst), or simply because the controller has nothing to do.

use std::collections::BTreeMap;

use super::coverage::Graph;

/// Most sweeps of value iteration per refresh; values are used as a ranking, so near convergence is
/// enough.
const MAX_SWEEPS: usize = 400;
/// Largest change in a sweep (in events) at which the values count as converged.
const EPSILON: f32 = 0.01;
/// Value of a state from which no target can be reached.
const UNREACHABLE: f32 = 1.0e9;
/// Least chance given to a target command outside the focus site, as a share of a uniform choice among
/// the state's commands.
const TARGET_FLOOR: f32 = 0.5;
/// Most commands a focus site may offer (its rounds are the subsets: 2^6 values per state at most).
const MAX_FOCUS_EVENTS: usize = 6;
/// Fixed-point scale of [`Steering::rank_after`]: ranks in sixteenths of an event.
const RANK_SCALE: f32 = 16.0;

/// A choice site: a plant (member index) in one of its local states.
pub type Site = (usize, u32);

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

/// What the steering is told of one enabled command in one closed-loop state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Command {
    /// Firing it takes a transition not taken yet.
    pub target: bool,
    /// The chance the controller fires it there, as its current rounds stand.
    pub chance: f32,
    /// The choice site it is chosen at, when its plant's state is one (a local queue's round applies).
    pub site: Option<Site>,
    /// `local-queue` ([`Steering::queue_at`]): bit `c` set when the controller picks it with its plant
    /// cursor at `c`, the site cursors as they stand; `chance` is then not read.
    pub picked_at: u64,
    /// `local-queue`: the plant cursor after it (past its plant).
    pub next_cursor: u8,
}

/// A choice site's commands and where its round stands, as the monitor mirrors them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Round {
    /// The commands its plant offers there (a new round holds them all).
    pub offered: Vec<u32>,
    /// The commands of the current round not taken yet (empty: none, the next choice starts a round).
    pub left: Vec<u32>,
}

/// One transition out of a closed-loop state, as the steering sees it.
#[derive(Clone, Copy, Debug, Default)]
struct Step {
    /// A command (the controller's) rather than one of the plant's events.
    command: bool,
    /// A command that takes a transition not taken yet.
    target: bool,
    /// For a command outside the focus site, the chance the controller fires it there.
    chance: f32,
    /// For a command of the focus site, its bit in the site's rounds.
    bit: Option<u8>,
    /// `local-queue`: the plant cursors at which it is fired, and the cursor after it.
    picked_at: u64,
    next_cursor: u8,
}

/// The focus site's part of one state: its commands enabled there and their plant's share of the choice.
#[derive(Clone, Copy, Debug, Default)]
struct FocusHere {
    /// Bits of the focus site's commands enabled in the state (0: the site is not there).
    candidates: u64,
    /// The chance the controller picks the focus site's plant there.
    share: f32,
}

/// Expected events to the next new transition, per (closed-loop state, focus round); see the module
/// docs.
#[derive(Clone, Debug, Default)]
pub struct Steering {
    /// Per state × round, reached by one of the plant's events: the plant may move first.
    values: Vec<f32>,
    /// Per state × round, reached by a command: the controller moves again while it has a command.
    after_command: Vec<f32>,
    /// Per state, its outgoing transitions in the graph's order.
    steps: Vec<Vec<Step>>,
    /// Per state, the focus site's commands there.
    here: Vec<FocusHere>,
    /// The focus site and its offered commands (their order gives the round bits).
    focus: Option<(Site, Vec<u32>)>,
    /// Rounds per state (a power of two: all subsets of the focus site's commands; 1 without focus).
    rounds: usize,
    /// The focus site's round now.
    round: u64,
    /// Sites outside the focus that hold a target: a change of their round changes the values.
    target_sites: Vec<Site>,
    /// Whether any target is left (false: coverage is complete and the plant is left to itself).
    targets_left: bool,
    /// The plant answers every command before the controller decides again (a session in steps).
    answers: bool,
    /// `local-queue`: the number of plants (the values' cursors) and the plant cursor now.
    queue: Option<(usize, u64)>,
    fresh: bool,
}

impl Steering {
    /// Values to be computed on first use.
    pub fn new() -> Self {
        Steering { rounds: 1, ..Steering::default() }
    }

    /// Whether the plant gets its turn after every command (a session in steps) rather than the
    /// controller going on while it has commands; see the module docs.
    pub fn plant_answers_commands(&mut self, answers: bool) {
        self.answers = answers;
        self.fresh = false;
    }

    /// The controller is a `local-queue` over `plants` plants (at most 64) whose plant cursor is now at
    /// `cursor`: the cursor is part of the state (see the module docs). A moved cursor needs no
    /// recomputation.
    pub fn queue_at(&mut self, plants: usize, cursor: usize) {
        if self.queue.map(|(p, _)| p) != Some(plants) {
            self.fresh = false;
        }
        self.queue = Some((plants, cursor as u64));
        if self.rounds == plants {
            self.round = cursor as u64;
        }
    }

    /// The targets or the controller's chances changed: recompute before the next use.
    pub fn invalidate(&mut self) {
        self.fresh = false;
    }

    /// The round of `site` moved to `round`: the focus site's is part of the state; another site's
    /// matters only when it holds a target.
    pub fn round_moved(&mut self, site: Site, round: &Round) {
        match &self.focus {
            Some((focus, offered)) if *focus == site => self.round = mask(offered, &round.left),
            _ if self.target_sites.contains(&site) => self.fresh = false,
            _ => {}
        }
    }

    /// Recomputes the values over `graph` unless they are fresh. `describe(state, commands)` tells what
    /// each of the enabled `commands` of closed-loop state number `state` is; `round(site)` where a
    /// site's round stands.
    pub fn refresh(
        &mut self,
        graph: &Graph,
        controllable: &[bool],
        describe: impl Fn(u32, &[u32]) -> Vec<Command>,
        round: impl Fn(Site) -> Round,
    ) {
        if self.fresh {
            return;
        }
        self.fresh = true;
        let n = graph.len();
        let described: Vec<Vec<(u32, Command)>> = (0..n as u32)
            .map(|s| {
                let commands: Vec<u32> =
                    graph.edges(s).map(|(e, _)| e).filter(|&e| controllable[e as usize]).collect();
                commands.iter().copied().zip(describe(s, &commands)).collect()
            })
            .collect();
        let mut per_site: BTreeMap<Site, usize> = BTreeMap::new();
        for command in described.iter().flatten().map(|(_, c)| c).filter(|c| c.target) {
            if let Some(site) = command.site {
                *per_site.entry(site).or_default() += 1;
            }
        }
        self.targets_left = described.iter().flatten().any(|(_, c)| c.target);
        if !self.targets_left {
            return;
        }
        // The site holding the most targets (the first such in site order), if its rounds are few enough.
        let focus =
            per_site.iter().max_by_key(|&(site, k)| (*k, std::cmp::Reverse(*site))).map(|(&site, _)| site);
        let focus =
            focus.map(|site| (site, round(site))).filter(|(_, r)| r.offered.len() <= MAX_FOCUS_EVENTS);
        self.target_sites =
            per_site.keys().copied().filter(|&s| Some(s) != focus.as_ref().map(|f| f.0)).collect();
        self.round = focus.as_ref().map_or(0, |(_, r)| mask(&r.offered, &r.left));
        self.rounds = focus.as_ref().map_or(1, |(_, r)| 1 << r.offered.len());
        self.focus = focus.map(|(site, r)| (site, r.offered));
        if let Some((plants, cursor)) = self.queue {
            (self.round, self.rounds, self.focus) = (cursor, plants, None);
        }
        self.build_steps(graph, controllable, &described);
        self.iterate(graph);
    }

    /// The steps of every state, and the focus site's part of each.
    fn build_steps(&mut self, graph: &Graph, controllable: &[bool], described: &[Vec<(u32, Command)>]) {
        let n = graph.len();
        let (focus, offered) = match &self.focus {
            Some((site, offered)) => (Some(*site), offered.as_slice()),
            None => (None, &[][..]),
        };
        self.here = vec![FocusHere::default(); n];
        self.steps = (0..n as u32)
            .map(|s| {
                let mut commands = described[s as usize].iter();
                let floor = TARGET_FLOOR / described[s as usize].len().max(1) as f32;
                let mut here = FocusHere::default();
                let steps = graph
                    .edges(s)
                    .map(|(e, _)| {
                        if !controllable[e as usize] {
                            return Step::default();
                        }
                        let Some(&(_, c)) = commands.next() else { return Step::default() };
                        let bit = (c.site.is_some() && c.site == focus)
                            .then(|| offered.iter().position(|&o| o == e))
                            .flatten()
                            .map(|b| b as u8);
                        if let Some(b) = bit {
                            here.candidates |= 1 << b;
                            here.share += c.chance;
                        }
                        // A command the controller's round excludes now comes back when the round is over
                        // (the values are not recomputed when a round outside the focus moves unless it
                        // holds a target): a target keeps a floor, and so does any other command a site's
                        // round excludes, or every target behind it would look unreachable and the plant
                        // would stop steering. A command outside every site with no chance is never
                        // chosen, not even a target: under `first`, a command with a lower one enabled
                        // beside it never fires there, and a floor would steer the plant to where the
                        // target never comes.
                        let chance = match (bit, c.target) {
                            (None, true) if c.site.is_some() || c.chance > 0.0 => c.chance.max(floor),
                            (None, false) if c.chance == 0.0 && c.site.is_some() => floor,
                            _ => c.chance,
                        };
                        let (picked_at, next_cursor) = (c.picked_at, c.next_cursor);
                        Step { command: true, target: c.target, chance, bit, picked_at, next_cursor }
                    })
                    .collect();
                // The focus plant is picked with the chance its commands have together (at least one
                // of them is in its pool, whatever the round).
                if here.candidates != 0 && here.share == 0.0 {
                    here.share = floor;
                }
                self.here[s as usize] = here;
                steps
            })
            .collect();
    }

    /// Value iteration over (state, round), from the distance to a target as a lower bound.
    fn iterate(&mut self, graph: &Graph) {
        let n = graph.len();
        let m = self.rounds;
        // Only what can happen counts: the plant's events, and commands the controller may fire.
        let possible = |s: u32, k: usize| {
            let step = self.steps[s as usize][k];
            !step.command || step.chance > 0.0 || step.bit.is_some() || step.picked_at != 0
        };
        let lower = graph.distances(|s, k| self.steps[s as usize][k].target && possible(s, k), possible);
        if self.values.len() != n * m {
            self.values = vec![0.0; n * m];
            self.after_command = vec![0.0; n * m];
        }
        for (s, &d) in lower.iter().enumerate() {
            for i in s * m..(s + 1) * m {
                for v in [&mut self.values[i], &mut self.after_command[i]] {
                    *v = if d == u32::MAX { UNREACHABLE } else { v.max(d as f32) };
                }
            }
        }
        // Gauss-Seidel in order of distance to a target: a state's successors on its way are updated
        // before it, so values travel outwards in few sweeps.
        let mut order: Vec<u32> = (0..n as u32).filter(|&s| lower[s as usize] != u32::MAX).collect();
        order.sort_by_key(|&s| lower[s as usize]);
        for _ in 0..MAX_SWEEPS {
            let mut change = 0.0f32;
            for &s in &order {
                for r in 0..m as u64 {
                    let (wait, own) = self.options(graph, s, r);
                    let best = wait.map_or(own, |w| w.min(own)).min(UNREACHABLE);
                    let forced = if self.answers { best } else { wait.unwrap_or(own).min(UNREACHABLE) };
                    let i = s as usize * m + r as usize;
                    change =
                        change.max((best - self.values[i]).abs()).max((forced - self.after_command[i]).abs());
                    self.values[i] = best;
                    self.after_command[i] = forced;
                }
            }
            if change < EPSILON {
                break;
            }
        }
    }

    /// In state `s` with the focus round `r`: the value of waiting for the controller (`None` when it
    /// has no command to choose) and the best value of the plant's own events.
    fn options(&self, graph: &Graph, s: u32, r: u64) -> (Option<f32>, f32) {
        let m = self.rounds;
        let here = self.here[s as usize];
        // The focus plant's pool as the firmware draws it: its enabled commands still in the round, or
        // all of them when none is (a new round starts, holding every offered command).
        let in_round = here.candidates & r;
        let (pool, next_round) = if in_round == 0 { (here.candidates, m as u64 - 1) } else { (in_round, r) };
        let per = if pool == 0 { 0.0 } else { here.share / pool.count_ones() as f32 };
        let (mut wait, mut total, mut own) = (0.0f32, 0.0f32, UNREACHABLE);
        for ((_, t), step) in graph.edges(s).zip(&self.steps[s as usize]) {
            if step.command {
                let (chance, after_round) = match step.bit {
                    _ if self.queue.is_some() => {
                        (f32::from(u8::from(step.picked_at >> r & 1 == 1)), u64::from(step.next_cursor))
                    }
                    Some(b) if pool & (1 << b) != 0 => (per, next_round & !(1 << b)),
                    Some(_) => (0.0, r),
                    None => (step.chance, r),
                };
                if chance > 0.0 {
                    let after = if step.target {
                        0.0
                    } else {
                        self.after_command[t as usize * m + after_round as usize]
                    };
                    wait += chance * after;
                    total += chance;
                }
            } else {
                own = own.min(1.0 + self.values[t as usize * m + r as usize]);
            }
        }
        ((total > 0.0).then(|| 1.0 + wait / total), own)
    }

    /// The plant's rank of taking its event to closed-loop state `next`: lower is better; `None` once no
    /// target is left (or `next` cannot reach one).
    pub fn rank_after(&self, next: u32) -> Option<u32> {
        let v = *self.values.get(next as usize * self.rounds + self.round as usize)?;
        (self.targets_left && v < UNREACHABLE).then(|| (v * RANK_SCALE).round() as u32)
    }

    /// Who should move next in closed-loop state `s`.
    pub fn next_move(&self, graph: &Graph, s: u32) -> Move {
        if !self.targets_left || self.steps.len() != graph.len() {
            return Move::Plant;
        }
        match self.options(graph, s, self.round) {
            // Where the controller's choice leads to no target, holding the plant back would only starve it.
            (Some(wait), own) if wait <= own && wait < UNREACHABLE => Move::Controller,
            (Some(_), _) => Move::PlantFirst,
            (None, _) => Move::Plant,
        }
    }
}

/// The bits of `left` among `offered`.
fn mask(offered: &[u32], left: &[u32]) -> u64 {
    offered.iter().enumerate().filter(|(_, e)| left.contains(e)).fold(0, |m, (b, _)| m | 1 << b)
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

    /// Refreshes `steering` on `g` with the targets `target` and the controller's chances `chance`, no
    /// site having rounds.
    fn refresh(
        steering: &mut Steering,
        g: &Graph,
        controllable: &[bool],
        target: impl Fn(u32) -> bool,
        chance: impl Fn(u32, &[u32]) -> f32,
    ) {
        steering.refresh(
            g,
            controllable,
            |_, commands| {
                commands
                    .iter()
                    .map(|&e| Command {
                        target: target(e),
                        chance: chance(e, commands),
                        ..Command::default()
                    })
                    .collect()
            },
            |_| Round::default(),
        );
    }

    fn uniform(_: u32, commands: &[u32]) -> f32 {
        1.0 / commands.len() as f32
    }

    #[test]
    fn the_plant_heads_for_the_target_and_then_lets_the_controller_take_it() {
        let (g, controllable, t) = fork();
        let c1 = t.id("c1").unwrap().as_u32();
        let mut steering = Steering::new();
        refresh(&mut steering, &g, &controllable, |e| e == c1, uniform);
        let after = |e: &str| g.next(0, t.id(e).unwrap()).unwrap();
        let (left, right) =
            (steering.rank_after(after("left")).unwrap(), steering.rank_after(after("right")).unwrap());
        assert!(left < right, "left leads to c1 at once ({left}), right only after a round ({right})");
        assert_eq!(steering.next_move(&g, 0), Move::Plant, "the controller has nothing to choose at rest");
        assert_eq!(steering.next_move(&g, after("left")), Move::Controller);

        // Once c1 is taken there is nothing to steer to: the plant is left to its own timing.
        steering.invalidate();
        refresh(&mut steering, &g, &controllable, |_| false, uniform);
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
            refresh(
                &mut s,
                &g,
                &controllable,
                |e| e == take,
                |c, _| if c == take { p_take } else { 1.0 - p_take },
            );
            s.values[0]
        };
        // With chance p per visit, each miss costs `skip` and `back`: 1 + 2(1-p)/p events.
        assert!((value(1.0) - 1.0).abs() < 0.05, "{}", value(1.0));
        assert!((value(0.5) - 3.0).abs() < 0.05, "{}", value(0.5));
        // Outside every site, no chance is never (`first`, with a lower id enabled beside the target).
        assert_eq!(value(0.0), UNREACHABLE);
        // At a site, a round that excludes the target still leaves it a floor (it comes back with the
        // next round).
        let mut s = Steering::new();
        let excluded = |e: u32| Command {
            target: e == take,
            chance: f32::from(e != take),
            site: Some((0, 0)),
            ..Command::default()
        };
        s.refresh(
            &g,
            &controllable,
            |_, commands| commands.iter().map(|&e| excluded(e)).collect(),
            |_| Round::default(),
        );
        assert!(s.values[0] < UNREACHABLE, "{}", s.values[0]);
    }

    #[test]
    fn in_steps_the_plant_answers_a_controller_that_never_runs_out_of_commands() {
        // A piston the controller switches at will: `on` at rest, `off` while pushed; only the plant's
        // `arrive`, while pushed, brings it to the front, where `back` is the target. A controller that
        // decides again at once after `on` fires `off` before `arrive` can get in: the target is out of
        // reach. In steps the plant answers `on` with `arrive`, and `back` follows.
        let m = automaton(
            "Piston",
            Kind::Plant,
            3,
            &[0],
            &["on", "off", "back"],
            &[(0, "on", 1), (1, "off", 0), (1, "arrive", 2), (2, "back", 0)],
        );
        let table = EventTable::build([&m]).unwrap();
        let closed = Composition::new(&[&m], &table).unwrap();
        let controllable: Vec<bool> = table.ids().map(|e| table.is_controllable(e)).collect();
        let g = Graph::explore(&closed, 10).unwrap();
        let back = table.id("back").unwrap().as_u32();
        let pushed = g.next(0, table.id("on").unwrap()).unwrap();
        for answers in [false, true] {
            let mut steering = Steering::new();
            steering.plant_answers_commands(answers);
            refresh(&mut steering, &g, &controllable, |e| e == back, uniform);
            let rest = steering.after_command[0];
            if answers {
                assert_eq!(steering.next_move(&g, pushed), Move::PlantFirst, "arrive beats switching off");
                assert_eq!(steering.next_move(&g, 0), Move::Controller, "at rest only the controller moves");
                // on, arrive, back: 3 events from rest.
                assert!((rest - 3.0).abs() < 0.05, "{rest}");
            } else {
                // Value iteration climbs without bound (on, off, on, off …), stopped by the sweep limit.
                assert!(rest > 100.0, "{rest}");
            }
        }
    }

    #[test]
    fn the_focus_sites_round_is_part_of_the_state() {
        // M offers a and b at rest; the supervisor allows only b first, then a or b. The target is b in
        // the supervisor's second state. A local queue that took b first has only a left in its round
        // there, takes a, then b again at the start: b in the second state never comes — unless the
        // round still holds it when the loop gets there.
        let m =
            automaton("M", Kind::Plant, 2, &[0], &["a", "b"], &[(0, "a", 1), (0, "b", 1), (1, "done", 0)]);
        let sup =
            automaton("S", Kind::Supervisor, 2, &[0], &["a", "b"], &[(0, "b", 1), (1, "a", 0), (1, "b", 0)]);
        let table = EventTable::build([&m, &sup]).unwrap();
        let closed = Composition::new(&[&m, &sup], &table).unwrap();
        let controllable: Vec<bool> = table.ids().map(|e| table.is_controllable(e)).collect();
        let g = Graph::explore(&closed, 10).unwrap();
        let (a, b) = (table.id("a").unwrap().as_u32(), table.id("b").unwrap().as_u32());
        let choice_state = g.id(&[0, 1]).unwrap();
        let steer = |left: Vec<u32>| {
            let mut steering = Steering::new();
            steering.refresh(
                &g,
                &controllable,
                |s, commands| {
                    commands
                        .iter()
                        .map(|&e| Command {
                            target: e == b && g.tuple(s)[1] == 1,
                            chance: 1.0 / commands.len() as f32,
                            site: Some((0, 0)),
                            ..Command::default()
                        })
                        .collect()
                },
                |_| Round { offered: vec![a, b], left: left.clone() },
            );
            steering
        };
        let full = steer(vec![a, b]);
        let only_a = steer(vec![a]);
        let (hopeful, hopeless) = (full.rank_after(choice_state).unwrap(), only_a.rank_after(choice_state));
        // b in the round: half a chance per visit, a miss costs a, done, b, done: 1 + (3 + x)/2 = x = 5.
        assert!((hopeful as f32 / 16.0 - 5.0).abs() < 0.1, "{hopeful}");
        assert!(hopeless.is_none_or(|r| r > 16 * 100), "b can never come back in step: {hopeless:?}");
        // The round moving is seen without recomputing.
        let mut moved = steer(vec![a]);
        moved.round_moved((0, 0), &Round { offered: vec![a, b], left: vec![a, b] });
        assert_eq!(moved.rank_after(choice_state), Some(hopeful));
    }
}
