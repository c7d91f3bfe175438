//! One hybrid controller: the automation net of the plant coupled to a supervisor's auto-net by
//! inhibitor arcs, as Ladder Diagram rungs in the seed's order (Uzam & Gelen 2013, §3–4).
//!
//! - **auto-net**: one place per supervisor state (`A_<k>`, one token, on the initial state), one
//!   transition per supervisor transition between two different states;
//! - **inhibitor arcs**: from the auto-net place of each supervisor state to every net transition whose
//!   controllable event that state disables (the control data, `synth::condat`);
//! - **rungs**, in order: the initial marking (network 0, on the first scan), the plant net's
//!   transitions in net order — each followed, when it has a delay, by its on-delay timer (so that the
//!   scan that fires it turns the timer off before the place can be marked again) — then the
//!   auto-net's transitions, the place actions, and the end of the scan. A plant transition fires when
//!   its input places are marked, no inhibiting place is, its condition holds and its timer (if any) has
//!   run out; firing it moves the tokens and sets the memory bit of its event (`E_<event>`). An
//!   auto-net transition moves the supervisor's token on that bit. At most one plant transition fires
//!   per scan (the bit `fired`), so the auto-net sees every event in the order the plant made them; the
//!   events on which the auto-net could move twice in one scan (p –σ→ q –σ→ r, the avalanche check of
//!   `plc::avalanche`) have their bit reset by the auto-net rung that uses it (AEEM); every bit is reset
//!   at the end of the scan. Only the events that move the auto-net's token have a bit.

use super::super::avalanche::{chain_events, Out};
use super::super::ld::{Coil, CoilKind, Element, Rung};
use super::super::names::Names;
use crate::model::{Automaton, EventId, StateId};
use crate::net::condition::Expr;
use crate::net::interpretation::{Direction, Interpretation};

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

/// The identifiers of one controller, unique without regard to case.
struct Idents {
    place: Vec<String>,
    state: Vec<String>,
    event: Vec<String>,
    signal: Vec<String>,
    timer: Vec<Option<String>>,
    init: String,
    fired: String,
}

impl Idents {
    fn new(net: &Interpretation, events: &[String], sup: &Automaton) -> Idents {
        let mut names = Names::default();
        let init = names.plain("Init");
        let fired = names.plain("fired");
        let signal = net.signals.iter().map(|s| names.plain(&s.name)).collect();
        let place = net.net.places.iter().map(|p| names.fresh("P", &p.id)).collect();
        let state = (0..sup.states.len()).map(|k| names.fresh("A", &k.to_string())).collect();
        let event = events.iter().map(|e| names.fresh("E", e)).collect();
        let timer = net
            .net
            .transitions
            .iter()
            .zip(&net.delays)
            .map(|(t, &d)| (d > 0).then(|| names.fresh("T", &t.id)))
            .collect();
        Idents { place, state, event, signal, timer, init, fired }
    }
}

/// Y(t) as contacts: negations pushed down to the signals (a normally closed contact).
fn condition(e: &Expr<usize>, negate: bool, signal: &[String]) -> Element {
    match e {
        Expr::Const(b) if *b != negate => Element::Series(Vec::new()),
        Expr::Const(_) => Element::Parallel(Vec::new()),
        Expr::Var(s) => Element::contact(signal[*s].clone(), negate),
        Expr::Not(x) => condition(x, !negate, signal),
        Expr::And(xs) | Expr::Or(xs) => {
            let parts = xs.iter().map(|x| condition(x, negate, signal)).collect();
            if matches!(e, Expr::And(_)) != negate {
                Element::Series(parts)
            } else {
                Element::Parallel(parts)
            }
        }
    }
}

fn coil(variable: &str, kind: CoilKind) -> Coil {
    Coil { variable: variable.to_owned(), kind }
}

