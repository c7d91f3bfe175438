//! `codegen sim`: the supervised plant in a browser. A [`Sim`] holds a set's closed loop plants ‖
//! supervisors at one point of a trace — stepped by hand, reverted, reset, or run for N events by the
//! firmware's choice policy against the virtual plant's steering (module `run`) — with the coverage of the
//! supervisors' transitions so far and `check`'s findings located on the automata ([`findings`]).
//! [`api`] answers the page's JSON requests on it, [`draw`] lays each automaton out as SVG (the
//! neighbourhood of its current state when large), and [`server`] serves the page and the API on a local
//! port (docs/sim.md). For a state-based project, [`state_based`] adds the program's signal word and
//! rungs; for a project with a Petri net (a sequence, or a hybrid controller's plant net), [`sequence`]
//! its marking.

pub mod api;
mod controller;
pub mod draw;
pub mod findings;
mod run;
pub mod sequence;
pub mod server;
pub mod state_based;

use std::collections::BTreeSet;

use crate::config::RuntimeConfig;
use crate::model::{Automaton, Composition, EventId, ModelError};
use crate::pack::{PackSet, Role};

pub use findings::Located;

/// Who took a step of the trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Actor {
    /// The user, clicking an event.
    User,
    /// The virtual plant, in a run.
    Plant,
    /// The controller's choice policy, in a run.
    Controller,
}

/// One step of the trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Step {
    /// The event taken.
    pub event: EventId,
    /// Who took it.
    pub by: Actor,
}

/// Why a step was refused.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
pub enum StepError {
    /// No event of that name in the set.
    #[error("no event named '{0}' in the set")]
    Unknown(String),
    /// The closed loop refuses the event here.
    #[error("'{event}' is not possible here: refused by {}", by.join(", "))]
    Refused {
        /// The event.
        event: String,
        /// The automata that refuse it.
        by: Vec<String>,
    },
    /// A revert past the end of the trace.
    #[error("the trace has {len} steps; cannot go back to step {to}")]
    Beyond {
        /// Where the user asked to go.
        to: usize,
        /// The trace's length.
        len: usize,
    },
}

/// A set's closed loop under simulation; see the module documentation.
pub struct Sim {
    /// The project's name.
    pub name: String,
    /// Plants first, then supervisors: the members of [`Sim::closed`] in order.
    pub automata: Vec<Automaton>,
    /// How many of [`Sim::automata`] are plants.
    pub plants: usize,
    /// The set (its event numbering, and what a run's virtual plant and monitor are made of).
    pub set: PackSet,
    /// Plants ‖ supervisors, tracked.
    pub closed: Composition,
    /// The runtime configuration (policy, seed) a run's controller uses.
    pub runtime: RuntimeConfig,
    /// The steps taken, from the initial state.
    pub trace: Vec<Step>,
    /// The state before each step and after the last: `states[k]` is the state after `k` steps.
    states: Vec<Vec<u32>>,
    /// Per supervisor: the transitions `(state, global event)` the trace has taken.
    pub covered: Vec<BTreeSet<(u32, u32)>>,
    /// `check`'s findings, located on the automata.
    pub findings: Result<Vec<Located>, String>,
    /// Runs so far: each run's plant and controller are seeded from the runtime seed plus this count, so
    /// two runs from one point differ and the whole session is reproducible.
    pub runs: u64,
    /// A state-based project's program (`[state]`): its signal word and rungs, or why there is none;
    /// `None` for a project without the section.
    pub program: Option<Result<state_based::Program, String>>,
    /// A project's Petri net (a `[net]` sequence, or a hybrid controller's plant net), or why it could
    /// not be read; `None` for a project without one.
    pub net: Option<Result<sequence::Net, String>>,
}

