//! Writing the manifest's `[board]` section ([`BoardSpec`]) as `firmware::board` tables, checked
//! against the set's events: inputs are uncontrollable events, outputs controllable ones, pins distinct
//! per direction and within the sampled word.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::config::{BoardSpec, SamplingSpec};
use crate::model::suggest::did_you_mean;
use crate::pack::tables::Packed;

/// Highest GPIO number a board table may name (one bit per pin in a `u64` sample: two ports of 32, as
/// the nRF52840 numbers P1.n as 32 + n).
pub const MAX_PIN: u8 = 63;

/// A `[board]` section that does not fit the set.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum BoardError {
    /// Event names the set does not have: every one of the section, each with the event names closest
    /// in spelling ("did you mean …?").
    #[error("board: {}", .0.join("; "))]
    UnknownEvents(Vec<String>),
    /// An input mapped to a controllable event, or an output to an uncontrollable one.
    #[error("board: event '{event}' is {what}")]
    WrongKind {
        /// Event name.
        event: String,
        /// What is wrong.
        what: &'static str,
    },
    /// A pin number beyond [`MAX_PIN`].
    #[error("board: pin {0} is beyond GPIO {MAX_PIN}")]
    Pin(u8),
    /// A pin used as input and output, or with two pulls.
    #[error("board: pin {0} is used both as input and output, or with two different pulls")]
    PinConflict(u8),
    /// An unknown edge, pull or action word, or a missing or stray parameter.
    #[error("board: {0}")]
    Value(String),
}

