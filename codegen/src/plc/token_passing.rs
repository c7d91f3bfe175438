//! The one lowering of a Petri net into scan code (DESIGN §11 "Code", token passing logic): both the
//! sequence beside the interlocks ([`super::sequence`]) and the hybrid controller ([`super::hybrid`])
//! are written by it, so they share one identifier scheme, one reading of a condition, one meaning of a
//! delay and one safe-net check.
//!
//! **The net** must be safe ([`crate::net::safety`]): a place is one `BOOL`, `P_<id>`, initialised to
//! its marking. An unsafe or unbounded net is refused naming the place and a shortest firing sequence
//! that puts a second token there.
//!
//! **The rungs**, in this order (each a [`Rung`], written in ST by [`Rung::statements`] and in Ladder
//! Diagram by [`crate::scan::ld`]):
//!
//! 1. *timers* — per transition with a delay D, an on-delay timer `T_<id>` (`TON`) whose input is its
//!    input places, all marked: **a delay D means the transition fires once its input places have been
//!    marked for D without a break** (and its other conditions hold then). The timers run before any
//!    transition, so a scan sees a place emptied by the previous scan's firing before it is marked
//!    again, and the next token starts its timer afresh. A timer starts in the first scan that sees its
//!    places marked, so a delay is D to D plus one task interval. An SFC step's elapsed time `.T` means
//!    the same, which is how [`chart`] writes it.
//! 2. `fired := FALSE`.
//! 3. *firing* — per transition in net order: `NOT fired` AND its input places AND NOT its inhibitor
//!    places AND NOT the places of `blocked` (the hybrid's supervisor states) AND its condition (contacts,
//!    negations pushed to the signals) AND the output enabling (each carried output an input place sets
//!    already holds, read from the actuators' feedback `is_<signal>`) AND its timer's `Q` → RESET its
//!    input places, SET its output places and the coils of `also` (the hybrid's event bit), SET `fired`.
//!    At most one transition fires per scan, as the RTPN's firing rule has it, so a token never runs
//!    through two transitions in one scan.
//! 4. *actions* — [`Actions::Held`]: per output signal and value, the places that set it (SET or RESET
//!    coil), the value kept while no marked place names it (the RTPN's Z(p)); [`Actions::Level`]: per
//!    output, ON while a place that sets it is marked (an automation net's place action).

use crate::net::condition;
use crate::net::interpretation::{Direction, Interpretation};
use crate::net::{safety, NetError};
use crate::scan::ir::{Expr, Op, Stmt};
use crate::scan::ld::{Coil, CoilKind, Element, Rung};
use crate::scan::names::Names;
use crate::scan::sfc::{Chart, Step, Transition};

/// Most markings the safe-net check explores.
pub const MARKING_LIMIT: usize = 1_000_000;

/// The identifiers of a net's program, unique without regard to case and clear of the keywords (a
/// signal called `sr`, the standard's bistable block, becomes `e_sr`): what a program calling the block
/// connects. A form names its own variables with [`Idents::fresh`] after these.
pub struct Idents {
    /// `fired`: a transition fired this scan.
    pub fired: String,
    /// `P_<id>` per place.
    pub place: Vec<String>,
    /// Per signal, its variable.
    pub signal: Vec<String>,
    /// Per signal, the feedback input of a carried output (`is_<name>`: the value the actuator has now).
    pub feedback: Vec<String>,
    /// Per place, its SFC step name.
    pub step: Vec<String>,
    /// Per transition, the name of its on-delay timer (`T_<id>`; declared where it has a delay).
    pub timer: Vec<String>,
    names: Names,
}

impl Idents {
    /// The identifiers of `net`'s program.
    pub fn new(net: &Interpretation) -> Idents {
        let mut names = Names::default();
        let fired = names.plain("fired");
        let place = net.net.places.iter().map(|p| names.fresh("P", &p.id)).collect();
        let signal = net.signals.iter().map(|s| names.plain(&s.name)).collect();
        let feedback = net.signals.iter().map(|s| names.fresh("is", &s.name)).collect();
        let step = net.net.places.iter().map(|p| names.fresh("step", &p.id)).collect();
        let timer = net.net.transitions.iter().map(|t| names.fresh("T", &t.id)).collect();
        Idents { fired, place, signal, feedback, step, timer, names }
    }

