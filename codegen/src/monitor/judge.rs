//! The monitor: every event the link carries, judged against plants ‖ supervisors.

use std::collections::{BTreeSet, VecDeque};

use super::choice_model::{ChoiceModel, Choices};
use super::coverage::{Edge, Graph, Taken};
use super::report::TimeoutFigures;
use super::report::{CoverageLine, FirmwareCounters, Report};
use super::steering::{Command, Move, Steering};
use super::timers::{Timers, Timing};
use crate::model::{Automaton, Composition, EventId, EventTable, ModelError};

/// Most firmware views kept at once; the ones that have seen the most events win.
const MAX_VIEWS: usize = 4096;
/// Most violation messages kept for the report.
const MAX_FINDINGS: usize = 10;
/// Largest closed loop explored for the coverage denominator.
const EXPLORATION_LIMIT: usize = 2_000_000;

/// What the monitor made of one event.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Allowed; plant and controller agree.
    Ok,
    /// A command the controller decided before it saw the plant's latest events (inexact
    /// synchronisation). `resolved`: the monitor took it in the controller's order and the run goes on
    /// (the plant must be put in [`Monitor::plant_state`]); otherwise the two sides cannot agree any more
    /// and the link must be reset.
    Desync {
        /// Whether the monitor could reorder the events consistently.
        resolved: bool,
    },
    /// A safety violation (message in the report); the link must be reset.
    Violation,
}

/// A possible state of the controller's knowledge: the closed-loop state after all of its commands and
/// the first `seen` uncontrollable events the plant sent.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct View {
    seen: u64,
    state: Vec<u32>,
}

/// Judges a closed-loop run event by event and keeps the figures of its [`Report`].
///
/// The monitor keeps the *physical* closed-loop state, in the order the host saw events (an uncontrollable
/// event happens when the plant sends it, a command when it arrives), and the set of states the
/// controller may be in: it may not have read the plant's latest events when it decided. An event sent
/// more than `window_us` before a command is taken as read.
///
/// - A command no controller view allows is a **violation** (the supervisors disable it or the plant
///   cannot take it, whatever the controller knew), as is an uncontrollable event the supervisors refuse.
/// - A command some view allows but the physical state does not is a **desynchronisation**: it was
///   decided on stale information.
#[derive(Clone, Debug)]
pub struct Monitor {
    closed: Composition,
    plants: usize,
    controllable: Vec<bool>,
    names: Vec<String>,
    physical: Vec<u32>,
    views: BTreeSet<View>,
    /// Uncontrollable events sent and maybe not yet read by the controller, with their send times;
    /// `unread[0]` is event number `first_unread`.
    unread: VecDeque<(EventId, u64)>,
    first_unread: u64,
    sent: u64,
    window_us: u64,
    graph: Option<Graph>,
    reachable: Option<Vec<BTreeSet<Edge>>>,
    taken: Taken,
    /// Where the plant should lead the closed loop next.
    steering: Steering,
    /// The controller's choices as far as the monitor can tell.
    choices: Choices,
    report: Report,
    gap: u64,
    /// The run's timers (none unless [`Monitor::set_timers`]).
    timers: Timers,
    /// The virtual time in ms, as the session last set it ([`Monitor::clock`]).
    now_ms: u64,
}

