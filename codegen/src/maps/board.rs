//! `[board]` against the set's events and the board's pins.

use std::collections::BTreeMap;

use crate::config::{BoardSpec, SamplingSpec};
use crate::manifest::Key;
use crate::model::suggest::did_you_mean;
use crate::model::EventTable;

use super::pins::{Board, Pin};
use super::{Changes, Problems};

/// Highest pin number a map may name: one bit per pin in the firmware's 64-bit sample.
const MAX_PIN: u8 = 63;

/// Which changes of a pin an edge word takes: rising, falling.
fn edges(word: &str) -> Option<(bool, bool)> {
    match word {
        "rising" => Some((true, false)),
        "falling" => Some((false, true)),
        "both" => Some((true, true)),
        _ => None,
    }
}

/// Checks the events, words and pins of `spec`; `board` is the board its pins are checked against,
/// `chosen` the one the command builds for (if any).
pub(super) fn check(
    spec: &BoardSpec,
    events: &EventTable,
    board: Option<Board>,
    chosen: Option<Board>,
    every_command: bool,
    p: &mut Problems,
) {
    let base = Key::new("board");
    let names = || events.ids().map(|e| events.name(e));
    // The event of an entry: known, and of the kind its direction needs.
    let event = |key: &Key, name: &str, input: bool, p: &mut Problems| match events.id(name) {
        None => p.at(key, format!("'{name}' is not an event of the set{}", did_you_mean(name, names()))),
        Some(e) if input && events.is_controllable(e) => p.at(
            key,
            format!(
                "'{name}' is controllable: an input's edge makes an uncontrollable event (a sensor); a \
                 command drives a pin in [[board.outputs]]"
            ),
        ),
        Some(e) if !input && !events.is_controllable(e) => p.at(
            key,
            format!(
                "'{name}' is uncontrollable: an output is driven by a controllable event (a command); a \
                 sensor's edge goes in [[board.inputs]]"
            ),
        ),
        Some(_) => {}
    };
    match (spec.sampling, spec.sample_period_us) {
        (SamplingSpec::Interrupt, Some(_)) => p.at(
            &base.field("sample_period_us"),
            "goes with sampling = \"timer\" only (edge interrupts need no period)",
        ),
        (SamplingSpec::Timer, None | Some(0)) => {
            p.at(&base.field("sampling"), "\"timer\" needs sample_period_us, the sampling period in µs (> 0)")
        }
        _ => {}
    }
    // Per pin: the entries on it with their edges, and its pull.
    let mut on_pin: BTreeMap<u8, Changes> = BTreeMap::new();
    let mut pulls: BTreeMap<u8, (usize, &str)> = BTreeMap::new();
    let mut sources: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, input) in spec.inputs.iter().enumerate() {
        let key = base.field("inputs").item(i);
        event(&key.field("event"), &input.event, true, p);
        if let Some(&first) = sources.get(input.event.as_str()) {
            p.at(
                &key.field("event"),
                format!(
                    "'{}' is already the event of board.inputs[{first}] (pin {}): one event, one input edge",
                    input.event, spec.inputs[first].pin
                ),
            );
        } else {
            sources.insert(&input.event, i);
        }
        if !["floating", "up", "down"].contains(&input.pull.as_str()) {
            p.at(&key.field("pull"), format!("'{}': floating, up or down", input.pull));
        } else if let Some(&(first, pull)) = pulls.get(&input.pin) {
            if pull != input.pull {
                p.at(
                    &key.field("pull"),
                    format!(
                        "pin {} is pulled {} by board.inputs[{first}] and {} here: one pin, one pull",
                        input.pin, pull, input.pull
                    ),
                );
            }
        } else {
            pulls.insert(input.pin, (i, &input.pull));
        }
        let Some(edge) = edges(&input.edge) else {
            p.at(&key.field("edge"), format!("'{}': rising, falling or both", input.edge));
            continue;
        };
        if let Some((other, event, which)) =
            on_pin.entry(input.pin).or_default().claim(key.clone(), &input.event, edge)
        {
            p.at(
                &key.field("edge"),
                format!(
                    "the {which} edge of pin {} would make both '{event}' ({other}) and '{}': one edge, one \
                     event (a second sensor needs a pin of its own; one pin may carry one event rising and \
                     another falling)",
                    input.pin, input.event
                ),
            );
        }
    }
    // Per output pin: whether pulses drive it, and the first entry that says so.
    let mut driven: BTreeMap<u8, (usize, bool)> = BTreeMap::new();
    let mut commands: BTreeMap<(u8, &str), usize> = BTreeMap::new();
    for (o, output) in spec.outputs.iter().enumerate() {
        let key = base.field("outputs").item(o);
        event(&key.field("event"), &output.event, false, p);
        let pulse = match (output.action.as_str(), output.pulse_ms) {
            ("set" | "clear", None) => false,
            ("pulse", Some(ms)) if ms > 0 => true,
            ("pulse", Some(_)) => {
                p.at(&key.field("pulse_ms"), "a pulse lasts 1 ms or more");
                true
            }
            ("pulse", None) => {
                p.at(&key.field("action"), "\"pulse\" needs pulse_ms, the pulse's length in ms (> 0)");
                true
            }
            ("set" | "clear", Some(_)) => {
                p.at(
                    &key.field("pulse_ms"),
                    format!("goes with action = \"pulse\" only, not \"{}\"", output.action),
                );
                false
            }
            (other, _) => {
                p.at(&key.field("action"), format!("'{other}': set, clear or pulse (with pulse_ms)"));
                continue;
            }
        };
        if let Some(&(first, _)) = pulls.get(&output.pin) {
            p.at(
                &key.field("pin"),
                format!(
                    "pin {} is already an input (board.inputs[{first}]): one pin, one direction",
                    output.pin
                ),
            );
        }
        if let Some(&first) = commands.get(&(output.pin, output.event.as_str())) {
            p.at(
                &key.field("event"),
                format!("'{}' already drives pin {} (board.outputs[{first}])", output.event, output.pin),
            );
        } else {
            commands.insert((output.pin, &output.event), o);
        }
        match driven.get(&output.pin) {
            Some(&(first, pulsed)) if pulsed != pulse => p.at(
                &key.field("action"),
                format!(
                    "pin {} is {} by board.outputs[{first}]: a pin is driven by pulses or by set and \
                     clear, not both",
                    output.pin,
                    if pulsed { "pulsed" } else { "set or cleared" }
                ),
            ),
            Some(_) => {}
            None => {
                driven.insert(output.pin, (o, pulse));
            }
        }
    }
    for (i, name) in spec.internal.iter().enumerate() {
        let key = base.field("internal").item(i);
        event(&key, name, false, p);
        if let Some(o) = spec.outputs.iter().position(|o| o.event == *name) {
            p.at(&key, format!("'{name}' is listed in `internal` and drives a pin (board.outputs[{o}])"));
        }
    }
    if every_command {
        let mapped = |name: &str| spec.outputs.iter().any(|o| o.event == name);
        for name in events.ids().filter(|&e| events.is_controllable(e)).map(|e| events.name(e)) {
            if !mapped(name) && !spec.internal.iter().any(|i| i == name) {
                p.at(
                    &base.field("outputs"),
                    format!(
                        "command '{name}' drives no pin: the supervisors would fire it and the plant never \
                         see it; map it in [[board.outputs]] or list it in [board] internal"
                    ),
                );
            }
        }
    }
    pins(spec, board, chosen, p);
}

