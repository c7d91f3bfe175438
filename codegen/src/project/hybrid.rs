//! The stages of a hybrid controller's project (a manifest with a `[hybrid]` section, docs/hybrid.md):
//! its `[net]` is the plant — read, labelled by `[hybrid]`, and its reachability graph the plant
//! automaton the manifest's specifications are read against — and its supervisor is supC of those
//! specifications against that plant, or one ready supervisor checked against it. The event-based
//! runtimes run the graph beside the arrivals its controllable transitions wait for ([`arrivals()`]).

use std::path::Path;

use crate::manifest::{Manifest, ModelSet};
use crate::model::{Automaton, Kind};
use crate::net::arrivals;
use crate::net::reachability::{reachability, Labels};
use crate::net::{read_pnml, Interpretation, NetError};
use crate::plc::hybrid::Plant;
use crate::plc::PlcError;
use crate::synth::{self, Config};

use super::ProjectError;

/// The plant of the hybrid manifest `m`: its net with the interpretation of `[net]`, the labels of
/// `[hybrid]` and the reachability graph (at most `cfg`'s state limit).
pub fn plant(m: &Manifest, cfg: &Config) -> Result<Plant, ProjectError> {
    let sections = || PlcError::Sections { file: m.file.clone() };
    let (spec, hybrid) = (m.net.as_ref().ok_or_else(sections)?, m.hybrid.as_ref().ok_or_else(sections)?);
    let net = read_pnml(&m.resolve(spec.pnml.get_ref())).map_err(|e| plc(NetError::from(e)))?;
    let table = crate::model::EventTable::build([]).map_err(|e| plc(NetError::from(e)))?;
    let net = Interpretation::bind(spec, &m.file, net, &table).map_err(plc)?;
    let labels = Labels::bind(spec, hybrid, &m.file, &net.net).map_err(plc)?;
    let graph =
        reachability(&net.net, &labels, &format!("G_{}", net.net.name), cfg.state_limit).map_err(plc)?;
    Ok(Plant { net, labels, graph })
}

/// The plant automata of the arrivals the controllable transitions of the hybrid manifest `m`'s
/// `plant` wait for ([`arrivals::arrivals`]): the plants an event-based runtime runs beside the graph.
pub fn arrivals(m: &Manifest, plant: &Plant) -> Result<Vec<Automaton>, ProjectError> {
    let spec = m.net.as_ref().ok_or_else(|| plc(PlcError::Sections { file: m.file.clone() }))?;
    arrivals::arrivals(spec, &m.file, &plant.net, &plant.labels).map_err(plc)
}

/// A net's error as the PLC wing's.
fn plc(e: impl Into<PlcError>) -> ProjectError {
    ProjectError::Plc(Box::new(e.into()))
}

/// The hybrid controller's supervisor (`SUPER`): supC of the manifest's specifications against the
/// plant, or its one ready supervisor, checked against it (one automaton, the net's events, controllable
/// and nonblocking with it).
pub fn supervisor(
    m: &Manifest,
    models: &ModelSet,
    plant: &Plant,
    cfg: &Config,
) -> Result<Automaton, ProjectError> {
    let graph = std::slice::from_ref(&plant.graph);
    let mut sup = match (models.specs.as_slice(), m.supervisors.as_slice()) {
        (specs, []) if !specs.is_empty() => {
            let sup = synth::supc(graph, specs, cfg).map_err(plc)?;
            if sup.states.is_empty() {
                return Err(plc(PlcError::NoSupervisor { file: m.file.clone() }));
            }
            sup
        }
        ([], [one]) => given(&m.resolve(one), &models.supervisors, plant, cfg)?,
        (specs, supervisors) => {
            return Err(plc(PlcError::Source {
                file: m.file.clone(),
                specs: specs.len(),
                supervisors: supervisors.len(),
            }))
        }
    };
    sup.name = "SUPER".into();
    Ok(sup)
}

/// The ready supervisor read from `file` (`read`), checked against the net's reachability graph: one
/// automaton, its events the net's, it never refuses an uncontrollable event the net can generate, and
/// the closed loop is nonblocking — so that the controller written on it keeps what synthesis would
/// have guaranteed.
fn given(file: &Path, read: &[Automaton], plant: &Plant, cfg: &Config) -> Result<Automaton, ProjectError> {
    let labels = &plant.labels;
    let mut sup = match read {
        [one] => one.clone(),
        many => {
            return Err(plc(PlcError::Given {
                file: file.to_owned(),
                name: file.display().to_string(),
                problem: format!(
                    "the file holds {} automata, a hybrid controller takes one supervisor",
                    many.len()
                ),
            }))
        }
    };
    sup.kind = Kind::Supervisor;
    let problem =
        |problem: String| plc(PlcError::Given { file: file.to_owned(), name: sup.name.clone(), problem });
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
    let plants = std::slice::from_ref(&plant.graph);
    if let Some(u) = synth::verify::controllability(plants, &sup, cfg).map_err(plc)? {
        return Err(problem(format!(
            "not controllable: after {} it refuses the uncontrollable '{}' the net can generate (state {})",
            trace(&u.trace),
            u.event,
            u.state
        )));
    }
    if let Some(b) = synth::verify::nonblocking(&[plant.graph.clone(), sup.clone()], cfg).map_err(plc)? {
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
