//! `[state]` against the set's plants, its signals' addresses and pins.

use std::collections::BTreeMap;

use crate::config::StateSpec;
use crate::manifest::{Key, ModelSet};
use crate::model::suggest::did_you_mean;

use super::address::Address;
use super::pins::{Board, Pin};
use super::plc::address;
use super::Problems;

/// Checks `spec`: readable, one component per plant with a formula per state and a command per
/// controllable event, addresses and pins one per signal and of the signal's direction (pins on
/// `board`'s free pins when a board is known).
pub(super) fn check(spec: &StateSpec, models: &ModelSet, board: Option<Board>, p: &mut Problems) {
    if let Err(e) = spec.check() {
        p.at(&Key::parse(&e.key), e.message);
    }
    let base = Key::new("state").field("components");
    let plants = || models.plants.iter().map(|a| a.name.as_str());
    for plant in &models.plants {
        if !spec.components.contains_key(&plant.name) {
            p.at(&base, format!("plant '{}' has no state vector: add [state.components.{0}]", plant.name));
        }
    }
    let mut at_address: BTreeMap<Address, Key> = BTreeMap::new();
    let mut at_pin: BTreeMap<u8, Key> = BTreeMap::new();
    for (name, component) in &spec.components {
        let key = base.field(name);
        let lists = [("inputs", &component.inputs, true), ("outputs", &component.outputs, false)];
        for (field, list, input) in lists {
            for (i, signal) in list.iter().enumerate() {
                let here = key.field(field).item(i);
                if let Some(text) = &signal.address {
                    if let Some(a) = address(&here.field("address"), text, input, p) {
                        match at_address.get(&a) {
                            Some(other) => p.at(
                                &here.field("address"),
                                format!("{a} is already the address of {other}: one address, one signal"),
                            ),
                            None => {
                                at_address.insert(a, here.clone());
                            }
                        }
                    }
                }
                if let Some(pin) = signal.pin {
                    match at_pin.get(&pin) {
                        Some(other) => p.at(
                            &here.field("pin"),
                            format!("pin {pin} is already the pin of {other}: one pin, one signal"),
                        ),
                        None => {
                            at_pin.insert(pin, here.clone());
                        }
                    }
                    match board.map(|b| (b, b.pin(pin))) {
                        _ if pin > 63 => p.at(&here.field("pin"), format!("pin {pin} is beyond GPIO 63")),
                        Some((b, Pin::Absent(why))) => p.at(
                            &here.field("pin"),
                            format!("the {} has no pin {pin} ({}): {why}", b.name(), b.pin_name(pin)),
                        ),
                        Some((b, Pin::Reserved(why))) => p.at(
                            &here.field("pin"),
                            format!("pin {pin} ({}) of the {} is not free: {why}", b.pin_name(pin), b.name()),
                        ),
                        _ => {}
                    }
                }
            }
        }
        let Some(plant) = models.plants.iter().find(|a| a.name == *name) else {
            p.at(&key, format!("no plant of the set is called '{name}'{}", did_you_mean(name, plants())));
            continue;
        };
        let states = || plant.states.iter().map(|s| s.name.as_str());
        for s in &plant.states {
            if !component.states.contains_key(&s.name) {
                p.at(&key.field("states"), format!("state '{}' of {name} has no formula", s.name));
            }
        }
        for state in component.states.keys() {
            if plant.state_id(state).is_none() {
                p.at(
                    &key.field("states").field(state),
                    format!("{name} has no state '{state}'{}", did_you_mean(state, states())),
                );
            }
        }
        for e in plant.events.iter().filter(|e| e.controllable) {
            if !component.commands.contains_key(&e.name) {
                p.at(
                    &key.field("commands"),
                    format!(
                        "controllable event '{}' of {name} has no command (the outputs it writes)",
                        e.name
                    ),
                );
            }
        }
        for event in component.commands.keys() {
            let here = key.field("commands").field(event);
            match plant.event_id(event) {
                None => p.at(
                    &here,
                    format!(
                        "{name} has no event '{event}'{}",
                        did_you_mean(event, plant.events.iter().map(|e| e.name.as_str()))
                    ),
                ),
                Some(e) if !plant.events[e.index()].controllable => {
                    p.at(&here, format!("'{event}' is uncontrollable: a command is a controllable event's"))
                }
                Some(_) => {}
            }
        }
    }
}
