//! A sequence net as PLC code beside the interlocks, in one program (DESIGN §11, "Code"): token
//! passing in Structured Text, a Sequential Function Chart in PLCopen TC6 XML, and the `PROGRAM` that
//! calls the sequence and then the interlocks' block.
//!
//! **Token passing** (`<name>_seq`, a `FUNCTION_BLOCK`): a `BOOL` per place, initialised to its marking;
//! per transition, in net order, one statement — `IF NOT fired AND` its input places `AND NOT` its
//! inhibitor places `AND` its condition `AND` every carried action of its input places already holding
//! (the RTPN's output enabling, read from the actuators' feedback inputs `is_<signal>`) `THEN` clear the
//! input places, set the output places, `fired := TRUE`. At most one transition fires per scan, as the
//! firing rule has it, so a token never runs through two transitions in one scan. Then the place
//! actions: each output signal set to the value of a marked place that names it (the outputs keep their
//! value when no marked place names them).
//!
//! **SFC** (the same block in the XML, its body an `<SFC>`): a step per place, a transition per net
//! transition with its condition (and the output enabling) inline in ST, selection divergences and
//! convergences where a place has several transitions out or in, simultaneous ones where a transition
//! has several places in or out, an action block per step setting its outputs (qualifier N).
//!
//! **One program** ([`beside`]): the sequence *requests*, the interlocks *allow* — the seed paper's
//! structure. The interlocks' block is built with a `req_<event>` input per controllable event
//! ([`super::PlcOptions::requests`]): an event is enabled when every supervisor allows it *and* it is
//! requested. The `PROGRAM` calls the sequence (sensors from their input variables, actuators' feedback
//! from their output variables, free inputs from variables of its own), then the interlocks' block with
//! `req_<s>1 := seq.<s> AND NOT <s>` and `req_<s>0 := NOT seq.<s> AND <s>` per demanded actuator, then
//! copies the outputs. A demanded command the supervisors disable waits, requested, until they allow it.
//!
//! **Delays** (`[net.delays]`): a transition with a delay D also waits until its input places have been
//! marked for D — in the ST an on-delay timer per such transition (`T_<id> : TON`, called each scan
//! with `IN :=` its input places, `PT := T#<D>ms`; its `Q` joins the enabling), in the SFC the steps'
//! elapsed time (`step_<p>.T >= T#<D>ms` per input place).
//!
//! Only safe nets are written (initial markings and arc weights of at most 1): a place is a `BOOL`.

use std::fmt::Write as _;

use super::io::Source;
use super::names::Names;
use super::st::{Expr, Op, Pou, Section, SectionKind, Stmt, Type, Var, VarClass};
use super::{PlcError, Program};
use crate::config::{Action, Edge};
use crate::formats::xml_escape;
use crate::net::condition;
use crate::net::interpretation::{Direction, Interpretation};

/// The identifiers of a net's program, unique without regard to case and clear of the keywords (a
/// signal called `sr`, the standard's bistable block, becomes `e_sr`): what a program calling the block
/// connects.
pub struct Idents {
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
}

impl Idents {
    /// The identifiers of `net`'s program.
    pub fn new(net: &Interpretation) -> Idents {
        let mut names = Names::default();
        names.reserve("fired");
        let place = net.net.places.iter().map(|p| names.fresh("P", &p.id)).collect();
        let signal = net.signals.iter().map(|s| names.plain(&s.name)).collect();
        let feedback = net.signals.iter().map(|s| names.fresh("is", &s.name)).collect();
        let step = net.net.places.iter().map(|p| names.fresh("step", &p.id)).collect();
        let timer = net.net.transitions.iter().map(|t| names.fresh("T", &t.id)).collect();
        Idents { place, signal, feedback, step, timer }
    }
}

