//! The hybrid controller (Uzam & Gelen 2013): the plant is an automation Petri net (conditions on its
//! transitions, actions on its places, on-delays), the specifications are automata over the events its
//! transitions generate; the supervisor is synthesised against the net's reachability graph (by the
//! project's pipeline, `Project::load` of a `[hybrid]` manifest), reduced here, turned into an auto-net
//! and coupled to the net by inhibitor arcs from its control data, and the whole is written as Ladder
//! Diagram (and the same rungs in ST) — once with the reduced supervisor, once with the full one, side
//! by side in the report as the paper's Table 4.
//!
//! | part | module |
//! |---|---|
//! | the coupled net as rungs: auto-net, inhibitor arcs, AEEM bits, timers | [`controller`] |
//! | the coupled net as a place/transition net, checked against plant ‖ supervisor | [`coupled`] |
//! | the figures of one controller and the report of both | [`report`] |
//! | the plant net as a virtual plant: its token game, delays and sensors on the scan clock | [`plant`] |
//! | a controller run closed loop against that plant, judged by the monitor | [`closed_loop`] |
//!
//! [`generate`] writes both controllers of a plant net and its supervisor.

pub mod closed_loop;
pub mod controller;
pub mod coupled;
pub mod plant;
pub mod report;

pub use controller::Controller;
pub use report::{Figures, Report};

use super::PlcError;
use crate::model::Automaton;
use crate::net::interpretation::{Direction, Interpretation};
use crate::net::reachability::Labels;
use crate::provenance::Provenance;
use crate::scan::files::{File, Header, Source};
use crate::scan::ir::{Pou, Section, Type, Var, VarClass};
use crate::scan::names;
use crate::scan::{Graphic, Program};
use crate::synth::{self, Config};

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
    /// `(file name, contents)`: `<name>_hybrid.st`, `<name>_hybrid_config.st`, `<name>_hybrid.xml`
    /// (reduced supervisor), then the same three `<name>_hybrid_full` files (unreduced).
    pub files: Vec<File>,
    /// The two programs the files are written from, reduced first, for a vendor's printer.
    pub sources: Vec<Source>,
    /// The reduced controller.
    pub reduced: Side,
    /// The unreduced controller.
    pub full: Side,
    /// The report.
    pub report: Report,
}

/// The plant net of a hybrid controller: its interpretation, the event of each transition, and its
/// reachability graph (the plant of synthesis).
#[derive(Clone, Debug)]
pub struct Plant {
    /// The net with its interpretation (its signals: the `free` sensors and the `outputs` actuators).
    pub net: Interpretation,
    /// The event of each transition, with controllability.
    pub labels: Labels,
    /// The reachability graph as an automaton.
    pub graph: Automaton,
}

/// Writes the two controllers of the plant net `plant` under the supervisor `full` (synthesised, or
/// ready and checked): reduces it, takes both supervisors' control data, checks each coupled net against
/// plant ‖ `full` ([`coupled::check`]) and writes `<name>_hybrid` (reduced) and `<name>_hybrid_full`,
/// each task running every `cycle_ms`, under `provenance`.
pub fn generate(
    plant: &Plant,
    full: &Automaton,
    name: &str,
    cycle_ms: u32,
    provenance: &Provenance,
    cfg: &Config,
) -> Result<Output, PlcError> {
    let net = &plant.net;
    token_check(net)?;
    let plants = std::slice::from_ref(&plant.graph);
    let mut full = full.clone();
    full.name = "SUPER".into();
    let mut reduced = synth::reduce(plants, &full, cfg)?;
    reduced.name = "RSUPER".into();
    let side = |sup: Automaton| -> Result<Side, PlcError> {
        let condat = synth::condat(plants, &sup, cfg)?;
        let controller = Controller::new(net, &plant.labels.events, &sup, &condat)?;
        coupled::check(&net.net, &plant.labels, &plant.graph, &full, &sup, &controller.inhibitors, cfg)?;
        Ok(Side { supervisor: sup, condat, controller })
    };
    let (reduced, full) = (side(reduced)?, side(full.clone())?);
    let base = names::stem(name);
    let (mut files, mut sources) = (Vec::new(), Vec::new());
    for (suffix, which, s) in [("hybrid", "reduced", &reduced), ("hybrid_full", "full", &full)] {
        let header = Header {
            about: vec![format!(
                "Hybrid controller of '{name}': the automation net {} coupled by inhibitor arcs to the auto-net of its supervisor.",
                net.net.name
            )],
            provenance: provenance.clone(),
            options: vec![
                ("encoding", "hybrid".into()),
                ("supervisor", which.into()),
                ("cycle_ms", cycle_ms.to_string()),
            ],
            notes: vec![format!(
                "Supervisor {}: {} states; report: docs/hybrid.md.",
                s.supervisor.name,
                s.supervisor.states.len()
            )],
        };
        let stem = format!("{base}_{suffix}");
        let pou = pou(&s.controller, &stem, &s.supervisor.name);
        let program = Program {
            base: stem,
            types: Vec::new(),
            pous: vec![(pou, Graphic::Ladder(s.controller.rungs.clone()))],
            cycle_ms,
        };
        let source = Source { program, header };
        files.extend(source.files()?);
        sources.push(source);
    }
    let report = Report::new(net, &plant.graph, &reduced, &full);
    Ok(Output { files, sources, reduced, full, report })
}

/// Refuses a plant net the program cannot keep a place of in one bit, before anything is reduced.
fn token_check(net: &Interpretation) -> Result<(), PlcError> {
    Ok(super::token_passing::check(net)?)
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
        sections: vec![Section::new(
            "rungs",
            format!(
                "initial marking, plant net (timers, transitions), auto-net of {supervisor}, actions, end of scan: {} networks",
                c.rungs.len()
            ),
            c.rungs.iter().flat_map(|r| r.statements()).collect(),
        )],
    }
}