/// Rust source for `BOARD`, `INPUT_PINS`, `INPUT_PULLS` and `OUTPUT_PINS`: `spec` over `packed`'s events.
pub fn rust(spec: &BoardSpec, packed: &Packed) -> Result<String, BoardError> {
    let known = || packed.event_names.iter().map(String::as_str);
    let unknown: Vec<String> = spec
        .inputs
        .iter()
        .map(|i| &i.event)
        .chain(spec.outputs.iter().map(|o| &o.event))
        .filter(|name| !known().any(|k| k == name.as_str()))
        .map(|name| format!("event '{name}' is not an event of the set{}", did_you_mean(name, known())))
        .collect();
    if !unknown.is_empty() {
        return Err(BoardError::UnknownEvents(unknown));
    }
    let id = |name: &str| -> Result<usize, BoardError> {
        packed
            .event_names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| BoardError::UnknownEvents(vec![name.into()]))
    };
    let controllable = |e: usize| packed.controllable.get(e / 32).is_some_and(|w| w & (1 << (e % 32)) != 0);
    let pin = |p: u8| if p > MAX_PIN { Err(BoardError::Pin(p)) } else { Ok(p) };
    let mut pulls: BTreeMap<u8, &'static str> = BTreeMap::new();
    let mut inputs = Vec::new();
    for i in &spec.inputs {
        let e = id(&i.event)?;
        if controllable(e) {
            return Err(BoardError::WrongKind {
                event: i.event.clone(),
                what: "controllable: it cannot be an input",
            });
        }
        let edge = match i.edge.as_str() {
            "rising" => "Rising",
            "falling" => "Falling",
            "both" => "Both",
            other => return Err(BoardError::Value(format!("edge '{other}' (rising, falling or both)"))),
        };
        let pull = match i.pull.as_str() {
            "floating" => "Floating",
            "up" => "Up",
            "down" => "Down",
            other => return Err(BoardError::Value(format!("pull '{other}' (floating, up or down)"))),
        };
        let p = pin(i.pin)?;
        if *pulls.entry(p).or_insert(pull) != pull {
            return Err(BoardError::PinConflict(p));
        }
        inputs.push(format!(
            "firmware::board::Input {{ pin: {p}, edge: firmware::board::Edge::{edge}, pull: firmware::board::Pull::{pull}, event: {e} }}"
        ));
    }
    let mut out_pins = BTreeMap::new();
    let mut outputs = Vec::new();
    for o in &spec.outputs {
        let e = id(&o.event)?;
        if !controllable(e) {
            return Err(BoardError::WrongKind {
                event: o.event.clone(),
                what: "uncontrollable: it cannot drive an output",
            });
        }
        let action = match (o.action.as_str(), o.pulse_ms) {
            ("set", None) => "Set".to_string(),
            ("clear", None) => "Clear".to_string(),
            ("pulse", Some(ms)) => format!("Pulse {{ ms: {ms} }}"),
            (other, ms) => {
                let ms =
                    ms.map_or_else(|| "without pulse_ms".to_owned(), |ms| format!("with pulse_ms = {ms}"));
                return Err(BoardError::Value(format!(
                    "action '{other}' {ms} (set, clear, or pulse with pulse_ms)"
                )));
            }
        };
        let p = pin(o.pin)?;
        if pulls.contains_key(&p) {
            return Err(BoardError::PinConflict(p));
        }
        out_pins.insert(p, ());
        outputs.push(format!(
            "firmware::board::Output {{ pin: {p}, action: firmware::board::Action::{action}, event: {e} }}"
        ));
    }
    let sampling = match (spec.sampling, spec.sample_period_us) {
        (SamplingSpec::Interrupt, None) => "firmware::board::Sampling::Interrupt".to_string(),
        (SamplingSpec::Timer, Some(us)) if us > 0 => {
            format!("firmware::board::Sampling::Timer {{ period_us: {us} }}")
        }
        _ => {
            return Err(BoardError::Value(
                "sample_period_us (> 0) goes with sampling = \"timer\" only".into(),
            ))
        }
    };
    let mut s = String::new();
    let list = |items: &[String]| items.iter().map(|i| format!("        {i},\n")).collect::<String>();
    let _ = writeln!(s, "/// The board's pin map (`[board]`).");
    let _ = writeln!(s, "pub static BOARD: firmware::board::Board<'static> = firmware::board::Board {{");
    let _ = writeln!(s, "    name: {:?},", spec.name);
    let _ = writeln!(s, "    sampling: {sampling},");
    let _ = writeln!(s, "    inputs: &[\n{}    ],", list(&inputs));
    let _ = writeln!(s, "    outputs: &[\n{}    ],", list(&outputs));
    let _ = writeln!(s, "}};");
    let ins: Vec<String> = pulls.keys().map(u8::to_string).collect();
    let in_pulls: Vec<String> = pulls.values().map(|p| format!("firmware::board::Pull::{p}")).collect();
    let outs: Vec<String> = out_pins.keys().map(u8::to_string).collect();
    let _ = writeln!(s, "/// Distinct input GPIOs, ascending.");
    let _ = writeln!(s, "pub const INPUT_PINS: [u8; {}] = [{}];", ins.len(), ins.join(", "));
    let _ = writeln!(s, "/// Bias of each input GPIO.");
    let _ = writeln!(
        s,
        "pub const INPUT_PULLS: [firmware::board::Pull; {}] = [{}];",
        ins.len(),
        in_pulls.join(", ")
    );
    let _ = writeln!(s, "/// Distinct output GPIOs, ascending.");
    let _ = writeln!(s, "pub const OUTPUT_PINS: [u8; {}] = [{}];", outs.len(), outs.join(", "));
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn packed() -> Packed {
        Packed {
            event_names: vec!["go".into(), "done".into()],
            controllable: vec![0b01],
            plants: 0,
            masks: vec![],
            wide: false,
            position_bytes: 2,
            layout: firmware::build::Layout::Ranked,
            automata: vec![],
        }
    }

    fn spec(text: &str) -> BoardSpec {
        #[derive(serde::Deserialize)]
        struct File {
            board: BoardSpec,
        }
        toml::from_str::<File>(text).unwrap().board
    }

    const OK: &str = r#"
        [board]
        name = "t"
        [[board.inputs]]
        event = "done"
        pin = 3
        edge = "falling"
        pull = "up"
        [[board.outputs]]
        event = "go"
        pin = 5
        action = "pulse"
        pulse_ms = 20
    "#;

    #[test]
    fn writes_the_pin_map() {
        let rust = rust(&spec(OK), &packed()).unwrap();
        assert!(rust.contains("Input { pin: 3, edge: firmware::board::Edge::Falling, pull: firmware::board::Pull::Up, event: 1 }"));
        assert!(
            rust.contains("Output { pin: 5, action: firmware::board::Action::Pulse { ms: 20 }, event: 0 }")
        );
        assert!(rust.contains("pub const INPUT_PINS: [u8; 1] = [3];"));
        assert!(rust.contains("pub const OUTPUT_PINS: [u8; 1] = [5];"));
    }

    #[test]
    fn refuses_what_does_not_fit() {
        let cases = [
            (
                OK.replace("\"done\"", "\"dome\"").replace("\"go\"", "\"og\""),
                BoardError::UnknownEvents(vec![
                    "event 'dome' is not an event of the set (did you mean 'done'?)".into(),
                    "event 'og' is not an event of the set (did you mean 'go'?)".into(),
                ]),
            ),
            (
                OK.replace("event = \"done\"", "event = \"go\""),
                BoardError::WrongKind { event: "go".into(), what: "controllable: it cannot be an input" },
            ),
            (OK.replace("pin = 3", "pin = 64"), BoardError::Pin(64)),
            (OK.replace("pin = 3", "pin = 5"), BoardError::PinConflict(5)),
        ];
        for (text, err) in cases {
            assert_eq!(rust(&spec(&text), &packed()), Err(err));
        }
        assert!(matches!(rust(&spec(&OK.replace("falling", "up")), &packed()), Err(BoardError::Value(_))));
        assert!(matches!(
            rust(&spec(&OK.replace("pulse_ms = 20", "")), &packed()),
            Err(BoardError::Value(_))
        ));
        let timer = OK.replace("name = \"t\"", "name = \"t\"\nsampling = \"timer\"");
        assert!(matches!(rust(&spec(&timer), &packed()), Err(BoardError::Value(_))));
        let timer = timer.replace("sampling = \"timer\"", "sampling = \"timer\"\nsample_period_us = 500");
        assert!(rust(&spec(&timer), &packed()).unwrap().contains("Timer { period_us: 500 }"));
    }
}