/// Checks that every pin of `spec` is one `board` has and leaves free (only that it is at most
/// [`MAX_PIN`] without a board), and that a map `[board] name` says is another board's is not built for
/// `chosen`.
pub(super) fn pins(spec: &BoardSpec, board: Option<Board>, chosen: Option<Board>, p: &mut Problems) {
    let base = Key::new("board");
    if let (Some(chosen), Some(named)) = (chosen, Board::named(&spec.name)) {
        if chosen != named {
            p.at(
                &base.field("name"),
                format!(
                    "the map is written for the {} and the project is built for the {}: its pin numbers \
                     name other pins there; write a [board] section for the {1}",
                    named.name(),
                    chosen.name()
                ),
            );
        }
    }
    let inputs = spec.inputs.iter().enumerate().map(|(i, x)| (base.field("inputs").item(i), x.pin, "input"));
    let outputs =
        spec.outputs.iter().enumerate().map(|(o, x)| (base.field("outputs").item(o), x.pin, "output"));
    for (key, pin, role) in inputs.chain(outputs) {
        if pin > MAX_PIN {
            p.at(&key.field("pin"), format!("pin {pin} is beyond GPIO {MAX_PIN}"));
            continue;
        }
        let Some(board) = board else { continue };
        match board.pin(pin) {
            Pin::Free => {}
            Pin::Absent(why) => p.at(
                &key.field("pin"),
                format!("the {} has no pin {pin} ({}): {why}", board.name(), board.pin_name(pin)),
            ),
            Pin::Reserved(why) => p.at(
                &key.field("pin"),
                format!(
                    "pin {pin} ({}) of the {} is not free for an {role}: {why}",
                    board.pin_name(pin),
                    board.name()
                ),
            ),
        }
    }
}
