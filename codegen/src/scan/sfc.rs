//! Sequential Function Charts (IEC 61131-3 6.7): steps, transitions with their conditions in ST, and
//! action blocks — the chart IR and its PLCopen TC6 2.01 `<SFC>` printer.
//!
//! A [`Chart`] is steps and transitions, each transition naming the steps it leaves and enters; the
//! printer draws the wiring the schema asks for: a selection divergence where a step has several
//! transitions out, a selection convergence where several transitions enter it, simultaneous ones
//! where a transition leaves or enters several steps, and an action block (qualifier N, inline ST) per
//! step with actions. Every object is numbered (`localId`) and wired to what feeds it; positions are a
//! plain grid (editors re-route). Output is deterministic.

use std::fmt::Write as _;

use super::ir::{Expr, Stmt};
use super::st::statements;
use crate::formats::xml_escape;

/// A step.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    /// Its name (`step.T` is its elapsed time, `step.X` whether it is active).
    pub name: String,
    /// Active in the initial situation.
    pub initial: bool,
    /// Statements run while it is active (one action block, qualifier N).
    pub actions: Vec<Stmt>,
}

/// A transition between steps.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Transition {
    /// Its name (the inline condition's).
    pub name: String,
    /// The steps it leaves (all must be active), by index.
    pub from: Vec<usize>,
    /// The steps it enters, by index.
    pub to: Vec<usize>,
    /// Its condition.
    pub condition: Expr,
}

/// A chart.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Chart {
    /// The steps, in order.
    pub steps: Vec<Step>,
    /// The transitions, in order.
    pub transitions: Vec<Transition>,
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

impl Chart {
    /// The chart as the contents of a PLCopen `<SFC>` body: steps, transitions, the divergences and
    /// convergences their arcs make, action blocks.
    pub fn body(&self) -> String {
        let (np, nt) = (self.steps.len(), self.transitions.len());
        let mut ids = Ids { next: 0 };
        let step_id: Vec<u64> = (0..np).map(|_| ids.take()).collect();
        let trans_id: Vec<u64> = (0..nt).map(|_| ids.take()).collect();
        let ins = |p: usize| (0..nt).filter(move |&t| self.transitions[t].to.contains(&p));
        let outs = |p: usize| (0..nt).filter(move |&t| self.transitions[t].from.contains(&p));
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
        for (t, tr) in self.transitions.iter().enumerate() {
            if tr.to.len() > 1 {
                let div = ids.take();
                let _ = writeln!(
                out,
                "          <simultaneousDivergence localId=\"{div}\">{}<connectionPointIn>{}</connectionPointIn>{}</simultaneousDivergence>",
                pos(2 * t as u64 + 1, 3),
                conn(&[(trans_id[t], None)]),
                tr.to.iter().enumerate().map(|(k, _)| format!("<connectionPointOut formalParameter=\"o{k}\"/>")).collect::<String>()
            );
                for (k, &p) in tr.to.iter().enumerate() {
                    trans_out[t].push((p, div, Some(format!("o{k}"))));
                }
            } else if let Some(&p) = tr.to.first() {
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
                .flat_map(|t| {
                    trans_out[t].iter().filter(|(q, _, _)| *q == p).map(|(_, id, f)| (*id, f.clone()))
                })
                .collect();
            let input = match feeds.len() {
                0 => String::new(),
                1 => format!("<connectionPointIn>{}</connectionPointIn>", conn(&feeds)),
                _ => {
                    let conv = ids.take();
                    let points: String = feeds
                        .iter()
                        .map(|f| {
                            format!(
                                "<connectionPointIn>{}</connectionPointIn>",
                                conn(std::slice::from_ref(f))
                            )
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
            let step = &self.steps[p];
            let has_out =
                if step_out[p].is_empty() { "" } else { "<connectionPointOut formalParameter=\"\"/>" };
            let _ = writeln!(
            out,
            "          <step localId=\"{}\" name=\"{}\" initialStep=\"{}\">{}{input}{has_out}<connectionPointOutAction formalParameter=\"\"/></step>",
            step_id[p],
            xml_escape(&step.name),
            step.initial,
            pos(2 * p as u64, 1)
        );
            let body: String = step
                .actions
                .iter()
                .map(|s| statements(std::slice::from_ref(s), 0).trim_end().to_owned())
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
        for (t, tr) in self.transitions.iter().enumerate() {
            let feeds: Vec<(u64, Option<String>)> = tr
                .from
                .iter()
                .flat_map(|&p| {
                    step_out[p].iter().filter(|(u, _, _)| *u == t).map(|(_, id, f)| (*id, f.clone()))
                })
                .collect();
            let input = if feeds.len() > 1 {
                let conv = ids.take();
                let points: String = feeds
                    .iter()
                    .map(|f| {
                        format!("<connectionPointIn>{}</connectionPointIn>", conn(std::slice::from_ref(f)))
                    })
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
            let cond = tr.condition.text();
            let output = if tr.to.is_empty() { "" } else { "<connectionPointOut/>" };
            let _ = writeln!(
            out,
            "          <transition localId=\"{}\">{}{input}{output}<condition><inline name=\"{}\"><ST><xhtml:p><![CDATA[{cond}]]></xhtml:p></ST></inline></condition></transition>",
            trans_id[t],
            pos(2 * t as u64 + 1, 2),
            xml_escape(&tr.name)
        );
        }
        out
    }
}