impl Monitor {
    /// A monitor of `plants` ‖ `supervisors` over the numbering of `table`, in the initial state.
    pub fn new(
        plants: &[&Automaton],
        supervisors: &[&Automaton],
        table: &EventTable,
        window_us: u64,
    ) -> Result<Self, ModelError> {
        let all: Vec<&Automaton> = plants.iter().chain(supervisors).copied().collect();
        let closed = Composition::new(&all, table)?;
        let controllable: Vec<bool> = table.ids().map(|e| table.is_controllable(e)).collect();
        let sups = plants.len()..all.len();
        let graph = Graph::explore(&closed, EXPLORATION_LIMIT).ok();
        let reachable =
            graph.as_ref().map(|g| g.controllable_edges(&closed, sups.clone(), &controllable, |_, _| true));
        let physical = closed.initial();
        let choices = Choices::new(ChoiceModel::Uniform, &closed, plants.len(), &controllable);
        let mut report = Report {
            coverage: supervisors
                .iter()
                .enumerate()
                .map(|(k, s)| CoverageLine {
                    supervisor: s.name.clone(),
                    taken: 0,
                    reachable: reachable.as_ref().map(|r| r[k].len()),
                })
                .collect(),
            ..Report::default()
        };
        report.marked_at_end = closed.is_marked(&physical);
        Ok(Monitor {
            views: BTreeSet::from([View { seen: 0, state: physical.clone() }]),
            physical,
            plants: plants.len(),
            names: table.ids().map(|e| table.name(e).to_owned()).collect(),
            controllable,
            unread: VecDeque::new(),
            first_unread: 0,
            sent: 0,
            window_us,
            graph,
            reachable,
            taken: Taken::new(supervisors.len()),
            steering: Steering::new(),
            choices,
            report,
            gap: 0,
            closed,
            timers: Timers::default(),
            now_ms: 0,
        })
    }

    /// The physical state of the plant subsystems (the first members of the closed loop).
    pub fn plant_state(&self) -> &[u32] {
        &self.physical[..self.plants]
    }

    /// The figures so far.
    pub fn report(&self) -> &Report {
        &self.report
    }

    /// Mutable figures, for the session to add what only it knows (time, link counters).
    pub fn report_mut(&mut self) -> &mut Report {
        &mut self.report
    }

    /// The plant sent uncontrollable `event` at `t_us`.
    pub fn uncontrollable(&mut self, event: EventId, t_us: u64) -> Verdict {
        self.report.events += 1;
        self.report.trace.push(event.index() as u8);
        self.report.uncontrollable += 1;
        if !self.closed.step(&mut self.physical, event) {
            let refusers = self.closed.refusers(&self.physical, event).join(", ");
            let name = self.name(event);
            return self.violation(format!("uncontrollable '{name}' refused by {refusers}"));
        }
        self.unread.push_back((event, t_us));
        self.sent += 1;
        self.timers.take(event, self.now_ms);
        self.after_event();
        Verdict::Ok
    }

    /// The run's timers: their timeouts are the target's events, judged by [`Monitor::timeout`] against
    /// deadlines in the virtual time the session keeps ([`Monitor::clock`]).
    pub fn set_timers(&mut self, timers: Timers) {
        self.report.timeouts = (!timers.is_empty())
            .then(|| TimeoutFigures { slack_ms: timers.slack_ms(), ..Default::default() });
        self.timers = timers;
    }

    /// The run's timers.
    pub fn timers(&self) -> &Timers {
        &self.timers
    }

    /// Virtual time is now `now_ms`: the time starts and stops are taken at, and timeouts judged at.
    pub fn clock(&mut self, now_ms: u64) {
        self.now_ms = now_ms;
    }

    /// The target raised timeout `event` at the current virtual time, having taken it as its input (so
    /// every later command was decided on it; `t_us` is the link time of the commands of the round): a
    /// violation when it comes before its timer's deadline or with the timer not running
    /// (`timeout_early`), or after the deadline plus the slack (`timeout_late`); otherwise it is taken
    /// as the uncontrollable event it is, judged by the supervisors as the plant's are.
    pub fn timeout(&mut self, event: EventId, t_us: u64) -> Verdict {
        self.report.events += 1;
        self.report.trace.push(event.index() as u8);
        let timing = self.timers.timeout(event, self.now_ms);
        let figures = self.report.timeouts.get_or_insert_with(TimeoutFigures::default);
        let kind = match timing {
            Timing::OnTime => {
                figures.on_time += 1;
                None
            }
            Timing::Early => {
                figures.early += 1;
                Some("timeout_early: before its timer's deadline, or with the timer not running")
            }
            Timing::Late => {
                figures.late += 1;
                Some("timeout_late: after its timer's deadline and slack")
            }
        };
        let name = self.name(event).to_owned();
        if let Some(kind) = kind {
            return self.violation(format!("'{name}' at {} ms: {kind}", self.now_ms));
        }
        if !self.closed.step(&mut self.physical, event) {
            let refusers = self.closed.refusers(&self.physical, event).join(", ");
            return self.violation(format!("timeout '{name}' refused by {refusers}"));
        }
        // The target took it before anything it decided after: read at once by every view.
        self.unread.push_back((event, t_us.saturating_sub(self.window_us)));
        self.sent += 1;
        self.after_event();
        Verdict::Ok
    }

