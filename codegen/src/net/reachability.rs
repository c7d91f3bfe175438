//! The reachability graph of a net whose transitions are labelled by events, as an automaton: the plant
//! of a hybrid controller (Uzam & Gelen 2013, step 4: a bounded automation net as the plant a supervisor
//! is synthesised against).
//!
//! One state per reachable marking, named by its marked places (`p1.p4`, a place holding k > 1 tokens
//! as `p3x2`); one transition per firing, labelled by the transition's event. The initial marking is the
//! only marked state: the production cycle's home. A net that is not bounded is refused naming a place
//! that grows — found by Karp and Miller's criterion, a marking that strictly covers one on its own path
//! from the initial marking (sound for nets without inhibitor arcs; a net with them is only bounded by
//! the state limit) — and so is one whose graph is not deterministic: two transitions with one event
//! enabled together, leading to different markings.

use std::collections::HashMap;
use std::path::Path;

use super::model::{Marking, Net};
use super::NetError;
use crate::config::{HybridSpec, NetSpec};
use crate::model::{Automaton, Kind, StateId};

/// The event of each transition and whether it is controllable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Labels {
    /// Per transition of the net, its event.
    pub events: Vec<String>,
    /// Per transition, whether its event is controllable.
    pub controllable: Vec<bool>,
}

impl Labels {
    /// The labels a manifest's `[hybrid]` section gives the transitions of `net` (the net of its `[net]`
    /// section `spec`, in the manifest `file`): every transition an event, every controllable event a
    /// transition's; a name that does not fit is refused with its manifest line.
    pub fn bind(spec: &NetSpec, hybrid: &HybridSpec, file: &Path, net: &Net) -> Result<Labels, NetError> {
        let at = |span: std::ops::Range<usize>, message: String| NetError::Spec {
            file: file.to_owned(),
            line: spec.line(span.start),
            message,
        };
        for key in hybrid.events.keys() {
            if net.transition(key.get_ref()).is_none() {
                return Err(at(
                    key.span(),
                    format!("hybrid.events.{}: the net has no such transition", key.get_ref()),
                ));
            }
        }
        let mut events = Vec::new();
        for t in &net.transitions {
            match hybrid.events.iter().find(|(k, _)| *k.get_ref() == t.id) {
                Some((_, e)) => events.push(e.get_ref().clone()),
                None => {
                    return Err(at(
                        spec.pnml.span(),
                        format!("transition '{}' has no event in [hybrid.events]", t.id),
                    ))
                }
            }
        }
        for c in &hybrid.controllable {
            if !events.contains(c.get_ref()) {
                return Err(at(
                    c.span(),
                    format!("hybrid.controllable: no transition generates '{}'", c.get_ref()),
                ));
            }
        }
        let controllable =
            events.iter().map(|e| hybrid.controllable.iter().any(|c| c.get_ref() == e)).collect();
        Ok(Labels { events, controllable })
    }

    /// The transition `event` fires in the marking `m`: the first in net order that `m` state-enables and
    /// that carries `event` — the firing [`reachability`] makes the graph's transition on `event` from
    /// `m` (a net where two such lead to different markings is refused there); `None` when there is none.
    pub fn firing(&self, net: &Net, m: &[u32], event: &str) -> Option<usize> {
        (0..net.transitions.len())
            .find(|&t| self.events.get(t).is_some_and(|e| e == event) && net.state_enabled(t, m))
    }
}

/// The reachability graph of `net` under `labels` as a plant automaton named `name`, at most `limit`
/// states.
pub fn reachability(net: &Net, labels: &Labels, name: &str, limit: usize) -> Result<Automaton, NetError> {
    let mut a = Automaton::new(name, Kind::Plant);
    for (t, e) in labels.events.iter().enumerate() {
        if a.event_id(e).is_none() {
            a.add_event(e.clone(), labels.controllable[t])?;
        }
    }
    let monotone = net.transitions.iter().all(|t| t.inhibitors.is_empty());
    let start = net.initial_marking();
    let mut index: HashMap<Marking, usize> = HashMap::from([(start.clone(), 0)]);
    let mut order = vec![start];
    let mut parent: Vec<Option<usize>> = vec![None];
    a.add_state(state_name(net, &order[0]), true)?;
    a.initial = Some(StateId::new(0).expect("state 0"));
    let mut here = 0;
    while here < order.len() {
        let m = order[here].clone();
        let mut by_event: HashMap<&str, (usize, Marking)> = HashMap::new();
        for t in 0..net.transitions.len() {
            if !net.state_enabled(t, &m) {
                continue;
            }
            let next = net.fire(t, &m).ok_or_else(|| NetError::Unbounded { place: overflow(net, t, &m) })?;
            let event = labels.events[t].as_str();
            match by_event.get(event) {
                Some((u, other)) if *other != next => {
                    return Err(NetError::Nondeterministic {
                        event: event.to_owned(),
                        first: net.transitions[*u].id.clone(),
                        second: net.transitions[t].id.clone(),
                        marking: state_name(net, &m),
                    })
                }
                Some(_) => continue,
                None => {
                    by_event.insert(event, (t, next.clone()));
                }
            }
            let target = match index.get(&next) {
                Some(&i) => i,
                None => {
                    if monotone {
                        check_bounded(net, &order, &parent, here, &next)?;
                    }
                    if order.len() >= limit {
                        return Err(NetError::StateLimit { limit });
                    }
                    index.insert(next.clone(), order.len());
                    a.add_state(state_name(net, &next), false)?;
                    order.push(next);
                    parent.push(Some(here));
                    order.len() - 1
                }
            };
            let e = a.event_id(event).expect("event added above");
            a.add_transition(StateId::new(here).expect("state"), e, StateId::new(target).expect("state"));
        }
        here += 1;
    }
    a.canonicalize();
    Ok(a)
}