/// Checks that `net` can be written: a safe net.
fn check(net: &Interpretation) -> Result<(), PlcError> {
    for p in &net.net.places {
        if p.initial > 1 {
            return Err(PlcError::Value(format!(
                "net: place '{}' starts with {} tokens; only safe nets are written",
                p.id, p.initial
            )));
        }
    }
    for t in &net.net.transitions {
        if t.inputs.iter().chain(&t.outputs).chain(&t.inhibitors).any(|&(_, w)| w > 1) {
            return Err(PlcError::Value(format!(
                "net: transition '{}' has an arc of weight above 1; only safe nets are written",
                t.id
            )));
        }
    }
    Ok(())
}

/// Y(t) as an ST expression over the signal variables.
fn condition(id: &Idents, e: &condition::Expr<usize>) -> Expr {
    match e {
        condition::Expr::Const(b) => Expr::Bool(*b),
        condition::Expr::Var(s) => Expr::var(&id.signal[*s]),
        condition::Expr::Not(x) => !condition(id, x),
        condition::Expr::And(xs) => {
            Expr::fold(xs.iter().map(|x| condition(id, x)), Op::And, Expr::Bool(true))
        }
        condition::Expr::Or(xs) => Expr::fold(xs.iter().map(|x| condition(id, x)), Op::Or, Expr::Bool(false)),
    }
}

/// The whole enabling of transition `t` besides `fired`: input places, inhibitors, condition, output
/// enabling.
fn enabling(net: &Interpretation, id: &Idents, t: usize, with_places: bool) -> Expr {
    let tr = &net.net.transitions[t];
    let mut terms = Vec::new();
    if with_places {
        terms.extend(tr.inputs.iter().map(|&(p, _)| Expr::var(&id.place[p])));
        terms.extend(tr.inhibitors.iter().map(|&(p, _)| !Expr::var(&id.place[p])));
    }
    terms.push(condition(id, &net.conditions[t]));
    for &(p, _) in &tr.inputs {
        for &(s, v) in &net.actions[p] {
            if net.signals[s].carried {
                let is = Expr::var(&id.feedback[s]);
                terms.push(if v { is } else { !is });
            }
        }
    }
    let delay = net.delays[t];
    if delay > 0 {
        if with_places {
            terms.push(Expr::var(format!("{}.Q", id.timer[t])));
        } else {
            let elapsed = |p: usize| Expr::var(format!("{}.T", id.step[p])).op(Op::Ge, Expr::Time(delay));
            terms.extend(tr.inputs.iter().map(|&(p, _)| elapsed(p)));
        }
    }
    terms.retain(|e| *e != Expr::Bool(true));
    Expr::fold(terms, Op::And, Expr::Bool(true))
}

/// The on-delay timers' calls: per transition with a delay, `T_<id>(IN := <its input places>, PT := …)`.
/// A delay counts from the moment every input place is marked, as an SFC step's elapsed time `.T` does.
fn timers(net: &Interpretation, id: &Idents) -> Vec<Stmt> {
    let delayed = net.net.transitions.iter().enumerate().filter(|&(t, _)| net.delays[t] > 0);
    delayed
        .map(|(t, tr)| {
            let marked = Expr::fold(
                tr.inputs.iter().map(|&(p, _)| Expr::var(&id.place[p])),
                Op::And,
                Expr::Bool(true),
            );
            Stmt::Call(
                id.timer[t].clone(),
                vec![("IN".into(), marked), ("PT".into(), Expr::Time(net.delays[t]))],
            )
        })
        .collect()
}