    /// Judges the timers still running once the target has had every millisecond up to the current
    /// virtual time: each one past its deadline plus the slack is a missing timeout (`timeout_missing`),
    /// a violation.
    pub fn missing_timeouts(&mut self) -> Verdict {
        let missing = self.timers.missing(self.now_ms);
        if missing.is_empty() {
            return Verdict::Ok;
        }
        for e in missing {
            if let Some(figures) = self.report.timeouts.as_mut() {
                figures.missing += 1;
            }
            let name = self.name(e).to_owned();
            self.violation(format!(
                "'{name}' at {} ms: timeout_missing: its timer ran past its deadline and slack",
                self.now_ms
            ));
        }
        Verdict::Violation
    }

    /// The controller sent command byte `event` at `t_us`.
    pub fn command(&mut self, event: EventId, t_us: u64) -> Verdict {
        self.report.events += 1;
        self.report.trace.push(event.index() as u8);
        self.report.commands += 1;
        if !self.controllable.get(event.index()).copied().unwrap_or(false) {
            let what = self.names.get(event.index()).map_or("an unknown event", |_| "uncontrollable");
            return self.violation(format!("command #{event} is {what}"));
        }
        let views = self.views_after(event, t_us);
        if views.is_empty() {
            let refusers = self.closed.refusers(&self.physical, event).join(", ");
            let name = self.name(event);
            return self.violation(format!("command '{name}' disabled by {refusers}"));
        }
        let verdict = if self.closed.allows(&self.physical, event) {
            let enabled: Vec<u32> = self
                .closed
                .enabled(&self.physical)
                .into_iter()
                .map(EventId::as_u32)
                .filter(|&e| self.controllable[e as usize])
                .collect();
            if let Some(site) = self.choices.fired(&self.closed, &self.physical, &enabled, event.as_u32()) {
                match self.choices.queue() {
                    // A local queue's site cursor moved: what the site picks changed everywhere.
                    Some(_) => self.steering.invalidate(),
                    None => self.steering.round_moved(site, &self.choices.round(&self.closed, site)),
                }
            }
            self.queue_moved();
            if self.taken.record(&self.closed, self.plants, &self.physical, event) {
                self.steering.invalidate();
            }
            self.closed.step(&mut self.physical, event);
            self.views = views;
            self.timers.take(event, self.now_ms);
            Verdict::Ok
        } else {
            self.report.desyncs += 1;
            // Take the command in the controller's order: before the events it had not read. Which of
            // the views it decided in is unknown, so all of them stay candidates.
            let reordered = views.iter().rev().find_map(|v| {
                let mut s = v.state.clone();
                self.unread_from(v.seen).all(|u| self.closed.step(&mut s, u)).then_some((v, s))
            });
            match reordered {
                Some((view, state)) => {
                    // The command's transition was taken too, in the state the controller decided in.
                    if let Some(before) = self.state_before(view, event) {
                        if self.taken.record(&self.closed, self.plants, &before, event) {
                            self.steering.invalidate();
                        }
                    }
                    self.physical = state;
                    self.views = views;
                    self.timers.take(event, self.now_ms);
                    Verdict::Desync { resolved: true }
                }
                None => return Verdict::Desync { resolved: false },
            }
        };
        self.forget_read();
        self.after_event();
        verdict
    }

