//! One hybrid controller: the automation net of the plant coupled to a supervisor's auto-net by
//! inhibitor arcs, as Ladder Diagram rungs in the seed's order (Uzam & Gelen 2013, §3–4).
//!
//! - **auto-net**: one place per supervisor state (`A_<k>`, one token, on the initial state), one
//!   transition per supervisor transition between two different states;
//! - **inhibitor arcs**: from the auto-net place of each supervisor state to every net transition whose
//!   controllable event that state disables (the control data, `synth::condat`);
//! - **rungs**, in order: the initial marking (network 0, on the first scan); the plant net's token
//!   passing — its timers, then its transitions in net order, each inhibited by the auto-net places
//!   its inhibitor arcs come from and setting the memory bit of its event (`E_<event>`) when it fires —
//!   written by the one lowering of a net ([`crate::plc::token_passing`], so a delay means what it means
//!   for a sequence: the input places marked for D); then the auto-net's transitions, the place actions
//!   (an actuator on while a place naming it is marked) and the end of the scan. An auto-net transition
//!   moves the supervisor's token on its event's bit. At most one plant transition fires per scan
//!   (the bit `fired`), so the auto-net sees every event in the order the plant made them; the events
//!   on which the auto-net could move twice in one scan (p –σ→ q –σ→ r, the avalanche check of
//!   `plc::avalanche`) have their bit reset by the auto-net rung that uses it (AEEM); every bit is
//!   reset at the end of the scan. Only the events that move the auto-net's token have a bit.

use super::super::avalanche::{chain_events, Out};
use super::super::token_passing::{self, Actions, Idents};
use crate::model::{Automaton, EventId, StateId};
use crate::net::interpretation::{Direction, Interpretation};
use crate::net::NetError;
use crate::scan::ld::{Coil, CoilKind, Element, Rung};

/// A hybrid controller's rungs and what they are made of.
#[derive(Clone, Debug)]
pub struct Controller {
    /// The rungs (networks), top to bottom.
    pub rungs: Vec<Rung>,
    /// Inhibitor arcs: (supervisor state, net transition).
    pub inhibitors: Vec<(usize, usize)>,
    /// The auto-net's transitions: (from state, event, to state), self-loops left out.
    pub auto_transitions: Vec<(usize, String, usize)>,
    /// The events whose memory bit the auto-net resets where it uses it (AEEM).
    pub aeem: Vec<String>,
    /// The BOOL variables: (name, comment), in declaration order.
    pub bools: Vec<(String, String)>,
    /// The timers: (instance, transition id, milliseconds).
    pub timers: Vec<(String, String, u32)>,
    /// Input signals (sensors) and output signals (actuators) as variables: (name, direction).
    pub signals: Vec<(String, Direction)>,
    /// The supervisor's states, for the report.
    pub states: usize,
}

fn coil(variable: &str, kind: CoilKind) -> Coil {
    Coil { variable: variable.to_owned(), kind }
}