impl Sim {
    /// A simulation of `set` named `name`, the controller running `runtime`, in the initial state.
    /// `check`'s findings are computed once here (their error, if any, is kept to show).
    pub fn new(name: &str, set: PackSet, runtime: RuntimeConfig) -> Result<Self, ModelError> {
        let of = |role| set.members().iter().filter(move |m| m.role == role).map(|m| m.automaton.clone());
        let automata: Vec<Automaton> = of(Role::Plant).chain(of(Role::Supervisor)).collect();
        let plants = set.members().iter().filter(|m| m.role == Role::Plant).count();
        let refs: Vec<&Automaton> = automata.iter().collect();
        let closed = Composition::new(&refs, set.events())?;
        let findings = findings::locate(&automata[..plants], &automata[plants..], set.events());
        let supervisors = automata.len() - plants;
        Ok(Sim {
            name: name.to_owned(),
            states: vec![closed.initial()],
            automata,
            plants,
            set,
            closed,
            runtime,
            trace: Vec::new(),
            covered: vec![BTreeSet::new(); supervisors],
            findings,
            runs: 0,
            program: None,
            net: None,
        })
    }

    /// Shows the state-based program of `signals` (the project's `[state]` section, checked) beside the
    /// closed loop; an error is kept to show.
    pub fn with_signals(mut self, signals: Result<crate::config::Signals, String>) -> Self {
        self.program = Some(signals.and_then(|s| state_based::Program::new(&self.set, s)));
        self
    }

    /// Shows the project's Petri net beside the closed loop, its marking following the trace; an error
    /// is kept to show.
    pub fn with_net(mut self, net: Result<sequence::Net, String>) -> Self {
        self.net = Some(net);
        self
    }

    /// The current state: one local state per automaton.
    pub fn state(&self) -> &[u32] {
        self.states.last().map_or(&[][..], Vec::as_slice)
    }

    /// Takes `event` by `by` when the closed loop allows it.
    pub fn step(&mut self, event: EventId, by: Actor) -> Result<(), StepError> {
        let mut next = self.state().to_vec();
        if !self.closed.step(&mut next, event) {
            let by = self.closed.refusers(self.state(), event).into_iter().map(str::to_owned).collect();
            return Err(StepError::Refused { event: self.set.events().name(event).to_owned(), by });
        }
        self.cover(self.states.len() - 1, event);
        self.trace.push(Step { event, by });
        self.states.push(next);
        Ok(())
    }

    /// Takes the event named `name` by the user.
    pub fn step_named(&mut self, name: &str) -> Result<(), StepError> {
        let event = self.set.events().id(name).ok_or_else(|| StepError::Unknown(name.to_owned()))?;
        self.step(event, Actor::User)
    }

    /// Back to the state after the first `to` steps; the later ones are dropped, and so is the coverage
    /// only they gave.
    pub fn revert(&mut self, to: usize) -> Result<(), StepError> {
        if to > self.trace.len() {
            return Err(StepError::Beyond { to, len: self.trace.len() });
        }
        self.trace.truncate(to);
        self.states.truncate(to + 1);
        for c in &mut self.covered {
            c.clear();
        }
        for k in 0..to {
            self.cover(k, self.trace[k].event);
        }
        Ok(())
    }

    /// Back to the initial state with an empty trace.
    pub fn reset(&mut self) {
        // Reverting to 0 steps is always in range.
        let _ = self.revert(0);
    }

    /// Records the supervisors' transitions taken by `event` from the state after `k` steps.
    fn cover(&mut self, k: usize, event: EventId) {
        let state = &self.states[k];
        for (s, covered) in self.covered.iter_mut().enumerate() {
            let i = self.plants + s;
            if self.closed.has_event(i, event) {
                covered.insert((state[i], event.as_u32()));
            }
        }
    }

    /// The events of the set in the current state, sorted into what the page lists.
    pub fn events(&self) -> Events {
        let table = self.set.events();
        let state = self.state();
        let mut out = Events::default();
        for e in table.ids() {
            let refusing = |range: std::ops::Range<usize>| -> Vec<String> {
                range
                    .filter(|&i| {
                        self.closed.has_event(i, e) && self.closed.local_step(i, state[i], e).is_none()
                    })
                    .map(|i| self.automata[i].name.clone())
                    .collect()
            };
            if !refusing(0..self.plants).is_empty() {
                continue; // the plant cannot take it here
            }
            let name = table.name(e).to_owned();
            let by = refusing(self.plants..self.automata.len());
            match (by.is_empty(), table.is_controllable(e)) {
                (true, true) => out.enabled.push(name),
                (true, false) => out.uncontrollable.push(name),
                (false, controllable) => out.disabled.push(Disabled { event: name, controllable, by }),
            }
        }
        out
    }

