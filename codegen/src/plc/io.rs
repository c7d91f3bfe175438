//! The `[plc]` I/O map checked against a set's events: per uncontrollable event where it comes from
//! (an input variable and its edge, or a member of the `EVENTS` structure), per output variable the
//! controllable events that drive it.

use std::collections::BTreeMap;

use crate::model::{EventId, EventTable};

use super::names::{is_identifier, Names};
use super::PlcError;
use crate::config::{Action, Edge, PlcSpec};

/// Where an uncontrollable event comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// An input variable of the program, and the edge that means the event.
    Input {
        /// Variable name.
        variable: String,
        /// Which change.
        edge: Edge,
        /// Located address.
        address: Option<String>,
    },
    /// A member of the `EVENTS` input structure; its rising edge is the event.
    Member(String),
}

/// One output variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    /// Variable name.
    pub variable: String,
    /// Located address.
    pub address: Option<String>,
    /// The events driving it, with their action and, for pulses, the length in scans.
    pub actions: Vec<(EventId, Action, u16)>,
}

impl Output {
    /// Whether the variable is driven by pulses (then by pulses only).
    pub fn pulsed(&self) -> bool {
        self.actions.iter().any(|&(_, a, _)| a == Action::Pulse)
    }
}

/// The checked map.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IoMap {
    /// Per uncontrollable event (by id), its source.
    pub sources: BTreeMap<EventId, Source>,
    /// Output variables in the order of their first mention.
    pub outputs: Vec<Output>,
}

impl IoMap {
    /// Checks `spec` against `events`; user-chosen names are reserved in `names`.
    pub fn new(spec: &PlcSpec, events: &EventTable, names: &mut Names) -> Result<IoMap, PlcError> {
        let id = |name: &str| events.id(name).ok_or_else(|| PlcError::UnknownEvent(name.to_owned()));
        let mut variable = |name: &str| {
            if !is_identifier(name) {
                return Err(PlcError::Identifier(name.to_owned()));
            }
            Ok(names.reserve(name))
        };
        let mut sources = BTreeMap::new();
        for i in &spec.inputs {
            let e = id(&i.event)?;
            if events.is_controllable(e) {
                return Err(PlcError::WrongKind {
                    event: i.event.clone(),
                    what: "controllable: it cannot be an input",
                });
            }
            if !variable(&i.variable)? {
                return Err(PlcError::Duplicate(i.variable.clone()));
            }
            let source =
                Source::Input { variable: i.variable.clone(), edge: i.edge, address: i.address.clone() };
            if sources.insert(e, source).is_some() {
                return Err(PlcError::Duplicate(i.event.clone()));
            }
        }
        let mut outputs: Vec<Output> = Vec::new();
        for o in &spec.outputs {
            let e = id(&o.event)?;
            if !events.is_controllable(e) {
                return Err(PlcError::WrongKind {
                    event: o.event.clone(),
                    what: "uncontrollable: it cannot drive an output",
                });
            }
            let scans = match (o.action, o.scans) {
                (Action::Pulse, None) => 1,
                (Action::Pulse, Some(n)) if n > 0 => n,
                (Action::Pulse, Some(_)) => {
                    return Err(PlcError::Value(format!("{}: pulse of 0 scans", o.event)))
                }
                (_, None) => 0,
                (_, Some(_)) => {
                    return Err(PlcError::Value(format!(
                        "{}: scans goes with action = \"pulse\" only",
                        o.event
                    )))
                }
            };
            match outputs.iter_mut().find(|x| x.variable == o.variable) {
                Some(x) => {
                    if x.pulsed() != (o.action == Action::Pulse) {
                        return Err(PlcError::Value(format!(
                            "{}: pulses and set/clear mixed on one variable",
                            o.variable
                        )));
                    }
                    if x.actions.iter().any(|&(y, ..)| y == e) {
                        return Err(PlcError::Duplicate(o.event.clone()));
                    }
                    if o.address.is_some() && o.address != x.address {
                        return Err(PlcError::Value(format!("{}: two addresses", o.variable)));
                    }
                    x.actions.push((e, o.action, scans));
                }
                None => {
                    if !variable(&o.variable)? {
                        return Err(PlcError::Duplicate(o.variable.clone()));
                    }
                    outputs.push(Output {
                        variable: o.variable.clone(),
                        address: o.address.clone(),
                        actions: vec![(e, o.action, scans)],
                    });
                }
            }
        }
        let mut members = Names::default();
        for e in events.ids().filter(|&e| !events.is_controllable(e)) {
            sources.entry(e).or_insert_with(|| Source::Member(members.plain(events.name(e))));
        }
        Ok(IoMap { sources, outputs })
    }

    /// The `EVENTS` members, by event.
    pub fn members(&self) -> impl Iterator<Item = (EventId, &str)> {
        self.sources.iter().filter_map(|(&e, s)| match s {
            Source::Member(m) => Some((e, m.as_str())),
            Source::Input { .. } => None,
        })
    }
}