impl Controller {
    /// The controller of the plant net `net` (transition `t` generating `events[t]`) under the
    /// supervisor `sup` over those events, with its control data `condat` (per state, the events it
    /// disables). The net must be safe.
    pub fn new(
        net: &Interpretation,
        events: &[String],
        sup: &Automaton,
        condat: &[Vec<String>],
    ) -> Result<Controller, NetError> {
        let mut out: Vec<Vec<(EventId, StateId)>> = vec![Vec::new(); sup.states.len()];
        let mut auto_transitions = Vec::new();
        for t in &sup.transitions {
            out[t.source.index()].push((t.event, t.target));
            if t.source != t.target {
                let e = sup.events[t.event.index()].name.clone();
                auto_transitions.push((t.source.index(), e, t.target.index()));
            }
        }
        // Only the events that move the auto-net's token need a memory bit.
        let mut distinct: Vec<String> = auto_transitions.iter().map(|(_, e, _)| e.clone()).collect();
        distinct.sort();
        distinct.dedup();
        let mut id = Idents::new(net);
        let init = id.plain("Init");
        let state: Vec<String> = (0..sup.states.len()).map(|k| id.fresh("A", &k.to_string())).collect();
        let event: Vec<String> = distinct.iter().map(|e| id.fresh("E", e)).collect();
        let event_var = |e: &str| distinct.binary_search_by(|x| x.as_str().cmp(e)).ok().map(|i| &event[i]);
        let inhibitors: Vec<(usize, usize)> = condat
            .iter()
            .enumerate()
            .flat_map(|(s, off)| {
                events.iter().enumerate().filter(move |(_, e)| off.contains(e)).map(move |(t, _)| (s, t))
            })
            .collect();
        let aeem: Vec<String> = chain_events(&out as &Out, &|_| true)
            .into_iter()
            .map(|e| sup.events[e.index()].name.clone())
            .collect();

        let transitions = &net.net.transitions;
        let blocked: Vec<Vec<String>> = (0..transitions.len())
            .map(|t| inhibitors.iter().filter(|&&(_, u)| u == t).map(|&(s, _)| state[s].clone()).collect())
            .collect();
        let also: Vec<Vec<String>> =
            (0..transitions.len()).map(|t| event_var(&events[t]).into_iter().cloned().collect()).collect();
        let mut lowered = token_passing::lower(net, &id, Actions::Level, &blocked, &also)?;
        for (rung, (tr, e)) in lowered.firing.iter_mut().skip(1).zip(transitions.iter().zip(events)) {
            rung.comment = format!("{}: event {e}", tr.id);
        }

        let mut first: Vec<Coil> = net
            .net
            .places
            .iter()
            .zip(&id.place)
            .filter(|(p, _)| p.initial > 0)
            .map(|(_, v)| coil(v, CoilKind::Set))
            .collect();
        if let Some(i) = sup.initial {
            first.push(coil(&state[i.index()], CoilKind::Set));
        }
        first.push(coil(&init, CoilKind::Set));
        let mut rungs = vec![Rung {
            comment: "NW0: the initial marking (first scan)".into(),
            condition: Element::contact(init.clone(), true),
            coils: first,
        }];
        rungs.extend(lowered.timers.iter().chain(&lowered.firing).cloned());
        for (s, e, target) in &auto_transitions {
            let bit = event_var(e).cloned().unwrap_or_default();
            let mut coils = vec![coil(&state[*s], CoilKind::Reset), coil(&state[*target], CoilKind::Set)];
            if aeem.contains(e) {
                coils.push(coil(&bit, CoilKind::Reset));
            }
            rungs.push(Rung {
                comment: format!("supervisor {} -{e}-> {}", sup.states[*s].name, sup.states[*target].name),
                condition: Element::Series(vec![
                    Element::contact(state[*s].clone(), false),
                    Element::contact(bit, false),
                ]),
                coils,
            });
        }
        rungs.extend(lowered.actions);
        if !event.is_empty() {
            rungs.push(Rung {
                comment: "end of scan: every event bit (AEEM's last step)".into(),
                condition: Element::Series(Vec::new()),
                coils: event.iter().map(|v| coil(v, CoilKind::Reset)).collect(),
            });
        }

        let mut bools = vec![
            (init.clone(), "the initial marking is set".to_owned()),
            (id.fired.clone(), "a plant transition fired in this scan".to_owned()),
        ];
        bools.extend(
            net.net.places.iter().zip(&id.place).map(|(p, v)| (v.clone(), format!("plant place {}", p.id))),
        );
        bools.extend(
            sup.states.iter().zip(&state).map(|(s, v)| (v.clone(), format!("supervisor state {}", s.name))),
        );
        bools.extend(
            distinct
                .iter()
                .zip(&event)
                .map(|(e, v)| (v.clone(), format!("event {e} occurred (read by the auto-net)"))),
        );
        let timers = transitions
            .iter()
            .enumerate()
            .filter(|&(t, _)| net.delays[t] > 0)
            .map(|(t, tr)| (id.timer[t].clone(), tr.id.clone(), net.delays[t]))
            .collect();
        let signals = net.signals.iter().zip(&id.signal).map(|(s, v)| (v.clone(), s.direction)).collect();
        Ok(Controller {
            rungs,
            inhibitors,
            auto_transitions,
            aeem,
            bools,
            timers,
            signals,
            states: sup.states.len(),
        })
    }
}
