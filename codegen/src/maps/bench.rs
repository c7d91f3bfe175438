//! The LED/button bench's pin map, written from the set's events (`codegen bench`): every uncontrollable
//! event a push-button to ground on a Pico input (pull-up, falling edge), every command an LED on a Pico
//! output (a pulse long enough to see), the buttons debounced by timer sampling slower than a button
//! bounces. The pins are the Pico's free ones ([`Board::pin`]) in ascending order, buttons first, in the
//! order of the set's events; the section is checked by the same pass as a hand-written one.

use std::fmt::Write as _;

use crate::model::EventTable;

use super::pins::{Board, Pin};

/// How the bench reads its buttons and shows its commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bench {
    /// The buttons' sampling period in microseconds: longer than a push-button's bounce (a few ms), so
    /// one press is one edge.
    pub sample_period_us: u32,
    /// How long an LED lights for a command, in milliseconds.
    pub pulse_ms: u16,
}

impl Default for Bench {
    /// 20 ms sampling, 200 ms pulses.
    fn default() -> Self {
        Bench { sample_period_us: 20_000, pulse_ms: 200 }
    }
}

/// The set has more events than the Pico has free pins.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the bench needs a pin per event, {needed} ({buttons} buttons, {leds} LEDs), and the Pico has {free} \
     free; write the [board] section by hand (an LED's set and clear commands can share a pin, and \
     commands nothing outside sees can be listed in [board] internal)"
)]
pub struct BenchError {
    /// Pins needed: one per event.
    pub needed: usize,
    /// Uncontrollable events.
    pub buttons: usize,
    /// Commands.
    pub leds: usize,
    /// Free pins of the Pico.
    pub free: usize,
}

/// The `[board]` section (TOML) of the Pico bench for `events`, named after the set `name`.
pub fn board_section(name: &str, events: &EventTable, bench: &Bench) -> Result<String, BenchError> {
    let board = Board::Pico;
    let free: Vec<u8> = (0..=u8::MAX).filter(|&n| board.pin(n) == Pin::Free).collect();
    let (commands, sensors): (Vec<_>, Vec<_>) = events.ids().partition(|&e| events.is_controllable(e));
    if sensors.len() + commands.len() > free.len() {
        return Err(BenchError {
            needed: sensors.len() + commands.len(),
            buttons: sensors.len(),
            leds: commands.len(),
            free: free.len(),
        });
    }
    let quoted = |e| toml::Value::String(events.name(e).to_owned()).to_string();
    let mut pins = free.iter();
    let mut out = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(
        out,
        "# The LED/button bench of {} (`codegen bench`): every uncontrollable event a push-button from\n\
         # its pin to ground, every command an LED (with its resistor) from its pin to ground.\n\
         [board]\nname = \"{}\"\nsampling = \"timer\"\nsample_period_us = {}",
        toml::Value::String(name.to_owned()),
        board.name(),
        bench.sample_period_us
    );
    for (&e, &pin) in sensors.iter().zip(&mut pins) {
        let _ = writeln!(
            out,
            "\n# {} button\n[[board.inputs]]\nevent = {}\npin = {pin}\nedge = \"falling\"\npull = \"up\"",
            board.pin_name(pin),
            quoted(e)
        );
    }
    for (&e, &pin) in commands.iter().zip(&mut pins) {
        let _ = writeln!(
            out,
            "\n# {} LED\n[[board.outputs]]\nevent = {}\npin = {pin}\naction = \"pulse\"\npulse_ms = {}",
            board.pin_name(pin),
            quoted(e),
            bench.pulse_ms
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::manifest::{Manifest, ModelSet};
    use crate::model::testing::machine;
    use crate::model::Automaton;

    fn events(plants: &[Automaton]) -> EventTable {
        EventTable::build(plants).unwrap()
    }

    /// The maps pass's problems with `section` as the manifest's `[board]`, for the Pico.
    fn problems(plants: Vec<Automaton>, section: &str) -> Vec<String> {
        let m = Manifest::parse(Path::new("m.toml"), &format!("name = \"m\"\n{section}")).unwrap();
        let models = ModelSet { plants, specs: Vec::new(), supervisors: Vec::new(), sources: Vec::new() };
        match super::super::check(&m, &models, Some(Board::Pico)) {
            Ok(()) => Vec::new(),
            Err(e) => e.problems.iter().map(ToString::to_string).collect(),
        }
    }

    #[test]
    fn every_event_gets_a_free_pin_and_the_section_passes_the_maps_check() {
        let plants = vec![machine("M1", "start1", "done1"), machine("M2", "start2", "done2")];
        let section = board_section("two machines", &events(&plants), &Bench::default()).unwrap();
        assert_eq!(problems(plants, &section), Vec::<String>::new(), "{section}");
        let spec: toml::Value = toml::from_str(&section).unwrap();
        let board = &spec["board"];
        assert_eq!(
            (board["sampling"].as_str(), board["sample_period_us"].as_integer()),
            (Some("timer"), Some(20_000))
        );
        let inputs = board["inputs"].as_array().unwrap();
        let outputs = board["outputs"].as_array().unwrap();
        let names = |xs: &[toml::Value]| {
            xs.iter().map(|x| x["event"].as_str().unwrap().to_owned()).collect::<Vec<_>>()
        };
        assert_eq!(names(inputs), ["done1", "done2"]);
        assert_eq!(names(outputs), ["start1", "start2"]);
        let pins: Vec<i64> = inputs.iter().chain(outputs).map(|x| x["pin"].as_integer().unwrap()).collect();
        assert_eq!(pins, [0, 1, 2, 3]);
        assert!(inputs
            .iter()
            .all(|x| x["edge"].as_str() == Some("falling") && x["pull"].as_str() == Some("up")));
        assert!(outputs
            .iter()
            .all(|x| x["action"].as_str() == Some("pulse") && x["pulse_ms"].as_integer() == Some(200)));
    }

    #[test]
    fn the_reserved_pins_are_skipped_and_too_many_events_are_refused() {
        // 13 machines: 26 events on the 27 free pins GP0–GP22, GP25–GP28 (GP23 and GP24 skipped).
        let plants: Vec<Automaton> =
            (0..13).map(|i| machine(&format!("M{i}"), &format!("s{i}"), &format!("d{i}"))).collect();
        let section = board_section("m", &events(&plants), &Bench::default()).unwrap();
        assert!(
            section.contains("pin = 25\n")
                && !section.contains("pin = 23\n")
                && !section.contains("pin = 24\n")
        );
        assert_eq!(problems(plants, &section), Vec::<String>::new(), "{section}");
        let plants: Vec<Automaton> =
            (0..14).map(|i| machine(&format!("M{i}"), &format!("s{i}"), &format!("d{i}"))).collect();
        let err = board_section("m", &events(&plants), &Bench::default()).unwrap_err();
        assert_eq!((err.needed, err.buttons, err.leds, err.free), (28, 14, 14, 27));
    }
}
