//! The `[plc]` I/O map checked against a set's events: per uncontrollable event where it comes from
//! (an input variable and its edge, or a member of the `EVENTS` structure), per output variable the
//! controllable events that drive it.

use std::collections::BTreeMap;

use crate::model::suggest::did_you_mean;
use crate::model::{EventId, EventTable};

use super::PlcError;
use crate::config::{Action, Edge, PlcSpec};
use crate::scan::names::{is_identifier, Names};

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

/// One input variable as `[plc]` maps it: its name, its events with their edges, its address.
type Line = (String, Vec<(EventId, Edge)>, Option<String>);

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
    /// Checks `spec` against `events`; user-chosen names are reserved in `names`. With `complete`, every
    /// controllable event must drive an output or be listed in `[plc] internal`.
    pub fn new(
        spec: &PlcSpec,
        events: &EventTable,
        names: &mut Names,
        complete: bool,
    ) -> Result<IoMap, PlcError> {
        let id = |name: &str| {
            events.id(name).ok_or_else(|| PlcError::UnknownEvent {
                event: name.to_owned(),
                hint: did_you_mean(name, events.ids().map(|e| events.name(e))),
            })
        };
        let mut variable = |name: &str| {
            if !is_identifier(name) {
                return Err(PlcError::Identifier(name.to_owned()));
            }
            Ok(names.reserve(name))
        };
        // Per input variable: its events with their edges, and its address. One variable may carry an
        // event per edge (`sb1` rising, `sb0` falling of `sb`), never one change for two events.
        let mut lines: Vec<Line> = Vec::new();
        for i in &spec.inputs {
            let e = id(&i.event)?;
            if events.is_controllable(e) {
                return Err(PlcError::WrongKind {
                    event: i.event.clone(),
                    what: "controllable: it cannot be an input",
                });
            }
            match lines.iter_mut().find(|(v, ..)| *v == i.variable) {
                Some((_, edges, address)) => {
                    let clash =
                        edges.iter().find(|&&(_, x)| x == i.edge || x == Edge::Both || i.edge == Edge::Both);
                    if let Some(&(other, _)) = clash {
                        return Err(PlcError::Value(format!(
                            "{}: its {} edge would mean both '{}' and '{}'",
                            i.variable,
                            i.edge.name(),
                            events.name(other),
                            i.event
                        )));
                    }
                    if i.address.is_some() && address.is_some() && i.address != *address {
                        return Err(PlcError::Value(format!("{}: two addresses", i.variable)));
                    }
                    if address.is_none() {
                        address.clone_from(&i.address);
                    }
                    edges.push((e, i.edge));
                }
                None => {
                    if !variable(&i.variable)? {
                        return Err(PlcError::Duplicate(i.variable.clone()));
                    }
                    lines.push((i.variable.clone(), vec![(e, i.edge)], i.address.clone()));
                }
            }
        }
        let mut sources = BTreeMap::new();
        for (variable, edges, address) in &lines {
            for &(e, edge) in edges {
                let source = Source::Input { variable: variable.clone(), edge, address: address.clone() };
                if sources.insert(e, source).is_some() {
                    return Err(PlcError::Duplicate(events.name(e).to_owned()));
                }
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
                // The countdown is an INT (the program's other counters are INT too).
                (Action::Pulse, Some(n)) if (1..=32_767).contains(&n) => n,
                (Action::Pulse, Some(n)) => {
                    return Err(PlcError::Value(format!("{}: pulse of {n} scans (1 to 32767)", o.event)))
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
        let mut internal = Vec::new();
        for name in &spec.internal {
            let e = id(name)?;
            if !events.is_controllable(e) {
                return Err(PlcError::WrongKind {
                    event: name.clone(),
                    what: "uncontrollable: `internal` lists controllable events without an output",
                });
            }
            if outputs.iter().any(|o| o.actions.iter().any(|&(x, ..)| x == e)) {
                return Err(PlcError::Value(format!("{name}: listed in `internal` and mapped to an output")));
            }
            internal.push(e);
        }
        if complete {
            let driven = |e: EventId| outputs.iter().any(|o| o.actions.iter().any(|&(x, ..)| x == e));
            let unmapped: Vec<(String, String)> = events
                .ids()
                .filter(|&e| events.is_controllable(e) && !driven(e) && !internal.contains(&e))
                .map(|e| {
                    // The output variables: an event mapped under another event's name shows here.
                    let near = spec.outputs.iter().map(|o| o.variable.as_str());
                    (events.name(e).to_owned(), did_you_mean(events.name(e), near))
                })
                .collect();
            if !unmapped.is_empty() {
                return Err(PlcError::Unmapped(unmapped));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{PlcInput, PlcOutput};

    fn events() -> EventTable {
        let mut t = EventTable::default();
        for (name, controllable) in
            [("sb1", false), ("sb0", false), ("piston_out", true), ("piston_in", true)]
        {
            t.insert(name, controllable, "test").unwrap();
        }
        t
    }

    fn input(event: &str, variable: &str, edge: Edge, address: Option<&str>) -> PlcInput {
        PlcInput { event: event.into(), variable: variable.into(), edge, address: address.map(Into::into) }
    }

    fn output(event: &str, variable: &str) -> PlcOutput {
        PlcOutput {
            event: event.into(),
            variable: variable.into(),
            action: Action::Set,
            scans: None,
            address: None,
        }
    }

    fn map(spec: &PlcSpec) -> Result<IoMap, PlcError> {
        IoMap::new(spec, &events(), &mut Names::default(), true)
    }

    #[test]
    fn one_input_carries_the_events_of_both_its_edges_once_each() {
        let mut spec = PlcSpec {
            inputs: vec![
                input("sb1", "sb", Edge::Rising, Some("%IX0.0")),
                input("sb0", "sb", Edge::Falling, None),
            ],
            outputs: vec![output("piston_out", "piston"), output("piston_in", "arm")],
            ..PlcSpec::default()
        };
        let io = map(&spec).unwrap();
        let address = |e: u32| match &io.sources[&EventId::from_u32(e)] {
            Source::Input { variable, address, .. } => (variable.clone(), address.clone()),
            Source::Member(_) => unreachable!(),
        };
        assert_eq!(address(0), address(1), "one variable, one address");
        spec.inputs[1].edge = Edge::Rising;
        let err = map(&spec).unwrap_err().to_string();
        assert!(err.contains("sb: its rising edge would mean both 'sb1' and 'sb0'"), "{err}");
        spec.inputs[1].edge = Edge::Both;
        assert!(map(&spec).is_err(), "'both' shares no variable");
        spec.inputs[1] = input("sb0", "sb", Edge::Falling, Some("%IX0.1"));
        assert!(map(&spec).unwrap_err().to_string().contains("two addresses"));
    }

    #[test]
    fn a_controllable_event_without_output_is_named_unless_internal() {
        let mut spec = PlcSpec { outputs: vec![output("piston_out", "piston")], ..PlcSpec::default() };
        let err = map(&spec).unwrap_err().to_string();
        assert!(
            err.contains("controllable event 'piston_in' (did you mean 'piston'?) drives no output"),
            "{err}"
        );
        assert!(IoMap::new(&spec, &events(), &mut Names::default(), false).is_ok(), "no [plc] section");
        spec.internal = vec!["piston_in".into()];
        assert!(map(&spec).is_ok());
        spec.internal = vec!["piston_out".into()];
        assert!(map(&spec).unwrap_err().to_string().contains("piston_out: listed in `internal` and mapped"));
        spec.internal = vec!["sb1".into()];
        assert!(map(&spec).unwrap_err().to_string().contains("'sb1' is uncontrollable"));
        spec.internal = vec!["piston_inn".into()];
        let err = map(&spec).unwrap_err().to_string();
        assert!(
            err.contains("event 'piston_inn' is not an event of the set (did you mean 'piston_in'?)"),
            "{err}"
        );
        spec.internal.clear();
        spec.outputs.clear();
        let err = map(&spec).unwrap_err().to_string();
        assert!(err.contains("events 'piston_out', 'piston_in' drive no output"), "every one named: {err}");
    }
}