impl Controller {
    /// The controller of the plant net `net` (transition `t` generating `events[t]`) under the
    /// supervisor `sup` over those events, with its control data `condat` (per state, the events it
    /// disables).
    pub fn new(
        net: &Interpretation,
        events: &[String],
        sup: &Automaton,
        condat: &[Vec<String>],
    ) -> Controller {
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
        let id = Idents::new(net, &distinct, sup);
        let event_var = |e: &str| distinct.binary_search_by(|x| x.as_str().cmp(e)).ok().map(|i| &id.event[i]);
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

        let mut rungs = Vec::new();
        let mut first: Vec<Coil> = net
            .net
            .places
            .iter()
            .zip(&id.place)
            .filter(|(p, _)| p.initial > 0)
            .map(|(_, v)| coil(v, CoilKind::Set))
            .collect();
        if let Some(i) = sup.initial {
            first.push(coil(&id.state[i.index()], CoilKind::Set));
        }
        first.push(coil(&id.init, CoilKind::Set));
        rungs.push(Rung {
            comment: "NW0: the initial marking (first scan)".into(),
            condition: Element::contact(id.init.clone(), true),
            coils: first,
        });
        for (t, tr) in net.net.transitions.iter().enumerate() {
            let mut enabled: Vec<Element> =
                tr.inputs.iter().map(|&(p, _)| Element::contact(id.place[p].clone(), false)).collect();
            enabled.extend(tr.inhibitors.iter().map(|&(p, _)| Element::contact(id.place[p].clone(), true)));
            enabled.extend(
                inhibitors
                    .iter()
                    .filter(|&&(_, u)| u == t)
                    .map(|&(s, _)| Element::contact(id.state[s].clone(), true)),
            );
            match condition(&net.conditions[t], false, &id.signal) {
                Element::Series(es) if es.is_empty() => {}
                c => enabled.push(c),
            }
            // The timer's rung comes after its transition's: the scan that fires the transition calls
            // it with its input off, so the next occupation of the place starts it afresh.
            let timer = id.timer[t].as_ref().map(|timer| {
                let rung = Rung {
                    comment: format!("{}: on-delay of {} ms", tr.id, net.delays[t]),
                    condition: Element::Series(enabled.clone()),
                    coils: vec![coil(timer, CoilKind::OnDelay(net.delays[t]))],
                };
                enabled.push(Element::contact(format!("{timer}.Q"), false));
                rung
            });
            let mut condition = vec![Element::contact(id.fired.clone(), true)];
            condition.extend(enabled);
            let mut coils: Vec<Coil> =
                tr.inputs.iter().map(|&(p, _)| coil(&id.place[p], CoilKind::Reset)).collect();
            coils.extend(tr.outputs.iter().map(|&(p, _)| coil(&id.place[p], CoilKind::Set)));
            if let Some(bit) = event_var(&events[t]) {
                coils.push(coil(bit, CoilKind::Set));
            }
            coils.push(coil(&id.fired, CoilKind::Set));
            rungs.push(Rung {
                comment: format!("{}: event {}", tr.id, events[t]),
                condition: Element::Series(condition),
                coils,
            });
            rungs.extend(timer);
        }
        for (s, e, target) in &auto_transitions {
            let bit = event_var(e).cloned().unwrap_or_default();
            let mut coils =
                vec![coil(&id.state[*s], CoilKind::Reset), coil(&id.state[*target], CoilKind::Set)];
            if aeem.contains(e) {
                coils.push(coil(&bit, CoilKind::Reset));
            }
            rungs.push(Rung {
                comment: format!("supervisor {} -{e}-> {}", sup.states[*s].name, sup.states[*target].name),
                condition: Element::Series(vec![
                    Element::contact(id.state[*s].clone(), false),
                    Element::contact(bit, false),
                ]),
                coils,
            });
        }
        for (k, s) in net.signals.iter().enumerate() {
            if s.direction != Direction::Output {
                continue;
            }
            let places: Vec<Element> = net
                .actions
                .iter()
                .enumerate()
                .filter(|(_, sets)| sets.contains(&(k, true)))
                .map(|(p, _)| Element::contact(id.place[p].clone(), false))
                .collect();
            rungs.push(Rung {
                comment: format!("action: {} while a place naming it is marked", s.name),
                condition: Element::Parallel(places),
                coils: vec![coil(&id.signal[k], CoilKind::Out)],
            });
        }
        let mut end: Vec<Coil> = id.event.iter().map(|v| coil(v, CoilKind::Reset)).collect();
        end.push(coil(&id.fired, CoilKind::Reset));
        rungs.push(Rung {
            comment: "end of scan: every event bit (AEEM's last step) and this scan's firing".into(),
            condition: Element::Series(Vec::new()),
            coils: end,
        });

        let mut bools = vec![
            (id.init.clone(), "the initial marking is set".to_owned()),
            (id.fired.clone(), "a plant transition fired in this scan".to_owned()),
        ];
        bools.extend(
            net.net.places.iter().zip(&id.place).map(|(p, v)| (v.clone(), format!("plant place {}", p.id))),
        );
        bools.extend(
            sup.states
                .iter()
                .zip(&id.state)
                .map(|(s, v)| (v.clone(), format!("supervisor state {}", s.name))),
        );
        bools.extend(
            distinct
                .iter()
                .zip(&id.event)
                .map(|(e, v)| (v.clone(), format!("event {e} occurred (read by the auto-net)"))),
        );
        let timers = net
            .net
            .transitions
            .iter()
            .enumerate()
            .filter_map(|(t, tr)| Some((id.timer[t].clone()?, tr.id.clone(), net.delays[t])))
            .collect();
        let signals = net.signals.iter().zip(&id.signal).map(|(s, v)| (v.clone(), s.direction)).collect();
        Controller {
            rungs,
            inhibitors,
            auto_transitions,
            aeem,
            bools,
            timers,
            signals,
            states: sup.states.len(),
        }
    }
}