    /// How good the plant's `event` is now for reaching a controllable supervisor transition the run has
    /// not taken yet: the expected events from the state it leads to (in sixteenths; lower is better,
    /// see `Steering` in `steering.rs`); `None` when no such transition is left (or the closed loop was too large to
    /// explore). The plant uses it to steer towards what the run has not covered.
    pub fn rank_after(&mut self, event: EventId) -> Option<u32> {
        self.refresh_steering();
        let graph = self.graph.as_ref()?;
        let next = graph.next(graph.id(&self.physical)?, event)?;
        self.steering.rank_after(next)
    }

    /// Whether plants ‖ supervisors enable a command in the physical state: a controller in step with
    /// the monitor, having read every event, has one to fire (the session tells a blocked loop from a
    /// slow controller by it).
    pub fn commands_enabled(&self) -> bool {
        let allows = |e: usize| self.closed.allows(&self.physical, EventId::from_u32(e as u32));
        self.controllable.iter().enumerate().any(|(e, &c)| c && allows(e))
    }

    /// Whether the monitor is steering: it could explore the closed loop and some reachable transition
    /// is not taken yet.
    pub fn is_steering(&self) -> bool {
        self.graph.is_some() && !self.report.full_coverage()
    }

    /// Who should move next from the current state to reach a transition not taken yet: the controller
    /// (the plant holds its next event back), or the plant (see [`Move`]).
    pub fn next_move(&mut self) -> Move {
        self.refresh_steering();
        let Some(graph) = self.graph.as_ref() else { return Move::Plant };
        graph.id(&self.physical).map_or(Move::Plant, |s| self.steering.next_move(graph, s))
    }

    /// Tells the steering where a local queue's plant cursor stands, if the controller has one.
    fn queue_moved(&mut self) {
        if let Some((plants, cursor)) = self.choices.queue().filter(|&(plants, _)| plants <= 64) {
            self.steering.queue_at(plants, cursor);
        }
    }

    fn refresh_steering(&mut self) {
        let Some(graph) = self.graph.as_ref() else { return };
        let (closed, taken, plants, choices) = (&self.closed, &self.taken, self.plants, &self.choices);
        self.steering.refresh(
            graph,
            &self.controllable,
            |s, commands| {
                let state = graph.tuple(s);
                let chances = choices.chances(closed, &state, commands);
                // A local queue: which command each plant cursor picks here, and the cursor after it.
                let mut picked = vec![(0u64, 0u8); commands.len()];
                if let Some((n, _)) = choices.queue().filter(|&(n, _)| n <= 64) {
                    for cursor in 0..n {
                        let Some((e, next)) = choices.queued(closed, &state, commands, cursor) else {
                            continue;
                        };
                        if let Some(k) = commands.iter().position(|&c| c == e) {
                            picked[k] = (picked[k].0 | 1 << cursor, next as u8);
                        }
                    }
                }
                commands
                    .iter()
                    .zip(chances)
                    .zip(picked)
                    .map(|((&e, chance), (picked_at, next_cursor))| Command {
                        target: (plants..closed.len()).any(|i| {
                            closed.has_event(i, EventId::from_u32(e))
                                && !taken.of(i - plants).contains(&(state[i], e))
                        }),
                        chance,
                        site: choices.site(closed, &state, e),
                        picked_at,
                        next_cursor,
                    })
                    .collect()
            },
            |site| choices.round(closed, site),
        );
    }

    /// Models the controller's choice policy for the steering and for coverage (uniform until told):
    /// the transitions to cover are those the policy can take ([`ChoiceModel::fires`]).
    pub fn model_choices(&mut self, model: ChoiceModel) {
        self.choices = Choices::new(model, &self.closed, self.plants, &self.controllable);
        self.queue_moved();
        self.reachable = self.graph.as_ref().map(|g| {
            g.controllable_edges(&self.closed, self.plants..self.closed.len(), &self.controllable, |on, e| {
                model.fires(on, e)
            })
        });
        if let Some(reachable) = &self.reachable {
            for (line, edges) in self.report.coverage.iter_mut().zip(reachable) {
                line.reachable = Some(edges.len());
            }
        }
        self.steering.invalidate();
    }

