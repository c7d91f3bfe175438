//! The coupled net of a hybrid controller as one place/transition net ([`crate::net::Net`]): the plant
//! net, the auto-net's places and the inhibitor arcs, as the program runs them — so that the net
//! module's own reachability ([`crate::net::reachability`]) and safe-net check can be run on what is
//! written, and its closed loop compared with plant ‖ supervisor.
//!
//! The program fires a plant transition t (event e) only while no auto-net place with an inhibitor arc
//! to t is marked, and the auto-net's token then follows the supervisor's transition on e from its
//! state, or stays where the supervisor has none that leaves it. As one net: for every plant transition
//! t and supervisor state s without an inhibitor arc from s to t, a transition `t@s` with t's arcs and
//! the auto-net place of s in, the place of its successor on e out (the same place when the token
//! stays), labelled e. Its reachability graph is the program's closed loop: equal in language to
//! plant ‖ supervisor exactly when the inhibitor arcs (the control data) disable what the supervisor
//! disables.

use crate::model::Automaton;
use crate::net::model::{Net, Place, Transition};
use crate::net::reachability::{reachability, Labels};
use crate::net::{safety, NetError};
use crate::synth::{language, product, Config};

use super::super::token_passing::MARKING_LIMIT;
use super::super::PlcError;

/// The coupled net of the plant net `net` (its transitions labelled by `labels`) and the supervisor
/// `sup` with the inhibitor arcs `inhibitors` (supervisor state, net transition), and its labels.
pub fn coupled(net: &Net, labels: &Labels, sup: &Automaton, inhibitors: &[(usize, usize)]) -> (Net, Labels) {
    let base = net.places.len();
    let mut places = net.places.clone();
    let initial = sup.initial.map(|i| i.index());
    places.extend(
        sup.states
            .iter()
            .enumerate()
            .map(|(k, s)| Place { id: format!("A_{}", s.name), initial: u32::from(initial == Some(k)) }),
    );
    let mut transitions = Vec::new();
    let mut out = Labels { events: Vec::new(), controllable: Vec::new() };
    for (t, tr) in net.transitions.iter().enumerate() {
        let event = &labels.events[t];
        let e = sup.event_id(event);
        for s in 0..sup.states.len() {
            if inhibitors.contains(&(s, t)) {
                continue;
            }
            let next = e
                .and_then(|e| sup.transitions.iter().find(|x| x.source.index() == s && x.event == e))
                .map_or(s, |x| x.target.index());
            let mut inputs = tr.inputs.clone();
            inputs.push((base + s, 1));
            let mut outputs = tr.outputs.clone();
            outputs.push((base + next, 1));
            transitions.push(Transition {
                id: format!("{}@{}", tr.id, sup.states[s].name),
                inputs,
                outputs,
                inhibitors: tr.inhibitors.clone(),
            });
            out.events.push(event.clone());
            out.controllable.push(labels.controllable[t]);
        }
    }
    (Net { name: format!("{}+{}", net.name, sup.name), places, transitions }, out)
}

/// Checks that the coupled net of `sup` is safe and that its closed loop generates the language of
/// `plant` ‖ `full` (the supervisor synthesis gave, which a reduced `sup` must match).
pub fn check(
    net: &Net,
    labels: &Labels,
    plant: &Automaton,
    full: &Automaton,
    sup: &Automaton,
    inhibitors: &[(usize, usize)],
    cfg: &Config,
) -> Result<(), PlcError> {
    let (c, l) = coupled(net, labels, sup, inhibitors);
    safety::check(&c, MARKING_LIMIT)?;
    let limit = cfg.state_limit.min(MARKING_LIMIT);
    let graph = reachability(&c, &l, &c.name, limit).map_err(|e| match e {
        NetError::Nondeterministic { .. } | NetError::Unbounded { .. } => {
            PlcError::Coupling { supervisor: sup.name.clone(), trace: e.to_string() }
        }
        e => e.into(),
    })?;
    let closed = product(&[plant.clone(), full.clone()], cfg)?;
    // Generated languages: every state marked in both.
    let generated = |a: &Automaton| {
        let mut a = a.clone();
        a.states.iter_mut().for_each(|s| s.marked = true);
        a
    };
    if let Some(d) = language::equal(&generated(&graph), &generated(&closed))? {
        let trace = if d.trace.is_empty() { "the initial state".to_owned() } else { d.trace.join(" ") };
        return Err(PlcError::Coupling { supervisor: sup.name.clone(), trace });
    }
    Ok(())
}