/// The token-passing function block `<name>_net`.
pub fn token_passing(net: &Interpretation, name: &str) -> Result<Pou, PlcError> {
    check(net)?;
    let id = Idents::new(net);
    let mut inputs = Vec::new();
    let mut outputs = Vec::new();
    for (k, s) in net.signals.iter().enumerate() {
        match s.direction {
            Direction::Input => {
                inputs.push(Var::new(&id.signal[k], Type::Bool, format!("input signal {}", s.name)))
            }
            Direction::Output => {
                outputs.push(Var::new(
                    &id.signal[k],
                    Type::Bool,
                    format!("{}, demanded by the marked places", s.name),
                ));
                if s.carried {
                    inputs.push(Var::new(
                        &id.feedback[k],
                        Type::Bool,
                        format!("the actuator {} now", s.name),
                    ));
                }
            }
        }
    }
    let mut locals: Vec<Var> = net
        .net
        .places
        .iter()
        .enumerate()
        .map(|(k, p)| {
            Var::new(&id.place[k], Type::Bool, format!("place {}", p.id)).init(Expr::Bool(p.initial == 1))
        })
        .collect();
    locals.push(Var::new("fired", Type::Bool, "a transition fired this scan"));
    for (t, tr) in net.net.transitions.iter().enumerate().filter(|&(t, _)| net.delays[t] > 0) {
        let what = format!("transition {}: its input places marked for {} ms", tr.id, net.delays[t]);
        locals.push(Var::new(&id.timer[t], Type::Named("TON".into()), what));
    }
    let mut passing = timers(net, &id);
    passing.push(Stmt::set("fired", Expr::Bool(false)));
    for (t, tr) in net.net.transitions.iter().enumerate() {
        let mut body: Vec<Stmt> =
            tr.inputs.iter().map(|&(p, _)| Stmt::set(&id.place[p], Expr::Bool(false))).collect();
        body.extend(tr.outputs.iter().map(|&(p, _)| Stmt::set(&id.place[p], Expr::Bool(true))));
        body.push(Stmt::set("fired", Expr::Bool(true)));
        let cond = (!Expr::var("fired")).op(Op::And, enabling(net, &id, t, true));
        passing.push(Stmt::when(cond, body));
    }
    let mut actions = Vec::new();
    for (s, _) in net.signals.iter().enumerate().filter(|(_, s)| s.direction == Direction::Output) {
        for value in [true, false] {
            let places = net
                .actions
                .iter()
                .enumerate()
                .filter(|(_, acts)| acts.contains(&(s, value)))
                .map(|(p, _)| Expr::var(&id.place[p]));
            let any = Expr::fold(places, Op::Or, Expr::Bool(false));
            if any != Expr::Bool(false) {
                actions.push(Stmt::when(any, vec![Stmt::set(&id.signal[s], Expr::Bool(value))]));
            }
        }
    }
    Ok(Pou {
        program: false,
        name: format!("{name}_seq"),
        vars: vec![(VarClass::Input, inputs), (VarClass::Output, outputs), (VarClass::Local, locals)],
        sections: vec![
            Section {
                kind: SectionKind::Transitions,
                title: "token passing, one transition per scan".into(),
                stmts: passing,
            },
            Section { kind: SectionKind::Outputs, title: "place actions".into(), stmts: actions },
        ],
    })
}

/// Local ids of the SFC's elements.
struct Ids {
    next: u64,
}

impl Ids {
    fn take(&mut self) -> u64 {
        self.next += 1;
        self.next
    }
}