    /// Tells the steering whether the plant answers every command before the controller decides again
    /// (a session in steps, [`SessionConfig::step`](crate::closed_loop::SessionConfig::step)) or the
    /// controller goes on while it has commands (the firmware deciding freely).
    pub fn plant_answers_commands(&mut self, answers: bool) {
        self.steering.plant_answers_commands(answers);
    }

    /// The link was reset: plant, controller and monitor are back in the initial state.
    pub fn reset(&mut self) {
        self.choices.reset();
        self.steering.invalidate();
        self.queue_moved();
        self.physical = self.closed.initial();
        self.views = BTreeSet::from([View { seen: self.sent, state: self.physical.clone() }]);
        self.unread.clear();
        self.first_unread = self.sent;
        self.timers.reset();
    }

    /// The firmware reported a fault and went to its safe state.
    pub fn firmware_safe(&mut self) {
        self.push_finding("firmware entered its safe state".to_owned());
        self.report.violations += 1;
    }

    /// Adds the firmware's counters since its last reset to the run's totals.
    pub fn firmware_counters(&mut self, c: FirmwareCounters) {
        self.report.firmware.add(c);
    }

    /// The controller views after command `event`: every view, moved on by any number of the events it
    /// may have read meanwhile (at least those older than the window), that allows `event`, then takes it.
    fn views_after(&self, event: EventId, t_us: u64) -> BTreeSet<View> {
        let must_read = self.first_unread
            + self.unread.iter().take_while(|&&(_, t)| t.saturating_add(self.window_us) <= t_us).count()
                as u64;
        let mut out = BTreeSet::new();
        for v in &self.views {
            let mut state = v.state.clone();
            let mut seen = v.seen;
            let mut pending = self.unread_from(seen);
            let mut alive = true;
            while seen < must_read && alive {
                alive = pending.next().is_some_and(|u| self.closed.step(&mut state, u));
                seen += 1;
            }
            while alive {
                if self.closed.allows(&state, event) {
                    let mut next = state.clone();
                    self.closed.step(&mut next, event);
                    out.insert(View { seen, state: next });
                }
                alive = pending.next().is_some_and(|u| self.closed.step(&mut state, u));
                seen += 1;
            }
        }
        while out.len() > MAX_VIEWS {
            out.pop_first();
        }
        out
    }

    /// A closed-loop state the controller can have been in when it fired `event` and reached `after`:
    /// one of the views before the command, with the events it had read by then.
    fn state_before(&self, after: &View, event: EventId) -> Option<Vec<u32>> {
        self.views.iter().filter(|w| w.seen <= after.seen).find_map(|w| {
            let mut state = w.state.clone();
            let read = usize::try_from(after.seen - w.seen).ok()?;
            let replayed = self.unread_from(w.seen).take(read).all(|u| self.closed.step(&mut state, u));
            let mut next = state.clone();
            (replayed && self.closed.step(&mut next, event) && next == after.state).then_some(state)
        })
    }