    /// A further identifier, `prefix_name`, unique among them all.
    pub fn fresh(&mut self, prefix: &str, name: &str) -> String {
        self.names.fresh(prefix, name)
    }

    /// A further identifier, `name` itself when free.
    pub fn plain(&mut self, name: &str) -> String {
        self.names.plain(name)
    }
}

/// How place actions drive the outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Actions {
    /// A marked place sets its signals to its values; a signal no marked place names keeps its value
    /// (the RTPN's Z(p): a sequence's actuators).
    Held,
    /// An output is on while a place that sets it is marked, off otherwise (an automation net's place
    /// actions: the hybrid's motors).
    Level,
}

/// The net's token passing as rungs, in the order of the module documentation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lowered {
    /// The on-delay timers.
    pub timers: Vec<Rung>,
    /// `fired := FALSE`, then one rung per transition.
    pub firing: Vec<Rung>,
    /// The place actions.
    pub actions: Vec<Rung>,
}

impl Lowered {
    /// Every rung, top to bottom.
    pub fn rungs(&self) -> impl Iterator<Item = &Rung> {
        self.timers.iter().chain(&self.firing).chain(&self.actions)
    }

    /// The rungs as ST, top to bottom.
    pub fn statements(&self) -> Vec<Stmt> {
        self.rungs().flat_map(Rung::statements).collect()
    }
}

/// Refuses `net` unless a program can keep each of its places in one bit.
pub fn check(net: &Interpretation) -> Result<(), NetError> {
    safety::check(&net.net, MARKING_LIMIT)
}

