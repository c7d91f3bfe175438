//! Timeouts as users write them (`[[timers]]`): a timer raises its uncontrollable *timeout* event `ms`
//! milliseconds after one of its *start* events unless one of its *stop* events comes first.
//!
//! ```toml
//! [[timers]]
//! name = "T_ext"                 # the timer's plant automaton
//! start = ["extend"]             # (re)arm it: a command, or a sensor event
//! stop = ["at_end"]              # disarm it
//! timeout = "ext_timeout"        # default: "<name>_timeout"
//! ms = 2000
//! ```
//!
//! The convention is ESCET's and CompileDES' timer-as-event one: for synthesis the timer is an ordinary,
//! untimed plant component — `idle` (marked) `—start→ running —timeout→ idle`, `running —stop→ idle`, a
//! start while running restarts it (a self-loop), a stop while idle changes nothing (a self-loop) — so
//! the supervisors are synthesised with it exactly; only the runtimes (firmware, PLC program, virtual
//! plant) know the duration.

use serde::Deserialize;

use crate::model::{Automaton, Kind, ModelError};

/// One `[[timers]]` entry.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimerSpec {
    /// The name of the timer's plant automaton (one name among all the set's automata).
    pub name: String,
    /// The events that arm the timer, or re-arm it while it runs (at least one).
    pub start: Vec<String>,
    /// The events that disarm it (none: only the timeout ends a run).
    #[serde(default)]
    pub stop: Vec<String>,
    /// The uncontrollable event the timer raises; default `<name>_timeout`.
    #[serde(default)]
    pub timeout: Option<String>,
    /// The delay from the last start to the timeout, in milliseconds (> 0).
    pub ms: u32,
}

impl TimerSpec {
    /// The timeout event's name.
    pub fn timeout_event(&self) -> String {
        self.timeout.clone().unwrap_or_else(|| format!("{}_timeout", self.name))
    }

    /// Why this timer cannot be built over the events of the set (`controllable` says, per event name,
    /// whether it is a command, `None` when no automaton of the set has it), each problem a line naming
    /// the key `timers[index]`; empty when it can.
    pub fn problems(&self, index: usize, controllable: impl Fn(&str) -> Option<bool>) -> Vec<String> {
        let key = format!("timers[{index}]");
        let mut problems = Vec::new();
        if self.ms == 0 {
            problems.push(format!("{key}.ms: a timeout of 0 ms is no timeout (give the delay in ms, > 0)"));
        }
        if self.start.is_empty() {
            problems
                .push(format!("{key}.start: a timer no event starts never runs (name one event at least)"));
        }
        for (field, events) in [("start", &self.start), ("stop", &self.stop)] {
            for e in events {
                if controllable(e).is_none() {
                    problems.push(format!("{key}.{field}: no automaton of the set has the event '{e}'"));
                }
            }
        }
        if let Some(e) = self.start.iter().find(|e| self.stop.contains(e)) {
            problems.push(format!("{key}: '{e}' both starts and stops the timer"));
        }
        let timeout = self.timeout_event();
        if self.start.contains(&timeout) || self.stop.contains(&timeout) {
            problems.push(format!(
                "{key}.timeout: '{timeout}' is the timer's own event; it cannot start or stop it"
            ));
        }
        if controllable(&timeout) == Some(true) {
            problems.push(format!(
                "{key}.timeout: '{timeout}' is controllable elsewhere; a timeout is the timer's, uncontrollable"
            ));
        }
        problems
    }

    /// The timer as an untimed plant automaton (see the module documentation); start and stop events
    /// take the controllability `controllable` gives them (false when it gives none), the timeout is
    /// uncontrollable.
    pub fn automaton(&self, controllable: impl Fn(&str) -> Option<bool>) -> Result<Automaton, ModelError> {
        let mut a = Automaton::new(self.name.clone(), Kind::Plant);
        let idle = a.add_state("idle", true)?;
        let running = a.add_state("running", false)?;
        a.initial = Some(idle);
        for e in &self.start {
            let id = a.add_event(e.clone(), controllable(e).unwrap_or(false))?;
            a.add_transition(idle, id, running);
            a.add_transition(running, id, running);
        }
        for e in &self.stop {
            let id = a.add_event(e.clone(), controllable(e).unwrap_or(false))?;
            a.add_transition(idle, id, idle);
            a.add_transition(running, id, idle);
        }
        let timeout = a.add_event(self.timeout_event(), false)?;
        a.add_transition(running, timeout, idle);
        Ok(a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> TimerSpec {
        TimerSpec {
            name: "T".into(),
            start: vec!["go".into()],
            stop: vec!["end".into()],
            timeout: None,
            ms: 2000,
        }
    }

    /// The event `e` of `a` from `state`, if any: the target's name.
    fn step(a: &Automaton, state: &str, e: &str) -> Option<String> {
        let (s, e) = (a.state_id(state)?, a.event_id(e)?);
        let t = a.transitions.iter().find(|t| t.source == s && t.event == e)?;
        Some(a.states[t.target.index()].name.clone())
    }

    #[test]
    fn the_timer_automaton_starts_restarts_stops_and_times_out() {
        let a = spec().automaton(|e| Some(e == "go")).unwrap();
        assert_eq!(a.name, "T");
        assert_eq!(a.kind, Kind::Plant);
        let ev = |n: &str| a.events[a.event_id(n).unwrap().index()].controllable;
        assert!(ev("go") && !ev("end") && !ev("T_timeout"));
        assert_eq!(step(&a, "idle", "go").as_deref(), Some("running"));
        assert_eq!(step(&a, "running", "go").as_deref(), Some("running"), "a start while running restarts");
        assert_eq!(step(&a, "running", "end").as_deref(), Some("idle"));
        assert_eq!(step(&a, "idle", "end").as_deref(), Some("idle"), "a stop while idle changes nothing");
        assert_eq!(step(&a, "running", "T_timeout").as_deref(), Some("idle"));
        assert_eq!(step(&a, "idle", "T_timeout"), None, "no timeout without a start");
        assert_eq!(a.marked_count(), 1);
        assert!(a.states[a.initial.unwrap().index()].marked);
    }

    #[test]
    fn a_timer_that_does_not_fit_the_set_is_refused_with_every_problem() {
        let mut t = spec();
        t.ms = 0;
        t.stop.push("nope".into());
        t.timeout = Some("go2".into());
        let problems = t.problems(3, |e| match e {
            "go" | "end" => Some(false),
            "go2" => Some(true),
            _ => None,
        });
        assert_eq!(problems.len(), 3, "{problems:?}");
        assert!(problems[0].starts_with("timers[3].ms:"), "{problems:?}");
        assert!(problems[1].contains("timers[3].stop: no automaton of the set has the event 'nope'"));
        assert!(problems[2].contains("'go2' is controllable elsewhere"));
        assert!(spec().problems(0, |_| Some(false)).is_empty());
    }
}