    /// The uncontrollable events sent from number `seen` on.
    fn unread_from(&self, seen: u64) -> impl Iterator<Item = EventId> + '_ {
        let skip = seen.saturating_sub(self.first_unread) as usize;
        self.unread.iter().skip(skip).map(|&(e, _)| e)
    }

    /// Drops the unread events every view has read.
    fn forget_read(&mut self) {
        let oldest = self.views.iter().map(|v| v.seen).min().unwrap_or(self.sent);
        while self.first_unread < oldest && self.unread.pop_front().is_some() {
            self.first_unread += 1;
        }
    }

    fn after_event(&mut self) {
        let marked = self.closed.is_marked(&self.physical);
        if marked {
            self.report.marked_visits += 1;
            self.gap = 0;
        } else {
            self.gap += 1;
            self.report.longest_marked_gap = self.report.longest_marked_gap.max(self.gap);
        }
        self.report.events_since_marked = self.gap;
        self.report.marked_at_end = marked;
        for (k, line) in self.report.coverage.iter_mut().enumerate() {
            line.taken = self.taken.of(k).len();
        }
        if self.report.full_coverage_at.is_none() && self.report.full_coverage() {
            self.report.full_coverage_at = Some(self.report.events);
        }
    }

    fn violation(&mut self, message: String) -> Verdict {
        self.report.violations += 1;
        self.push_finding(message);
        Verdict::Violation
    }

    fn push_finding(&mut self, message: String) {
        if self.report.findings.len() < MAX_FINDINGS {
            self.report.findings.push(format!("event {}: {message}", self.report.events));
        }
    }

    fn name(&self, event: EventId) -> &str {
        self.names.get(event.index()).map_or("?", String::as_str)
    }

    /// Lists the reachable controllable supervisor transitions not taken (the first few) in the report;
    /// call once the run is over.
    pub fn list_uncovered(&mut self) {
        let Some(reachable) = &self.reachable else { return };
        let mut out = Vec::new();
        for (k, edges) in reachable.iter().enumerate() {
            let sup = self.plants + k;
            for &(s, e) in edges.difference(self.taken.of(k)).take(MAX_FINDINGS.saturating_sub(out.len())) {
                let state = self.closed.state_name(sup, s);
                out.push(format!("{}: {state} --{}-->", self.closed.name(sup), self.names[e as usize]));
            }
        }
        self.report.uncovered = out;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::{automaton, machine};
    use crate::model::Kind;

    /// Two machines and a one-slot buffer between them (the textbook small factory, no breakdowns):
    /// the supervisor lets M1 start only when the buffer is empty and M2 only when it is full.
    fn factory() -> (Vec<Automaton>, Automaton, EventTable) {
        let m1 = machine("M1", "a1", "b1");
        let m2 = machine("M2", "a2", "b2");
        let sup = automaton(
            "S",
            Kind::Supervisor,
            2,
            &[0],
            &["a1", "a2"],
            &[(0, "a1", 0), (0, "b1", 1), (1, "a2", 0)],
        );
        let table = EventTable::build([&m1, &m2, &sup]).unwrap();
        (vec![m1, m2], sup, table)
    }

    fn monitor(window_us: u64) -> (Monitor, EventTable) {
        let (plants, sup, table) = factory();
        let plants: Vec<&Automaton> = plants.iter().collect();
        (Monitor::new(&plants, &[&sup], &table, window_us).unwrap(), table)
    }

    #[test]
    fn a_correct_run_is_clean_and_covers_everything() {
        let (mut m, t) = monitor(1000);
        let id = |n| t.id(n).unwrap();
        for round in 0..3 {
            let base = round * 100;
            assert_eq!(m.command(id("a1"), base), Verdict::Ok);
            assert_eq!(m.uncontrollable(id("b1"), base + 10), Verdict::Ok);
            assert_eq!(m.command(id("a2"), base + 20), Verdict::Ok);
            assert_eq!(m.uncontrollable(id("b2"), base + 30), Verdict::Ok);
        }
        let r = m.report();
        assert_eq!((r.events, r.violations, r.desyncs), (12, 0, 0));
        assert_eq!(r.coverage[0].taken, 2);
        assert_eq!(r.coverage[0].reachable, Some(2));
        assert_eq!(r.marked_visits, 3, "all idle and the buffer empty after each b2");
        assert_eq!(r.longest_marked_gap, 3);
        m.list_uncovered();
        assert!(m.report().uncovered.is_empty());
    }

    #[test]
    fn a_disabled_command_is_a_violation() {
        let (mut m, t) = monitor(1000);
        assert_eq!(m.command(t.id("a2").unwrap(), 0), Verdict::Violation);
        let r = m.report();
        assert_eq!(r.violations, 1);
        assert_eq!(r.findings, ["event 1: command 'a2' disabled by S"]);
        assert_eq!(m.command(t.id("b1").unwrap(), 1), Verdict::Violation, "b1 is not a command");
        assert_eq!(m.command(EventId::from_u32(77), 2), Verdict::Violation);
    }

    #[test]
    fn the_factory_is_race_free_a_stale_start_is_impossible_anyway() {
        let (mut m, t) = monitor(1000);
        let id = |n| t.id(n).unwrap();
        m.command(id("a1"), 0);
        m.uncontrollable(id("b1"), 10);
        assert_eq!(m.command(id("a2"), 20), Verdict::Ok);
        m.uncontrollable(id("b2"), 30);
        assert_eq!(m.command(id("a1"), 31), Verdict::Ok, "a1 commutes with b2: read or not, same state");
        m.uncontrollable(id("b1"), 40);
        // Buffer full: a1 is disabled now, and before b1 was read M1 was busy: no view allows it.
        assert_eq!(m.command(id("a1"), 41), Verdict::Violation);
        assert_eq!(m.report().desyncs, 0);
    }

    #[test]
    fn a_stale_command_that_cannot_be_reordered_is_an_unresolved_desync() {
        // The sensor event s happens only while M is idle and flips a mode in which S disables `a`.
        let m = automaton("M", Kind::Plant, 2, &[0], &["a"], &[(0, "a", 1), (1, "b", 0), (0, "s", 0)]);
        let sup =
            automaton("S", Kind::Supervisor, 2, &[0, 1], &["a"], &[(0, "a", 0), (0, "s", 1), (1, "s", 0)]);
        let table = EventTable::build([&m, &sup]).unwrap();
        let mut mon = Monitor::new(&[&m], &[&sup], &table, 1000).unwrap();
        let id = |n| table.id(n).unwrap();
        mon.uncontrollable(id("s"), 0);
        assert_eq!(mon.command(id("a"), 1), Verdict::Desync { resolved: false });
        assert_eq!((mon.report().desyncs, mon.report().violations), (1, 0));
    }

    #[test]
    fn past_the_window_an_unread_event_no_longer_excuses_a_command() {
        let (mut m, t) = monitor(5);
        let id = |n| t.id(n).unwrap();
        m.command(id("a1"), 0);
        m.uncontrollable(id("b1"), 10);
        assert_eq!(m.command(id("a1"), 100), Verdict::Violation);
    }

    #[test]
    fn a_reordered_race_that_commutes_is_resolved() {
        // Plant: one machine plus an independent sensor s (uncontrollable) that flips a mode the
        // supervisor watches: the supervisor allows `a` only in mode 0.
        let m = machine("M", "a", "b");
        let sensor = automaton("Sensor", Kind::Plant, 1, &[0], &[], &[(0, "s", 0)]);
        let sup =
            automaton("S", Kind::Supervisor, 2, &[0, 1], &["a"], &[(0, "a", 0), (0, "s", 1), (1, "s", 0)]);
        let table = EventTable::build([&m, &sensor, &sup]).unwrap();
        let mut mon = Monitor::new(&[&m, &sensor], &[&sup], &table, 1000).unwrap();
        let id = |n| table.id(n).unwrap();
        mon.uncontrollable(id("s"), 0);
        // Decided in mode 0 before s was read: stale, but a·s is defined, so taken in that order.
        assert_eq!(mon.command(id("a"), 1), Verdict::Desync { resolved: true });
        assert_eq!(mon.plant_state(), [1, 0]);
        assert_eq!(mon.physical[2], 1, "s moved the supervisor after a");
        assert_eq!(mon.report().violations, 0);
        // The supervisor's `a` transition from mode 0 was taken, though the command came as a desync.
        assert_eq!((mon.report().coverage[0].taken, mon.report().coverage[0].reachable), (1, Some(1)));
        assert!(mon.report().full_coverage_at.is_some());
    }

    #[test]
    fn a_supervisor_refusing_an_uncontrollable_event_is_a_violation() {
        let m = machine("M", "a", "b");
        let sup = automaton("S", Kind::Supervisor, 2, &[0], &["a"], &[(0, "a", 1), (1, "a", 0), (0, "b", 0)]);
        let table = EventTable::build([&m, &sup]).unwrap();
        let mut mon = Monitor::new(&[&m], &[&sup], &table, 1000).unwrap();
        mon.command(table.id("a").unwrap(), 0);
        assert_eq!(mon.uncontrollable(table.id("b").unwrap(), 1), Verdict::Violation);
        assert_eq!(mon.report().findings, ["event 2: uncontrollable 'b' refused by S"]);
    }
}