/// The `<SFC>` body of the net: steps, transitions, divergences and convergences, action blocks.
pub fn sfc_body(net: &Interpretation) -> Result<String, PlcError> {
    check(net)?;
    let id = Idents::new(net);
    let (np, nt) = (net.net.places.len(), net.net.transitions.len());
    let mut ids = Ids { next: 0 };
    let step_id: Vec<u64> = (0..np).map(|_| ids.take()).collect();
    let trans_id: Vec<u64> = (0..nt).map(|_| ids.take()).collect();
    let ins =
        |p: usize| (0..nt).filter(move |&t| net.net.transitions[t].outputs.iter().any(|&(q, _)| q == p));
    let outs =
        |p: usize| (0..nt).filter(move |&t| net.net.transitions[t].inputs.iter().any(|&(q, _)| q == p));
    // What feeds a step: a transition's output (through a simultaneous divergence when it has several
    // places out) — one source, or a selection convergence of several.
    let mut out = String::new();
    let pos = |x: u64, y: u64| format!("<position x=\"{}\" y=\"{}\"/>", x * 40, y * 40);
    let conn = |ids: &[(u64, Option<String>)]| -> String {
        let mut s = String::new();
        for (id, formal) in ids {
            let f = formal.as_ref().map(|f| format!(" formalParameter=\"{f}\"")).unwrap_or_default();
            let _ = write!(s, "<connection refLocalId=\"{id}\"{f}/>");
        }
        s
    };
    // Output point of transition t toward place p: the transition itself, or its simultaneous divergence.
    let mut trans_out: Vec<Vec<(usize, u64, Option<String>)>> = vec![Vec::new(); nt];
    for (t, tr) in net.net.transitions.iter().enumerate() {
        if tr.outputs.len() > 1 {
            let div = ids.take();
            let _ = writeln!(
                out,
                "          <simultaneousDivergence localId=\"{div}\">{}<connectionPointIn>{}</connectionPointIn>{}</simultaneousDivergence>",
                pos(2 * t as u64 + 1, 3),
                conn(&[(trans_id[t], None)]),
                tr.outputs.iter().enumerate().map(|(k, _)| format!("<connectionPointOut formalParameter=\"o{k}\"/>")).collect::<String>()
            );
            for (k, &(p, _)) in tr.outputs.iter().enumerate() {
                trans_out[t].push((p, div, Some(format!("o{k}"))));
            }
        } else if let Some(&(p, _)) = tr.outputs.first() {
            trans_out[t].push((p, trans_id[t], None));
        }
    }
    // Output point of place p toward transition t: the step, or its selection divergence.
    let mut step_out: Vec<Vec<(usize, u64, Option<String>)>> = vec![Vec::new(); np];
    for p in 0..np {
        let targets: Vec<usize> = outs(p).collect();
        if targets.len() > 1 {
            let div = ids.take();
            let _ = writeln!(
                out,
                "          <selectionDivergence localId=\"{div}\">{}<connectionPointIn>{}</connectionPointIn>{}</selectionDivergence>",
                pos(2 * p as u64, 2),
                conn(&[(step_id[p], None)]),
                targets.iter().enumerate().map(|(k, _)| format!("<connectionPointOut formalParameter=\"s{k}\"/>")).collect::<String>()
            );
            for (k, &t) in targets.iter().enumerate() {
                step_out[p].push((t, div, Some(format!("s{k}"))));
            }
        } else if let Some(&t) = targets.first() {
            step_out[p].push((t, step_id[p], None));
        }
    }
    for p in 0..np {
        let feeds: Vec<(u64, Option<String>)> = ins(p)
            .flat_map(|t| trans_out[t].iter().filter(|(q, _, _)| *q == p).map(|(_, id, f)| (*id, f.clone())))
            .collect();
        let input = match feeds.len() {
            0 => String::new(),
            1 => format!("<connectionPointIn>{}</connectionPointIn>", conn(&feeds)),
            _ => {
                let conv = ids.take();
                let points: String = feeds
                    .iter()
                    .map(|f| {
                        format!("<connectionPointIn>{}</connectionPointIn>", conn(std::slice::from_ref(f)))
                    })
                    .collect();
                let _ = writeln!(
                    out,
                    "          <selectionConvergence localId=\"{conv}\">{}{points}<connectionPointOut/></selectionConvergence>",
                    pos(2 * p as u64, 0)
                );
                format!("<connectionPointIn>{}</connectionPointIn>", conn(&[(conv, None)]))
            }
        };
        let pl = &net.net.places[p];
        let has_out = if step_out[p].is_empty() { "" } else { "<connectionPointOut formalParameter=\"\"/>" };
        let _ = writeln!(
            out,
            "          <step localId=\"{}\" name=\"{}\" initialStep=\"{}\">{}{input}{has_out}<connectionPointOutAction formalParameter=\"\"/></step>",
            step_id[p],
            id.step[p],
            pl.initial == 1,
            pos(2 * p as u64, 1)
        );
        let body: String = net.actions[p]
            .iter()
            .map(|&(s, v)| format!("{} := {};", id.signal[s], if v { "TRUE" } else { "FALSE" }))
            .collect::<Vec<_>>()
            .join(" ");
        if !body.is_empty() {
            let (block, action) = (ids.take(), ids.take());
            let _ = writeln!(
                out,
                "          <actionBlock localId=\"{block}\">{}<connectionPointIn>{}</connectionPointIn><action localId=\"{action}\" qualifier=\"N\"><relPosition x=\"0\" y=\"0\"/><inline><ST><xhtml:p><![CDATA[{body}]]></xhtml:p></ST></inline></action></actionBlock>",
                pos(2 * p as u64 + 1, 1),
                conn(&[(step_id[p], None)])
            );
        }
    }
    for (t, tr) in net.net.transitions.iter().enumerate() {
        let feeds: Vec<(u64, Option<String>)> = tr
            .inputs
            .iter()
            .flat_map(|&(p, _)| {
                step_out[p].iter().filter(|(u, _, _)| *u == t).map(|(_, id, f)| (*id, f.clone()))
            })
            .collect();
        let input = if feeds.len() > 1 {
            let conv = ids.take();
            let points: String = feeds
                .iter()
                .map(|f| format!("<connectionPointIn>{}</connectionPointIn>", conn(std::slice::from_ref(f))))
                .collect();
            let _ = writeln!(
                out,
                "          <simultaneousConvergence localId=\"{conv}\">{}{points}<connectionPointOut/></simultaneousConvergence>",
                pos(2 * t as u64 + 1, 1)
            );
            format!("<connectionPointIn>{}</connectionPointIn>", conn(&[(conv, None)]))
        } else {
            format!("<connectionPointIn>{}</connectionPointIn>", conn(&feeds))
        };
        let cond = enabling(net, &id, t, false).text();
        let output = if tr.outputs.is_empty() { "" } else { "<connectionPointOut/>" };
        let _ = writeln!(
            out,
            "          <transition localId=\"{}\">{}{input}{output}<condition><inline name=\"{}\"><ST><xhtml:p><![CDATA[{cond}]]></xhtml:p></ST></inline></condition></transition>",
            trans_id[t],
            pos(2 * t as u64 + 1, 2),
            xml_escape(&tr.id)
        );
    }
    Ok(out)
}

