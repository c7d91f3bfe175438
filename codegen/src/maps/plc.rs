//! `[plc]` against the set's events, and its addresses against the standard's grammar.

use std::collections::BTreeMap;

use crate::config::{Action, Edge, PlcSpec};
use crate::manifest::Key;
use crate::model::suggest::did_you_mean;
use crate::model::EventTable;

use super::address::{Address, Area};
use super::{Changes, Problems};

/// Whether `area` is one a variable of this role may sit in: an input is read from `%I` (or memory),
/// an output written to `%Q` (or memory).
fn fits(area: Area, input: bool) -> bool {
    matches!((area, input), (Area::Input, true) | (Area::Output, false) | (Area::Memory, _))
}

/// `text` at `key` as the address of a variable of that role; a problem (and `None`) when it is none.
pub(super) fn address(key: &Key, text: &str, input: bool, p: &mut Problems) -> Option<Address> {
    match Address::bit(text) {
        Err(why) => {
            p.at(key, why);
            None
        }
        Ok(a) if !fits(a.area, input) => {
            let (role, want) =
                if input { ("an input", "%IX (or %MX)") } else { ("an output", "%QX (or %MX)") };
            let area = if a.area == Area::Input { "a physical input" } else { "a physical output" };
            p.at(key, format!("'{text}' is {area}, and this is {role}: its address is {want}"));
            None
        }
        Ok(a) => Some(a),
    }
}

/// Which changes of a variable an edge takes: rising, falling.
fn changes(edge: Edge) -> (bool, bool) {
    match edge {
        Edge::Rising => (true, false),
        Edge::Falling => (false, true),
        Edge::Both => (true, true),
    }
}

/// One variable as the entries so far declare it: its role, its first entry, its address and that
/// entry.
struct Variable {
    input: bool,
    first: Key,
    address: Option<(Address, Key)>,
}

/// Checks the events, addresses and variables of `spec`.
pub(super) fn check(spec: &PlcSpec, events: &EventTable, p: &mut Problems) {
    let base = Key::new("plc");
    let names = || events.ids().map(|e| events.name(e));
    let event = |key: &Key, name: &str, want_controllable: bool, what: &str, p: &mut Problems| match events
        .id(name)
    {
        None => p.at(key, format!("'{name}' is not an event of the set{}", did_you_mean(name, names()))),
        Some(e) if events.is_controllable(e) != want_controllable => p.at(
            key,
            format!(
                "'{name}' is {}: {what}",
                if want_controllable { "uncontrollable" } else { "controllable" }
            ),
        ),
        Some(_) => {}
    };
    let mut variables: BTreeMap<String, Variable> = BTreeMap::new();
    let mut at_address: BTreeMap<Address, (String, Key)> = BTreeMap::new();
    // A variable at `key` of the role `input`, located at `text` if given: one role per variable, one
    // address per variable, one variable per address.
    let mut declare = |key: &Key, variable: &str, input: bool, text: Option<&str>, p: &mut Problems| {
        let v = variables.entry(variable.to_ascii_uppercase()).or_insert_with(|| Variable {
            input,
            first: key.clone(),
            address: None,
        });
        if v.input != input {
            p.at(
                &key.field("variable"),
                format!(
                    "'{variable}' is {} ({}) and {} here: one variable, one direction",
                    if v.input { "an input" } else { "an output" },
                    v.first,
                    if input { "an input" } else { "an output" }
                ),
            );
            return;
        }
        let Some(text) = text else { return };
        let Some(a) = address(&key.field("address"), text, input, p) else { return };
        match &v.address {
            Some((other, at)) if *other != a => p.at(
                &key.field("address"),
                format!("'{variable}' is already at {other} ({at}): one variable, one address"),
            ),
            Some(_) => {}
            None => v.address = Some((a, key.clone())),
        }
        match at_address.get(&a) {
            Some((other, at)) if !other.eq_ignore_ascii_case(variable) => p.at(
                &key.field("address"),
                format!("{a} is already the address of '{other}' ({at}): one address, one variable"),
            ),
            Some(_) => {}
            None => {
                at_address.insert(a, (variable.to_owned(), key.clone()));
            }
        }
    };
    let mut edges: BTreeMap<String, Changes> = BTreeMap::new();
    let mut sources: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, input) in spec.inputs.iter().enumerate() {
        let key = base.field("inputs").item(i);
        event(
            &key.field("event"),
            &input.event,
            false,
            "an input's edge is an uncontrollable event (a sensor); a command drives a variable in [[plc.outputs]]",
            p,
        );
        match sources.get(input.event.as_str()) {
            Some(&first) => p.at(
                &key.field("event"),
                format!(
                    "'{}' already comes from plc.inputs[{first}]: one event, one input edge",
                    input.event
                ),
            ),
            None => {
                sources.insert(&input.event, i);
            }
        }
        declare(&key, &input.variable, true, input.address.as_deref(), p);
        let here = edges.entry(input.variable.to_ascii_uppercase()).or_default();
        if let Some((other, event, which)) = here.claim(key.clone(), &input.event, changes(input.edge)) {
            p.at(
                &key.field("edge"),
                format!(
                    "the {which} edge of '{}' would mean both '{event}' ({other}) and '{}': one edge, one \
                     event (one variable may carry one event rising and another falling)",
                    input.variable, input.event
                ),
            );
        }
    }
    let mut pulsed: BTreeMap<String, (usize, bool)> = BTreeMap::new();
    let mut driven: BTreeMap<(String, &str), usize> = BTreeMap::new();
    for (o, output) in spec.outputs.iter().enumerate() {
        let key = base.field("outputs").item(o);
        event(
            &key.field("event"),
            &output.event,
            true,
            "an output is driven by a controllable event (a command); a sensor's edge goes in [[plc.inputs]]",
            p,
        );
        declare(&key, &output.variable, false, output.address.as_deref(), p);
        let variable = output.variable.to_ascii_uppercase();
        match driven.get(&(variable.clone(), output.event.as_str())) {
            Some(&first) => p.at(
                &key.field("event"),
                format!("'{}' already drives '{}' (plc.outputs[{first}])", output.event, output.variable),
            ),
            None => {
                driven.insert((variable.clone(), &output.event), o);
            }
        }
        let pulse = output.action == Action::Pulse;
        match (output.action, output.scans) {
            (Action::Pulse, Some(n)) if !(1..=32_767).contains(&n) => p.at(
                &key.field("scans"),
                format!("a pulse of {n} scans: 1 to 32767 (the countdown is an INT)"),
            ),
            (Action::Set | Action::Clear, Some(_)) => p.at(
                &key.field("scans"),
                format!("goes with action = \"pulse\" only, not \"{}\"", output.action.name()),
            ),
            _ => {}
        }
        match pulsed.get(&variable) {
            Some(&(first, was)) if was != pulse => p.at(
                &key.field("action"),
                format!(
                    "'{}' is {} by plc.outputs[{first}]: a variable is driven by pulses or by set and \
                     clear, not both",
                    output.variable,
                    if was { "pulsed" } else { "set or cleared" }
                ),
            ),
            Some(_) => {}
            None => {
                pulsed.insert(variable, (o, pulse));
            }
        }
    }
    for (i, name) in spec.internal.iter().enumerate() {
        let key = base.field("internal").item(i);
        event(&key, name, true, "`internal` lists controllable events that drive no output", p);
        if let Some(o) = spec.outputs.iter().position(|o| o.event == *name) {
            p.at(&key, format!("'{name}' is listed in `internal` and drives an output (plc.outputs[{o}])"));
        }
    }
}
