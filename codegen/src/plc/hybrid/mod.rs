//! The hybrid controller (Uzam & Gelen 2013): the plant is an automation Petri net (conditions on its
//! transitions, actions on its places, on-delays), the specifications are automata over the events its
//! transitions generate; the supervisor is synthesised against the net's reachability graph, reduced,
//! turned into an auto-net and coupled to the net by inhibitor arcs from its control data, and the whole
//! is written as Ladder Diagram (and the same rungs in ST) — once with the reduced supervisor, once with
//! the full one, side by side in the report as the paper's Table 4.
//!
//! | part | module |
//! |---|---|
//! | the coupled net as rungs: auto-net, inhibitor arcs, AEEM bits, timers | [`controller`] |
//! | the figures of one controller and the report of both | [`report`] |
//!
//! [`generate`] runs the steps from a manifest with `[net]` and `[hybrid]` sections.

pub mod controller;
pub mod report;

use std::path::{Path, PathBuf};

pub use controller::Controller;
pub use report::{Figures, Report};

use super::ld::{self, CoilKind, Element, Rung};
use super::st::{Expr, Pou, Section, SectionKind, Stmt, Type, Var, VarClass};
use super::{comment, names, strict, xml};
use crate::formats::ParseError;
use crate::manifest::Manifest;
use crate::model::{Automaton, EventTable, Kind};
use crate::net::interpretation::{Direction, Interpretation};
use crate::net::reachability::{reachability, Labels};
use crate::net::{read_pnml, NetError};
use crate::synth::{self, Config, SynthError};