/// The sequence as a function block with an SFC body: the interface of [`token_passing`]'s block (so
/// the program calls either form alike), no statements, and the `<SFC>` of [`sfc_body`].
pub fn sfc_block(net: &Interpretation, name: &str) -> Result<(Pou, String), PlcError> {
    let body = sfc_body(net)?;
    let mut pou = token_passing(net, name)?;
    pou.vars.retain(|(class, _)| *class != VarClass::Local);
    pou.sections.clear();
    Ok((pou, format!("<SFC>\n{body}        </SFC>")))
}

/// The sequence beside the interlocks in one PLC program ([`super::generate_with_sequence`]).
pub struct Sequence {
    /// The token-passing function block (`<name>_seq`), for the ST file.
    pub block: Pou,
    /// The same block with an SFC body (its interface, no statements) and that body, for the XML.
    pub sfc: (Pou, String),
    /// The one `PROGRAM`: the sequence called, then the interlocks' block with the sequence's requests,
    /// then the outputs.
    pub main: Pou,
}

/// Where a signal the automata carry lives in the interlocks' program: a sensor's level is its input
/// variable (negated where the variable's rising edge is the signal's falling one); an actuator's value
/// is the output variable its events set and clear. Both edges must meet in one variable.
fn level(net: &Interpretation, program: &Program, k: usize) -> Result<Expr, PlcError> {
    let signal = &net.signals[k];
    let missing = || {
        let wanted = match signal.direction {
            Direction::Input => "a sensor: map its events to one input variable in [[plc.inputs]]",
            Direction::Output => {
                "an actuator: map its events to one output variable, set and clear, in [[plc.outputs]]"
            }
        };
        PlcError::Value(format!("net: signal '{}' has no variable in [plc]; it is {wanted}", signal.name))
    };
    let mut found: Option<(&str, bool)> = None;
    for value in [true, false] {
        let Some(e) = net.event_for(k, value) else { continue };
        let here = match signal.direction {
            Direction::Input => match program.io.sources.get(&e) {
                Some(Source::Input { variable, edge, .. }) => {
                    (variable.as_str(), (*edge == Edge::Falling) == value)
                }
                _ => return Err(missing()),
            },
            Direction::Output => {
                let act = if value { Action::Set } else { Action::Clear };
                let o =
                    program.io.outputs.iter().find(|o| o.actions.iter().any(|&(x, a, _)| x == e && a == act));
                (o.ok_or_else(missing)?.variable.as_str(), false)
            }
        };
        if found.is_some_and(|(v, _)| v != here.0) {
            return Err(missing());
        }
        found = Some(here);
    }
    let (variable, negated) = found.ok_or_else(missing)?;
    Ok(if negated { !Expr::var(variable) } else { Expr::var(variable) })
}