    /// Per supervisor: its transitions the trace took and all of them.
    pub fn coverage(&self) -> Vec<(usize, usize)> {
        self.covered
            .iter()
            .zip(&self.automata[self.plants..])
            .map(|(c, a)| (c.len(), a.transitions.len()))
            .collect()
    }

    /// Runs `events` events from the current state: the controller's policy against the virtual plant's
    /// steering (module `run`); the steps join the trace. Returns how many were taken (fewer when the loop
    /// blocks).
    pub fn run(&mut self, events: u64) -> Result<usize, ModelError> {
        run::run(self, events)
    }
}

/// The events in the current state; see [`Sim::events`].
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Events {
    /// Uncontrollable events the plant can take (no supervisor refuses them).
    pub uncontrollable: Vec<String>,
    /// Controllable events the plant can take and every supervisor enables.
    pub enabled: Vec<String>,
    /// Events the plant can take but a supervisor disables.
    pub disabled: Vec<Disabled>,
}

/// An event the plant could take that supervisors disable.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Disabled {
    /// The event.
    pub event: String,
    /// Whether it is controllable (an uncontrollable one disabled is a controllability problem).
    pub controllable: bool,
    /// The supervisors that disable it.
    pub by: Vec<String>,
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::model::testing::build;

    /// A machine M (start: idle → busy, controllable; done: busy → idle) and a supervisor S that allows
    /// `start` only once until `reset`.
    pub fn small() -> Sim {
        let m =
            build("M", &["idle", "busy"], &["start"], &[("idle", "start", "busy"), ("busy", "done", "idle")]);
        let r = build("R", &["0"], &["reset"], &[("0", "reset", "0")]);
        let s = build(
            "S",
            &["fresh", "used"],
            &["start", "reset"],
            &[("fresh", "start", "used"), ("used", "reset", "fresh")],
        );
        let set = PackSet::new(vec![m, r], vec![s]).unwrap();
        Sim::new("small", set, RuntimeConfig::default()).unwrap()
    }

    #[test]
    fn step_revert_and_coverage() {
        let mut sim = small();
        assert_eq!(sim.events().enabled, ["start"]);
        sim.step_named("start").unwrap();
        let ev = sim.events();
        assert_eq!(ev.uncontrollable, ["done"]);
        assert_eq!(ev.enabled, ["reset"]);
        sim.step_named("done").unwrap();
        let ev = sim.events();
        assert_eq!(
            ev.disabled,
            [Disabled { event: "start".into(), controllable: true, by: vec!["S".into()] }]
        );
        assert_eq!(sim.coverage(), [(1, 2)]);
        assert!(matches!(sim.step_named("start"), Err(StepError::Refused { by, .. }) if by == ["S"]));
        assert_eq!(sim.step_named("nope"), Err(StepError::Unknown("nope".into())));
        sim.revert(0).unwrap();
        assert_eq!(sim.state(), sim.closed.initial());
        assert_eq!(sim.coverage(), [(0, 2)]);
        assert!(sim.revert(3).is_err());
    }

    #[test]
    fn a_run_takes_steps_by_plant_and_controller_and_covers_everything() {
        let mut sim = small();
        let taken = sim.run(200).unwrap();
        assert_eq!(taken, 200);
        assert!(sim.trace.iter().any(|s| s.by == Actor::Plant));
        assert!(sim.trace.iter().any(|s| s.by == Actor::Controller));
        assert_eq!(sim.coverage(), [(2, 2)]);
        // Every step of the trace was possible where it was taken.
        let mut state = sim.closed.initial();
        for s in &sim.trace {
            assert!(sim.closed.step(&mut state, s.event));
        }
        assert_eq!(state, sim.state());
    }
}
