//! What a hybrid controller's controllable transitions wait for, as plant automata: the part of the
//! plant the reachability graph leaves out, for the runtimes that run the plant as automata.
//!
//! A controllable transition with a condition Y(t) fires only once the supervisor allows it *and* the
//! condition holds — M1 starts (`s1`) on its part sensor (`part1`). The net's reachability graph,
//! the plant `SUPER` is synthesised against, has no signals: in it `s1` is possible whenever M1 is
//! idle. The hybrid controller reads the sensor itself, but an event-based runtime (the firmware
//! under QEMU or on a board) commands every event plants ‖ supervisors enable, and against the bare
//! graph it would start M1 the moment M1 is idle, as if parts never ran out — so the line would never
//! empty and never be back home.
//!
//! Here the condition's coming true is the plant's own uncontrollable event, its *arrival*, and one
//! two-state plant automaton per arrival (`waiting` after it, `none` before; both marked — arrivals
//! are the plant's environment, not a task to complete) lets every controllable event that waits on
//! it happen only in `waiting`, and takes it back to `none`: the part is taken. A condition that is one
//! input signal read as it is gives the arrival that signal's name (`part1`: a part waits at M1);
//! any other gives `<event>_ready`. A controllable event that some transition generates without a
//! condition waits for nothing (the automaton could not say in which markings it must wait). The
//! arrivals change neither the graph nor `SUPER` (whose events they are not): they only take from the
//! runtime's choice the commands the plant could not have followed.

use std::path::Path;

use super::condition::Expr;
use super::interpretation::Interpretation;
use super::reachability::Labels;
use super::NetError;
use crate::config::NetSpec;
use crate::model::{Automaton, Kind};

/// One plant automaton per arrival the controllable transitions of `net` (labelled by `labels`) wait
/// for, in the order of the first transition that waits on each; none when no controllable transition
/// has a condition. `spec` and `file` (the manifest) name the line of a condition whose arrival's name
/// is already an event of the net.
pub fn arrivals(
    spec: &NetSpec,
    file: &Path,
    net: &Interpretation,
    labels: &Labels,
) -> Result<Vec<Automaton>, NetError> {
    // (arrival, the controllable events waiting on it), in order of first appearance.
    let mut waits: Vec<(String, Vec<String>)> = Vec::new();
    for (t, event) in labels.events.iter().enumerate() {
        if !labels.controllable[t] {
            continue;
        }
        // The conditions of every transition `event` labels (`t`'s among them).
        let conditions: Vec<&Expr<usize>> =
            labels.events.iter().zip(&net.conditions).filter(|(e, _)| *e == event).map(|(_, c)| c).collect();
        if conditions.contains(&&Expr::Const(true)) {
            continue;
        }
        let arrival = match conditions.first() {
            Some(Expr::Var(s)) if conditions.iter().all(|c| *c == conditions[0]) => {
                net.signals[*s].name.clone()
            }
            _ => format!("{event}_ready"),
        };
        if labels.events.contains(&arrival) {
            let id = &net.net.transitions[t].id;
            let line =
                spec.conditions.keys().find(|k| k.get_ref() == id).map_or(0, |k| spec.line(k.span().start));
            return Err(NetError::Spec {
                file: file.to_owned(),
                line,
                message: format!(
                    "conditions.{id}: its arrival '{arrival}' (the condition coming true, for the event-based \
                     runtimes) is an event of the net already"
                ),
            });
        }
        match waits.iter_mut().find(|(a, _)| *a == arrival) {
            Some((_, events)) if !events.contains(event) => events.push(event.clone()),
            Some(_) => {}
            None => waits.push((arrival, vec![event.clone()])),
        }
    }
    waits.into_iter().map(|(arrival, events)| automaton(&arrival, &events)).collect()
}

/// The plant automaton of `arrival`: `none` (initial) –arrival→ `waiting` –each of `events`→ `none`.
fn automaton(arrival: &str, events: &[String]) -> Result<Automaton, NetError> {
    let mut a = Automaton::new(arrival, Kind::Plant);
    let none = a.add_state("none", true)?;
    let waiting = a.add_state("waiting", true)?;
    a.initial = Some(none);
    let came = a.add_event(arrival, false)?;
    a.add_transition(none, came, waiting);
    for e in events {
        let taken = a.add_event(e.as_str(), true)?;
        a.add_transition(waiting, taken, none);
    }
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::Manifest;
    use crate::model::EventTable;
    use crate::net::read_pnml;

    /// The example's arrivals with each `(from, to)` replaced in its manifest.
    fn line(edits: &[(&str, &str)]) -> Result<Vec<Automaton>, NetError> {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/hybrid/hybrid.toml");
        let text =
            edits.iter().fold(std::fs::read_to_string(&path).unwrap(), |t, (from, to)| t.replace(from, to));
        let m = Manifest::parse(&path, &text).unwrap();
        let spec = m.net.as_ref().unwrap();
        let raw = read_pnml(&m.resolve(spec.pnml.get_ref())).unwrap();
        let net = Interpretation::bind(spec, &m.file, raw, &EventTable::build([]).unwrap()).unwrap();
        let labels = Labels::bind(spec, m.hybrid.as_ref().unwrap(), &m.file, &net.net).unwrap();
        arrivals(spec, &m.file, &net, &labels)
    }

    fn shape(a: &Automaton) -> (String, Vec<(String, bool)>, usize) {
        let events = a.events.iter().map(|e| (e.name.clone(), e.controllable)).collect();
        (a.name.clone(), events, a.transitions.len())
    }

    #[test]
    fn m1_waits_for_its_part_and_takes_it() {
        let a = line(&[]).unwrap();
        assert_eq!(a.len(), 1, "t4's done2 is on an uncontrollable transition: the plant's own timing");
        assert_eq!(shape(&a[0]), ("part1".into(), vec![("part1".into(), false), ("s1".into(), true)], 2));
        assert!(a[0].states.iter().all(|s| s.marked), "arrivals complete no task");
    }

    #[test]
    fn a_compound_condition_is_the_events_readiness_and_none_waits_for_nothing() {
        let a = line(&[("t1 = \"part1\"", "t1 = \"part1 AND NOT done2\"")]).unwrap();
        assert_eq!(shape(&a[0]).0, "s1_ready");
        assert!(line(&[("t1 = \"part1\"", "")]).unwrap().is_empty());
    }

    #[test]
    fn an_arrival_named_as_an_event_of_the_net_is_refused_with_its_line() {
        let err = line(&[("\"done2\"]", "\"done2\", \"f1\"]"), ("t1 = \"part1\"", "t1 = \"f1\"")])
            .unwrap_err()
            .to_string();
        assert!(err.contains("hybrid.toml:15: conditions.t1: its arrival 'f1'"), "{err}");
    }
}