/// The sequence and the interlocks' `program` (built with requests) as one PLC program: see
/// [`Sequence`]. Each scan the `PROGRAM` calls the sequence with the sensors' input variables, the
/// actuators' output variables as feedback and the free inputs; then the interlocks' block, whose
/// `req_<event>` is the sequence's demand: an actuator's event is requested while the sequence demands
/// the value it gives and the output does not have it yet (an event of an actuator no place action
/// names is always requested: the interlocks alone decide it, as the verification lets it happen);
/// then the outputs, and the lamps from the sequence.
pub fn beside(net: &Interpretation, program: &Program, name: &str) -> Result<Sequence, PlcError> {
    let block = token_passing(net, name)?;
    let sfc = sfc_block(net, name)?;
    let id = Idents::new(net);
    let mut main = program.main.clone();
    let taken: Vec<String> =
        main.vars.iter().flat_map(|(_, vs)| vs.iter().map(|v| v.name.to_ascii_uppercase())).collect();
    let mut own = Vec::new();
    let declare = |own: &mut Vec<Var>, v: Var| -> Result<(), PlcError> {
        if taken.contains(&v.name.to_ascii_uppercase())
            || own.iter().any(|w: &Var| w.name.eq_ignore_ascii_case(&v.name))
        {
            return Err(PlcError::Duplicate(v.name));
        }
        own.push(v);
        Ok(())
    };
    declare(&mut own, Var::new("seq", Type::Named(block.name.clone()), "the sequence net"))?;
    let mut args = Vec::new();
    let mut lamps = Vec::new();
    // The sensors a condition reads and the actuators a place action names: only theirs are passed
    // (the block's other inputs are read by nothing), so only they need a variable in [plc].
    let read: Vec<usize> = net.conditions.iter().flat_map(|c| c.vars()).copied().collect();
    let demanded: Vec<usize> = (0..net.signals.len())
        .filter(|&k| net.actions.iter().any(|a| a.iter().any(|&(s, _)| s == k)))
        .collect();
    for (k, s) in net.signals.iter().enumerate() {
        match (s.direction, s.carried) {
            (Direction::Input, true) if read.contains(&k) => {
                args.push((id.signal[k].clone(), level(net, program, k)?))
            }
            (Direction::Output, true) if demanded.contains(&k) => {
                args.push((id.feedback[k].clone(), level(net, program, k)?))
            }
            (_, true) => {}
            (Direction::Input, false) => {
                let mut v = Var::new(
                    &id.signal[k],
                    Type::Bool,
                    format!("input {} (no automaton carries it)", s.name),
                );
                if let crate::net::condition::Value::Is(b) = s.initial {
                    v = v.init(Expr::Bool(b));
                }
                declare(&mut own, v)?;
                args.push((id.signal[k].clone(), Expr::var(&id.signal[k])));
            }
            (Direction::Output, false) => {
                declare(
                    &mut own,
                    Var::new(&id.signal[k], Type::Bool, format!("lamp {}, set by the sequence", s.name)),
                )?;
                lamps.push(Stmt::set(&id.signal[k], Expr::var(format!("seq.{}", id.signal[k]))));
            }
        }
    }
    let mut requests = Vec::new();
    for (e, req) in &program.requests {
        let (k, value) = net.edges[e.index()];
        let ask = if demanded.contains(&k) {
            let out = level(net, program, k)?;
            let want = Expr::var(format!("seq.{}", id.signal[k]));
            if value {
                want.op(Op::And, !out)
            } else {
                (!want).op(Op::And, out)
            }
        } else {
            Expr::Bool(true)
        };
        requests.push((req.clone(), ask));
    }
    let names: Vec<&str> = requests.iter().map(|(r, _)| r.as_str()).collect();
    for (_, vars) in &mut main.vars {
        vars.retain(|v| !names.contains(&v.name.as_str()));
    }
    let run = &mut main.sections[0].stmts;
    for stmt in run.iter_mut() {
        if let Stmt::Call(_, call) = stmt {
            for (arg, value) in call.iter_mut() {
                if let Some((_, ask)) = requests.iter().find(|(r, _)| r == arg) {
                    *value = ask.clone();
                }
            }
        }
    }
    run.insert(0, Stmt::Call("seq".into(), args));
    run.extend(lamps);
    main.sections[0].title = "the sequence, the interlocks with its requests, the outputs".into();
    main.vars.push((VarClass::Local, own));
    Ok(Sequence { block, sfc, main })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::Manifest;
    use crate::model::testing::build;
    use crate::model::EventTable;
    use crate::net::model::{Net, Place, Transition};
    use std::path::Path;

    /// The manifest of the tests: the net's interpretation and a `[plc]` section (`plc` appended).
    fn manifest(plc: &str) -> Manifest {
        let text = format!("name = \"x\"\n[net]\npnml = \"n.pnml\"\n[net.conditions]\nt0 = \"sr\"\n[net.actions]\np1 = {{ af = 1 }}\n{plc}");
        Manifest::parse(Path::new("m.toml"), &text).unwrap()
    }

    /// The plant of the tests: an actuator `af` and a sensor edge `sr1`.
    fn plant() -> crate::model::Automaton {
        build("A", &["0", "1"], &["af1", "af0"], &[("0", "af1", "1"), ("1", "af0", "0"), ("0", "sr1", "0")])
    }

    /// p0 –t0 (sr)→ p1 –t1→ p0, with a second way out of p0 (t2 into p1 and p2): p1 demands `af`.
    fn net() -> Interpretation {
        let t = |id: &str, inputs: Vec<(usize, u32)>, outputs: Vec<(usize, u32)>| Transition {
            id: id.into(),
            inputs,
            outputs,
            ..Transition::default()
        };
        let n = Net {
            name: "n".into(),
            places: (0..3).map(|i| Place { id: format!("p{i}"), initial: u32::from(i == 0) }).collect(),
            transitions: vec![
                t("t0", vec![(0, 1)], vec![(1, 1)]),
                t("t1", vec![(1, 1)], vec![(0, 1)]),
                t("t2", vec![(0, 1)], vec![(1, 1), (2, 1)]),
            ],
        };
        let a = plant();
        let table = EventTable::build([&a]).unwrap();
        let m = manifest("");
        Interpretation::bind(m.net.as_ref().unwrap(), &m.file, n, &table).unwrap()
    }

    #[test]
    fn token_passing_fires_one_transition_per_scan_behind_output_enabling() {
        let fb = token_passing(&net(), "n").unwrap();
        let body = fb.body();
        assert!(body.contains("IF NOT fired AND P_p0 AND e_sr THEN\n    P_p0 := FALSE;\n    P_p1 := TRUE;\n    fired := TRUE;\nEND_IF;"), "{body}");
        assert!(body.contains("IF NOT fired AND P_p1 AND is_af THEN"), "t1 waits for af: {body}");
        assert!(body.contains("IF P_p1 THEN\n    af := TRUE;\nEND_IF;"), "{body}");
        assert_eq!(fb.var("e_sr").map(|(c, _)| c), Some(VarClass::Input), "sr is the SR block's name");
        super::super::strict::check(&[], &[&fb]).unwrap();
    }

    #[test]
    fn the_sfc_diverges_and_converges_where_the_net_does() {
        let sfc = sfc_body(&net()).unwrap();
        assert_eq!(sfc.matches("<step ").count(), 3);
        assert_eq!(sfc.matches("<selectionDivergence ").count(), 1, "p0 has two ways out");
        assert_eq!(sfc.matches("<selectionConvergence ").count(), 1, "p1 has two ways in");
        assert_eq!(sfc.matches("<simultaneousDivergence ").count(), 1, "t2 marks two places");
        assert!(sfc.contains("initialStep=\"true\"") && sfc.contains("af := TRUE;"));
        let weighted = Interpretation {
            net: Net { places: vec![Place { id: "p".into(), initial: 2 }], ..Net::default() },
            ..net()
        };
        assert!(token_passing(&weighted, "w").unwrap_err().to_string().contains("only safe nets"));
    }

    /// The one program: the sequence first, its demand as the interlocks' requests, the sensor's input
    /// variable as the sequence's input and the actuator's output as its feedback; a sensor reaching the
    /// interlocks only as an `EVENTS` member has no level the sequence could read, and is refused.
    #[test]
    fn the_sequence_requests_and_the_interlocks_allow_in_one_program() {
        let outputs = "[[plc.outputs]]\nevent = \"af1\"\nvariable = \"af\"\naction = \"set\"\n[[plc.outputs]]\nevent = \"af0\"\nvariable = \"af\"\naction = \"clear\"\n";
        let input = "[[plc.inputs]]\nevent = \"sr1\"\nvariable = \"x_sr\"\nedge = \"falling\"\n";
        let set = crate::pack::PackSet::new(vec![plant()], Vec::new()).unwrap();
        let generate = |plc: &str| {
            let m = manifest(&format!("[plc]\npolicy = \"first\"\n{plc}"));
            let opts = crate::plc::PlcOptions::new("x", &Default::default(), m.plc.as_ref(), None).unwrap();
            let net =
                Interpretation::bind(m.net.as_ref().unwrap(), &m.file, net().net, set.events()).unwrap();
            crate::plc::generate_with_sequence(&set, &opts, &Default::default(), &net)
        };
        let out = generate(&format!("{outputs}{input}")).unwrap();
        let main = out.program.main.body();
        let seq = main.find("seq(is_af := af, e_sr := NOT x_sr);").expect(&main);
        let sct = main
            .find("sct(x_sr := x_sr, req_af1 := seq.af AND NOT af, req_af0 := NOT seq.af AND af")
            .expect(&main);
        assert!(seq < sct, "the sequence decides before the interlocks: {main}");
        assert!(
            out.program.fb.body().contains("enabled[0] := st_A = 0 AND req_af1;"),
            "{}",
            out.program.fb.body()
        );
        assert!(out.files[0].1.contains("FUNCTION_BLOCK x_seq") && out.files[2].1.contains("<SFC>"));
        let err = generate(outputs).unwrap_err().to_string();
        assert!(err.contains("net: signal 'sr' has no variable in [plc]; it is a sensor"), "{err}");
    }
}