/// Why a hybrid controller could not be written; each names the file (and line where there is one).
#[derive(Debug, thiserror::Error)]
pub enum HybridError {
    /// The manifest has no `[net]` or no `[hybrid]` section.
    #[error("{}: a hybrid controller needs the sections [net] (the plant's automation net) and [hybrid] (its transitions' events)", file.display())]
    Sections {
        /// The manifest.
        file: PathBuf,
    },
    /// A name of the `[hybrid]` section is wrong.
    #[error("{}:{line}: {message}", file.display())]
    Spec {
        /// The manifest.
        file: PathBuf,
        /// The line of the key or value.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The net, its interpretation or its reachability graph.
    #[error(transparent)]
    Net(#[from] NetError),
    /// A specification file.
    #[error(transparent)]
    Parse(#[from] ParseError),
    /// Synthesis, reduction or the control data.
    #[error(transparent)]
    Synth(#[from] SynthError),
    /// No supervisor exists: the specifications forbid what the net cannot be kept from.
    #[error("{}: no supervisor exists: the specifications cannot be enforced on the net (supC is empty)", file.display())]
    Empty {
        /// The manifest.
        file: PathBuf,
    },
    /// The manifest gives no specification and no supervisor, both, or more than one supervisor.
    #[error("{}: a hybrid controller takes either `specs` (its supervisor is synthesised) or one ready supervisor in `supervisors`; {specs} specification file(s) and {supervisors} supervisor file(s) given", file.display())]
    Source {
        /// The manifest.
        file: PathBuf,
        /// How many specification files it lists.
        specs: usize,
        /// How many supervisor files it lists.
        supervisors: usize,
    },
    /// The ready supervisor cannot control the net: an event no transition generates, an uncontrollable
    /// event it refuses, or a state of the closed loop from which no marked state is reachable.
    #[error("{}: supervisor '{name}': {problem}", file.display())]
    Given {
        /// The supervisor's file.
        file: PathBuf,
        /// The supervisor.
        name: String,
        /// What is wrong, with a trace where there is one.
        problem: String,
    },
    /// The program breaks a rule of the standard: the writer's bug.
    #[error("internal error, please report: the program is not strict IEC 61131-3: {0}")]
    Strict(#[from] strict::Violation),
}

/// One controller with its supervisor: the full one or the reduced one.
#[derive(Clone, Debug)]
pub struct Side {
    /// The supervisor.
    pub supervisor: Automaton,
    /// Its control data: per state, the controllable events it disables.
    pub condat: Vec<Vec<String>>,
    /// The controller built on it.
    pub controller: Controller,
}

/// What [`generate`] writes and reports.
#[derive(Clone, Debug)]
pub struct Output {
    /// `(file name, contents)`: `<name>_hybrid.st`, `<name>_hybrid.xml` (reduced supervisor),
    /// `<name>_hybrid_full.st`, `<name>_hybrid_full.xml` (unreduced).
    pub files: Vec<(String, String)>,
    /// The plant net with its interpretation.
    pub net: Interpretation,
    /// The event of each net transition.
    pub events: Vec<String>,
    /// The net's reachability graph, the plant.
    pub plant: Automaton,
    /// The reduced controller.
    pub reduced: Side,
    /// The unreduced controller.
    pub full: Side,
    /// The report.
    pub report: Report,
}

/// The net of `manifest` with its interpretation and the event of each of its transitions (with
/// controllability).
fn load_net(manifest: &Manifest) -> Result<(Interpretation, Labels), HybridError> {
    let sections = || HybridError::Sections { file: manifest.file.clone() };
    let (spec, hybrid) =
        (manifest.net.as_ref().ok_or_else(sections)?, manifest.hybrid.as_ref().ok_or_else(sections)?);
    let net = read_pnml(&manifest.resolve(spec.pnml.get_ref()))?;
    let net =
        Interpretation::bind(spec, &manifest.file, net, &EventTable::build([]).map_err(NetError::from)?)?;
    let at = |span: std::ops::Range<usize>, message: String| HybridError::Spec {
        file: manifest.file.clone(),
        line: spec.line(span.start),
        message,
    };
    for key in hybrid.events.keys() {
        if net.net.transition(key.get_ref()).is_none() {
            return Err(at(
                key.span(),
                format!("hybrid.events.{}: the net has no such transition", key.get_ref()),
            ));
        }
    }
    let mut events = Vec::new();
    for t in &net.net.transitions {
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
    let controllable = events.iter().map(|e| hybrid.controllable.iter().any(|c| c.get_ref() == e)).collect();
    Ok((net, Labels { events, controllable }))
}

/// Reads the manifest's net and specifications, synthesises, reduces and writes both controllers.
pub fn generate(manifest: &Manifest, cfg: &Config, cycle_ms: u32) -> Result<Output, HybridError> {
    let (net, labels) = load_net(manifest)?;
    let plant = reachability(&net.net, &labels, &format!("G_{}", net.net.name), cfg.state_limit)?;
    let plants = std::slice::from_ref(&plant);
    let mut full = match (manifest.specs.as_slice(), manifest.supervisors.as_slice()) {
        (specs, []) if !specs.is_empty() => synthesise(manifest, &plant, cfg)?,
        ([], [one]) => given(&manifest.resolve(one), &plant, &labels, cfg)?,
        (specs, supervisors) => {
            return Err(HybridError::Source {
                file: manifest.file.clone(),
                specs: specs.len(),
                supervisors: supervisors.len(),
            })
        }
    };
    full.name = "SUPER".into();
    let mut reduced = synth::reduce(plants, &full, cfg)?;
    reduced.name = "RSUPER".into();
    let side = |sup: Automaton| -> Result<Side, HybridError> {
        let condat = synth::condat(plants, &sup, cfg)?;
        let controller = Controller::new(&net, &labels.events, &sup, &condat);
        Ok(Side { supervisor: sup, condat, controller })
    };
    let (reduced, full) = (side(reduced)?, side(full)?);
    let base = names::stem(&manifest.name);
    let header = vec![
        format!("@generated by codegen {} (`codegen plc`): do not edit.", env!("CARGO_PKG_VERSION")),
        format!(
            "Hybrid controller of '{}' ({}): the automation net {} coupled by inhibitor arcs to the auto-net of its supervisor.",
            manifest.name,
            manifest.file.display(),
            net.net.name
        ),
    ];
    let mut files = Vec::new();
    for (suffix, s) in [("hybrid", &reduced), ("hybrid_full", &full)] {
        let name = format!("{base}_{suffix}");
        let pou = pou(&s.controller, &name, &s.supervisor.name);
        strict::check(&[], &[&pou])?;
        let mut lines = header.clone();
        lines.push(format!(
            "Supervisor {}: {} states; report: docs/hybrid.md.",
            s.supervisor.name,
            s.supervisor.states.len()
        ));
        files.push((format!("{name}.st"), format!("{}\n{}", comment(&lines), pou.text())));
        let body = ld::body(&s.controller.rungs);
        files.push((format!("{name}.xml"), xml::document(None, &[(&pou, &[body])], &name, cycle_ms, &lines)));
    }
    let report = Report::new(&net, &plant, &reduced, &full);
    Ok(Output { files, net, events: labels.events, plant, reduced, full, report })
}

/// supC of the manifest's specifications against the net's reachability graph `plant`.
fn synthesise(manifest: &Manifest, plant: &Automaton, cfg: &Config) -> Result<Automaton, HybridError> {
    let mut specs = Vec::new();
    for p in &manifest.specs {
        for mut a in crate::formats::read_path(&manifest.resolve(p))? {
            a.kind = Kind::Spec;
            specs.push(a);
        }
    }
    let full = synth::supc(std::slice::from_ref(plant), &specs, cfg)?;
    if full.states.is_empty() {
        return Err(HybridError::Empty { file: manifest.file.clone() });
    }
    Ok(full)
}

/// The ready supervisor of `file`, checked against the net's reachability graph `plant`: its events are
/// the net's, it never refuses an uncontrollable event the net can generate, and the closed loop is
/// nonblocking — so that the controller written on it keeps what synthesis would have guaranteed.
fn given(file: &Path, plant: &Automaton, labels: &Labels, cfg: &Config) -> Result<Automaton, HybridError> {
    let mut read = crate::formats::read_path(file)?;
    let mut sup = match read.len() {
        1 => read.remove(0),
        n => {
            return Err(HybridError::Given {
                file: file.to_owned(),
                name: file.display().to_string(),
                problem: format!("the file holds {n} automata, a hybrid controller takes one supervisor"),
            })
        }
    };
    sup.kind = Kind::Supervisor;
    let problem =
        |problem: String| HybridError::Given { file: file.to_owned(), name: sup.name.clone(), problem };
    let foreign: Vec<&str> = sup
        .events
        .iter()
        .map(|e| e.name.as_str())
        .filter(|e| !labels.events.iter().any(|n| n == e))
        .collect();
    if !foreign.is_empty() {
        return Err(problem(format!("no transition of the net generates {}", foreign.join(", "))));
    }
    if sup.states.is_empty() {
        return Err(problem("it has no state".into()));
    }
    for e in &mut sup.events {
        if let Some(i) = labels.events.iter().position(|n| *n == e.name) {
            e.controllable = labels.controllable[i];
        }
    }
    let plants = std::slice::from_ref(plant);
    if let Some(u) = synth::verify::controllability(plants, &sup, cfg)? {
        return Err(problem(format!(
            "not controllable: after {} it refuses the uncontrollable '{}' the net can generate (state {})",
            trace(&u.trace),
            u.event,
            u.state
        )));
    }
    if let Some(b) = synth::verify::nonblocking(&[plant.clone(), sup.clone()], cfg)? {
        return Err(problem(format!(
            "the closed loop blocks: after {} no marked state is reachable (state {})",
            trace(&b.trace),
            b.state
        )));
    }
    Ok(sup)
}

/// A trace as words for a message.
fn trace(events: &[String]) -> String {
    if events.is_empty() {
        "the initial state".into()
    } else {
        events.join(" ")
    }
}

/// The controller as a `PROGRAM <name>_main`: its signals, bits and timers, one statement per rung.
fn pou(c: &Controller, name: &str, supervisor: &str) -> Pou {
    let mut vars: Vec<Var> = c
        .signals
        .iter()
        .map(|(v, d)| {
            Var::new(
                v.clone(),
                Type::Bool,
                if *d == Direction::Input { "sensor (input)" } else { "actuator (output)" },
            )
        })
        .collect();
    vars.extend(c.bools.iter().map(|(v, what)| Var::new(v.clone(), Type::Bool, what.clone())));
    vars.extend(c.timers.iter().map(|(v, t, ms)| {
        Var::new(v.clone(), Type::Named("TON".into()), format!("on-delay of {t}, {ms} ms"))
    }));
    Pou {
        program: true,
        name: format!("{name}_main"),
        vars: vec![(VarClass::Local, vars)],
        sections: vec![Section {
            kind: SectionKind::Rungs,
            title: format!(
                "initial marking, plant net, auto-net of {supervisor}, actions, end of scan: {} networks",
                c.rungs.len()
            ),
            stmts: c.rungs.iter().flat_map(statements).collect(),
        }],
    }
}

/// A rung as ST: `IF condition THEN` its SET/RESET coils, an `OUT` coil as an assignment, a timer as
/// its call.
fn statements(r: &Rung) -> Vec<Stmt> {
    let cond = r.condition.st();
    let mut out = Vec::new();
    let mut latched = Vec::new();
    for c in &r.coils {
        match c.kind {
            CoilKind::Set | CoilKind::Reset => {
                latched.push(Stmt::set(c.variable.clone(), Expr::Bool(c.kind == CoilKind::Set)))
            }
            CoilKind::Out => out.push(Stmt::set(c.variable.clone(), cond.clone())),
            CoilKind::OnDelay(ms) => out.push(Stmt::Call(
                c.variable.clone(),
                vec![("IN".into(), cond.clone()), ("PT".into(), Expr::Time(ms))],
            )),
        }
    }
    if !latched.is_empty() {
        if matches!(&r.condition, Element::Series(es) if es.is_empty()) {
            out.extend(latched);
        } else {
            out.push(Stmt::when(cond, latched));
        }
    }
    out
}

#[cfg(test)]
mod tests;