/// Y(t) as contacts: negations pushed down to the signals (a normally closed contact), `TRUE` a plain
/// wire (an empty series), `FALSE` an open branch (an empty parallel).
pub fn condition(e: &condition::Expr<usize>, negate: bool, signal: &[String]) -> Element {
    match e {
        condition::Expr::Const(b) if *b != negate => Element::Series(Vec::new()),
        condition::Expr::Const(_) => Element::Parallel(Vec::new()),
        condition::Expr::Var(s) => Element::contact(signal[*s].clone(), negate),
        condition::Expr::Not(x) => condition(x, !negate, signal),
        condition::Expr::And(xs) | condition::Expr::Or(xs) => {
            let parts = xs.iter().map(|x| condition(x, negate, signal)).collect();
            if matches!(e, condition::Expr::And(_)) != negate {
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

/// What enables transition `t` besides its marking, its delay and `fired`: its condition and its
/// output enabling.
fn enabling(net: &Interpretation, id: &Idents, t: usize) -> Vec<Element> {
    let mut terms = Vec::new();
    match condition(&net.conditions[t], false, &id.signal) {
        Element::Series(es) if es.is_empty() => {}
        c => terms.push(c),
    }
    for &(p, _) in &net.net.transitions[t].inputs {
        for &(s, v) in &net.actions[p] {
            if net.signals[s].carried {
                terms.push(Element::contact(id.feedback[s].clone(), !v));
            }
        }
    }
    terms
}

/// The token passing of `net` (see the module documentation): `blocked[t]` are further contacts that
/// keep transition `t` from firing while closed (normally open: written negated), `also[t]` further coils
/// its firing sets; both may be empty.
pub fn lower(
    net: &Interpretation,
    id: &Idents,
    actions: Actions,
    blocked: &[Vec<String>],
    also: &[Vec<String>],
) -> Result<Lowered, NetError> {
    check(net)?;
    let transitions = &net.net.transitions;
    let timers = transitions
        .iter()
        .enumerate()
        .filter(|&(t, _)| net.delays[t] > 0)
        .map(|(t, tr)| Rung {
            comment: format!("{}: on-delay of {} ms (its input places marked)", tr.id, net.delays[t]),
            condition: Element::Series(
                tr.inputs.iter().map(|&(p, _)| Element::contact(id.place[p].clone(), false)).collect(),
            ),
            coils: vec![coil(&id.timer[t], CoilKind::OnDelay(net.delays[t]))],
        })
        .collect();
    let mut firing = vec![Rung {
        comment: "no transition fired yet this scan".into(),
        condition: Element::Series(Vec::new()),
        coils: vec![coil(&id.fired, CoilKind::Reset)],
    }];
    for (t, tr) in transitions.iter().enumerate() {
        let mut cond = vec![Element::contact(id.fired.clone(), true)];
        cond.extend(tr.inputs.iter().map(|&(p, _)| Element::contact(id.place[p].clone(), false)));
        cond.extend(tr.inhibitors.iter().map(|&(p, _)| Element::contact(id.place[p].clone(), true)));
        cond.extend(blocked.get(t).into_iter().flatten().map(|v| Element::contact(v.clone(), true)));
        cond.extend(enabling(net, id, t));
        if net.delays[t] > 0 {
            cond.push(Element::contact(format!("{}.Q", id.timer[t]), false));
        }
        let mut coils: Vec<Coil> =
            tr.inputs.iter().map(|&(p, _)| coil(&id.place[p], CoilKind::Reset)).collect();
        coils.extend(tr.outputs.iter().map(|&(p, _)| coil(&id.place[p], CoilKind::Set)));
        coils.extend(also.get(t).into_iter().flatten().map(|v| coil(v, CoilKind::Set)));
        coils.push(coil(&id.fired, CoilKind::Set));
        firing.push(Rung { comment: format!("{}: fires", tr.id), condition: Element::Series(cond), coils });
    }
    let mut rungs = Vec::new();
    for (s, signal) in net.signals.iter().enumerate().filter(|(_, s)| s.direction == Direction::Output) {
        let values: &[bool] = match actions {
            Actions::Held => &[true, false],
            Actions::Level => &[true],
        };
        for &value in values {
            let places: Vec<Element> = net
                .actions
                .iter()
                .enumerate()
                .filter(|(_, acts)| acts.contains(&(s, value)))
                .map(|(p, _)| Element::contact(id.place[p].clone(), false))
                .collect();
            let kind = match (actions, value) {
                (Actions::Level, _) => CoilKind::Out,
                (Actions::Held, true) => CoilKind::Set,
                (Actions::Held, false) => CoilKind::Reset,
            };
            if places.is_empty() && actions == Actions::Held {
                continue;
            }
            rungs.push(Rung {
                comment: match actions {
                    Actions::Held => {
                        format!("action: {} := {value} while a place naming it is marked", signal.name)
                    }
                    Actions::Level => format!("action: {} while a place naming it is marked", signal.name),
                },
                condition: Element::Parallel(places),
                coils: vec![coil(&id.signal[s], kind)],
            });
        }
    }
    Ok(Lowered { timers, firing, actions: rungs })
}

/// The net as a Sequential Function Chart: a step per place (`step_<id>`, the marked ones initial), a
/// transition per net transition with its condition and output enabling, its delay as the elapsed
/// time of each input step (`step_<p>.T >= T#<D>ms`: the same meaning as the token passing's timer),
/// and each step's held actions (`signal := value;`).
pub fn chart(net: &Interpretation, id: &Idents) -> Result<Chart, NetError> {
    check(net)?;
    let steps = net
        .net
        .places
        .iter()
        .enumerate()
        .map(|(p, place)| Step {
            name: id.step[p].clone(),
            initial: place.initial == 1,
            actions: net.actions[p]
                .iter()
                .map(|&(s, v)| Stmt::set(id.signal[s].clone(), Expr::Bool(v)))
                .collect(),
        })
        .collect();
    let transitions = net
        .net
        .transitions
        .iter()
        .enumerate()
        .map(|(t, tr)| {
            let mut terms: Vec<Expr> = enabling(net, id, t).iter().map(Element::st).collect();
            if net.delays[t] > 0 {
                let elapsed = Expr::Time(net.delays[t]);
                terms.extend(
                    tr.inputs
                        .iter()
                        .map(|&(p, _)| Expr::var(format!("{}.T", id.step[p])).op(Op::Ge, elapsed.clone())),
                );
            }
            Transition {
                name: tr.id.clone(),
                from: tr.inputs.iter().map(|&(p, _)| p).collect(),
                to: tr.outputs.iter().map(|&(p, _)| p).collect(),
                condition: Expr::fold(terms, Op::And, Expr::Bool(true)),
            }
        })
        .collect();
    Ok(Chart { steps, transitions })
}
