//! A sequence net as PLC code: token passing in Structured Text (a function block) and a Sequential
//! Function Chart in PLCopen TC6 XML (DESIGN §11, "Code").
//!
//! **Token passing** (`<name>_net`, a `FUNCTION_BLOCK`): a `BOOL` per place, initialised to its marking;
//! per transition, in net order, one statement — `IF NOT fired AND` its input places `AND NOT` its
//! inhibitor places `AND` its condition `AND` every carried action of its input places already holding
//! (the RTPN's output enabling, read from the actuators' feedback inputs `<signal>_is`) `THEN` clear the
//! input places, set the output places, `fired := TRUE`. At most one transition fires per scan, as the
//! firing rule has it, so a token never runs through two transitions in one scan. Then the place
//! actions: each output signal set to the value of a marked place that names it (the outputs keep their
//! value when no marked place names them). The interlocks' program runs beside it and turns a demanded
//! value into its event when the supervisors allow it.
//!
//! **SFC** (`<name>_main`, a `PROGRAM` with an SFC body): a step per place, a transition per net
//! transition with its condition (and the output enabling) inline in ST, selection divergences and
//! convergences where a place has several transitions out or in, simultaneous ones where a transition
//! has several places in or out, an action block per step setting its outputs (qualifier N).
//!
//! Only safe nets are written (initial markings and arc weights of at most 1): a place is a `BOOL`.
//! Delays are not written: as in the seed paper, timeouts are input signals of their own.

use std::fmt::Write as _;

use super::names::Names;
use super::st::{Expr, Op, Pou, Section, SectionKind, Stmt, Type, Var, VarClass};
use super::PlcError;
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
        Idents { place, signal, feedback, step }
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
    terms.retain(|e| *e != Expr::Bool(true));
    Expr::fold(terms, Op::And, Expr::Bool(true))
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
    let mut passing = vec![Stmt::set("fired", Expr::Bool(false))];
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
        name: format!("{name}_net"),
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

/// The SFC program `<name>_main`: its signals (and the actuators' feedback) as local variables; its
/// body, the `<SFC>` of [`sfc_body`], is written beside an ST body that only says so.
pub fn sfc_program(net: &Interpretation, name: &str) -> Result<(Pou, String), PlcError> {
    let body = sfc_body(net)?;
    let id = Idents::new(net);
    let mut vars = Vec::new();
    for (k, s) in net.signals.iter().enumerate() {
        vars.push(Var::new(&id.signal[k], Type::Bool, format!("signal {}", s.name)));
        if s.direction == Direction::Output && s.carried {
            vars.push(Var::new(&id.feedback[k], Type::Bool, format!("the actuator {} now", s.name)));
        }
    }
    let pou = Pou {
        program: true,
        name: format!("{name}_main"),
        vars: vec![(VarClass::Local, vars)],
        sections: vec![Section {
            kind: SectionKind::Run,
            title: "the net runs as the SFC body".into(),
            stmts: Vec::new(),
        }],
    };
    Ok((pou, format!("<SFC>\n{body}        </SFC>")))
}

/// The net's files: `<name>_net.st` (the token-passing function block) and `<name>_net.xml` (a PLCopen
/// project holding the function block and the SFC program, run by a cyclic task every `cycle_ms`);
/// `header` goes into both.
pub fn files(
    net: &Interpretation,
    name: &str,
    cycle_ms: u32,
    header: &[String],
) -> Result<Vec<(String, String)>, PlcError> {
    let fb = token_passing(net, name)?;
    let (sfc, body) = sfc_program(net, name)?;
    super::strict::check(&[], &[&fb, &sfc])?;
    let st = format!("{}\n{}", super::comment(header), fb.text());
    let xml = super::xml::document(None, &[(&fb, &[]), (&sfc, &[body])], name, cycle_ms, header);
    Ok(vec![(format!("{name}_net.st"), st), (format!("{name}_net.xml"), xml)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::Manifest;
    use crate::model::testing::build;
    use crate::model::EventTable;
    use crate::net::model::{Net, Place, Transition};
    use std::path::Path;

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
        let a = build(
            "A",
            &["0", "1"],
            &["af1", "af0"],
            &[("0", "af1", "1"), ("1", "af0", "0"), ("0", "sr1", "0")],
        );
        let table = EventTable::build([&a]).unwrap();
        let text = "name = \"x\"\n[net]\npnml = \"n.pnml\"\n[net.conditions]\nt0 = \"sr\"\n[net.actions]\np1 = { af = 1 }\n";
        let m = Manifest::parse(Path::new("m.toml"), text).unwrap();
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
}