/// Refuses `next` (reached from `order[from]`) when it strictly covers a marking on its path from the
/// initial one, naming the first place that grew.
fn check_bounded(
    net: &Net,
    order: &[Marking],
    parent: &[Option<usize>],
    from: usize,
    next: &[u32],
) -> Result<(), NetError> {
    let mut at = Some(from);
    while let Some(i) = at {
        let old = &order[i];
        if old.iter().zip(next).all(|(o, n)| n >= o) {
            if let Some(p) = old.iter().zip(next).position(|(o, n)| n > o) {
                return Err(NetError::Unbounded { place: net.places[p].id.clone() });
            }
        }
        at = parent[i];
    }
    Ok(())
}

/// The output place of `t` that overflows under `m`.
fn overflow(net: &Net, t: usize, m: &[u32]) -> String {
    let tr = &net.transitions[t];
    let p = tr.outputs.iter().find(|&&(p, w)| m[p].checked_add(w).is_none()).map_or(0, |&(p, _)| p);
    net.places[p].id.clone()
}

/// A marking's state name: its marked places joined by `.`, a count above one as `x<k>`; `empty` when
/// no place is marked.
pub fn state_name(net: &Net, m: &[u32]) -> String {
    let parts: Vec<String> = net
        .places
        .iter()
        .zip(m)
        .filter(|(_, &k)| k > 0)
        .map(|(p, &k)| if k == 1 { p.id.clone() } else { format!("{}x{k}", p.id) })
        .collect();
    if parts.is_empty() {
        "empty".into()
    } else {
        parts.join(".")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::net::model::{Place, Transition};

    fn place(id: &str, initial: u32) -> Place {
        Place { id: id.into(), initial }
    }

    fn arc(id: &str, inputs: &[usize], outputs: &[usize]) -> Transition {
        Transition {
            id: id.into(),
            inputs: inputs.iter().map(|&p| (p, 1)).collect(),
            outputs: outputs.iter().map(|&p| (p, 1)).collect(),
            inhibitors: Vec::new(),
        }
    }

    fn labels(events: &[&str]) -> Labels {
        Labels {
            events: events.iter().map(|e| e.to_string()).collect(),
            controllable: events.iter().map(|e| e.ends_with('1')).collect(),
        }
    }

    #[test]
    fn a_machine_and_a_buffer_of_two_give_their_product() {
        // Machine idle (p1) / working (p2); its output goes to a buffer (p3) that a consumer empties.
        let net = Net {
            name: "m".into(),
            places: vec![place("p1", 1), place("p2", 0), place("p3", 0), place("cap", 2)],
            transitions: vec![arc("t1", &[0, 3], &[1]), arc("t2", &[1], &[0, 2]), arc("t3", &[2], &[3])],
        };
        let a = reachability(&net, &labels(&["s1", "f2", "c4"]), "G", 100).unwrap();
        a.validate().unwrap();
        // Buffer 0, 1, 2 with the machine idle or working (working only with room): 5 markings.
        assert_eq!(a.states.len(), 5);
        assert_eq!(a.states[0].name, "p1.capx2");
        assert!(a.states[0].marked && a.states.iter().skip(1).all(|s| !s.marked));
        assert_eq!(a.transitions.len(), 7);
    }

    #[test]
    fn an_unbounded_place_is_named() {
        let net = Net {
            name: "u".into(),
            places: vec![place("p1", 1), place("heap", 0)],
            transitions: vec![arc("t1", &[0], &[0, 1])],
        };
        let err = reachability(&net, &labels(&["a1"]), "G", 100).unwrap_err();
        assert_eq!(err.to_string(), "place 'heap' overflows: the net is unbounded");
    }

    #[test]
    fn one_event_on_two_enabled_transitions_with_different_results_is_refused() {
        let net = Net {
            name: "n".into(),
            places: vec![place("p1", 1), place("p2", 0), place("p3", 0)],
            transitions: vec![arc("ta", &[0], &[1]), arc("tb", &[0], &[2])],
        };
        let err = reachability(&net, &labels(&["a1", "a1"]), "G", 100).unwrap_err();
        assert_eq!(
            err.to_string(),
            "event 'a1' labels transitions 'ta' and 'tb', enabled together at marking p1 with different results"
        );
    }

    #[test]
    fn the_state_limit_stops_the_walk() {
        let net = Net {
            name: "c".into(),
            places: vec![place("p1", 1), place("p2", 0), place("p3", 0)],
            transitions: vec![arc("t1", &[0], &[1]), arc("t2", &[1], &[2]), arc("t3", &[2], &[0])],
        };
        assert_eq!(reachability(&net, &labels(&["a1", "b0", "c0"]), "G", 3).unwrap().states.len(), 3);
        assert!(matches!(
            reachability(&net, &labels(&["a1", "b0", "c0"]), "G", 2),
            Err(NetError::StateLimit { limit: 2 })
        ));
    }
}
