//! The interpretation of a net (RTPN: Y, Z, D) bound to the signals of the admissible behaviour.
//!
//! Every plant event is one edge of one signal: `af1` is af rising, `sf0` sf falling, or what the
//! manifest's `[net.events]` says. A signal whose events are controllable is an output (an actuator), one
//! whose events are uncontrollable an input (a sensor). Signals no automaton carries are declared: free
//! inputs (either value), fixed inputs, and outputs that are set at once (lamps). Every name of the
//! `[net]` section is checked here against the net and these signals, and a bad one is reported with its
//! manifest line.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use toml::Spanned;

use super::condition::{Expr, Value};
use super::model::{Index, Net};
use super::NetError;
use crate::config::NetSpec;
use crate::model::{EventId, EventTable};

/// Whether a signal goes into the controller or out of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// A sensor or operator signal; conditions read it.
    Input,
    /// An actuator or lamp; place actions set it.
    Output,
}

/// One signal of the controller.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signal {
    /// Its name.
    pub name: String,
    /// Input or output.
    pub direction: Direction,
    /// Whether an automaton's events change it (else it is free, fixed, or an immediate output).
    pub carried: bool,
    /// Its initial value (`Either` for a free input).
    pub initial: Value,
}

/// A net with its interpretation, over the signals of one event table.
#[derive(Clone, Debug)]
pub struct Interpretation {
    /// The net.
    pub net: Net,
    /// The signals: carried ones first, in order of their first event, then free, fixed and immediate.
    pub signals: Vec<Signal>,
    /// Per global event id, the signal it changes and the value it gives it.
    pub edges: Vec<(usize, bool)>,
    /// Y(t) per transition (`TRUE` when the manifest gives none), over signal indices.
    pub conditions: Vec<Expr<usize>>,
    /// Z(p) per place: (signal, value), sorted by signal.
    pub actions: Vec<Vec<(usize, bool)>>,
    /// D(t) per transition, in milliseconds.
    pub delays: Vec<u32>,
}

impl Interpretation {
    /// Binds `spec` (from the manifest `file`) to `net` and the events of `table`.
    pub fn bind(
        spec: &NetSpec,
        file: &Path,
        net: Net,
        table: &EventTable,
    ) -> Result<Interpretation, NetError> {
        let b = Binder { spec, file };
        let mut signals: Vec<Signal> = Vec::new();
        let mut edges = Vec::with_capacity(table.len());
        let explicit: BTreeMap<&str, &Spanned<String>> =
            spec.events.keys().map(|k| (k.get_ref().as_str(), k)).collect();
        for key in spec.events.keys() {
            if table.id(key.get_ref()).is_none() {
                return Err(b.at(key, format!("events.{}: no automaton has this event", key.get_ref())));
            }
        }
        for e in table.ids() {
            let name = table.name(e);
            let (signal, value) = match explicit.get(name) {
                Some(key) => {
                    let edge = &spec.events[*key];
                    (edge.signal.clone(), edge.value.0)
                }
                None => by_convention(name).ok_or_else(|| NetError::Spec {
                    file: file.to_owned(),
                    line: b.line(&spec.pnml),
                    message: format!(
                        "event '{name}' is no signal edge: name it <signal>1 or <signal>0, or map it in [net.events]"
                    ),
                })?,
            };
            let direction = if table.is_controllable(e) { Direction::Output } else { Direction::Input };
            let index = match signals.iter().position(|s| s.name == signal) {
                Some(i) if signals[i].direction != direction => {
                    return Err(NetError::Spec {
                        file: file.to_owned(),
                        line: b.line(&spec.pnml),
                        message: format!(
                            "signal '{signal}' has controllable and uncontrollable events (event '{name}')"
                        ),
                    })
                }
                Some(i) => i,
                None => {
                    signals.push(Signal {
                        name: signal,
                        direction,
                        carried: true,
                        initial: Value::Is(false),
                    });
                    signals.len() - 1
                }
            };
            edges.push((index, value));
        }
        for (key, level) in &spec.initial {
            let Some(s) = signals.iter_mut().find(|s| s.name == *key.get_ref()) else {
                return Err(b.at(key, format!("initial.{}: no automaton carries this signal", key.get_ref())));
            };
            s.initial = Value::Is(level.0);
        }
        let declared = spec.free.iter().map(|k| (k, Direction::Input, Value::Either));
        let fixed = spec.fixed.iter().map(|(k, v)| (k, Direction::Input, Value::Is(v.0)));
        let outputs = spec.outputs.iter().map(|k| (k, Direction::Output, Value::Is(false)));
        for (key, direction, initial) in declared.chain(fixed).chain(outputs) {
            if let Some(s) = signals.iter().find(|s| s.name == *key.get_ref()) {
                let why = if s.carried { "an automaton carries it" } else { "declared twice" };
                return Err(b.at(key, format!("signal '{}': {why}", key.get_ref())));
            }
            if by_name_check(key.get_ref()).is_err() {
                return Err(b.at(key, format!("'{}' is not a signal name", key.get_ref())));
            }
            signals.push(Signal { name: key.get_ref().clone(), direction, carried: false, initial });
        }
        let find = |name: &str| signals.iter().position(|s| s.name == name);

        let mut conditions = vec![Expr::Const(true); net.transitions.len()];
        for (key, text) in &spec.conditions {
            let t = b.transition(&net, key, "conditions")?;
            let parsed = Expr::parse(text.get_ref())
                .map_err(|m| b.at(text, format!("conditions.{}: {m}", key.get_ref())))?;
            conditions[t] = parsed.bind(&mut |v: &String| match find(v) {
                Some(i) if signals[i].direction == Direction::Input => Ok(i),
                Some(_) => Err(b.at(text, format!("conditions.{}: '{v}' is an output", key.get_ref()))),
                None => Err(b.at(text, format!("conditions.{}: unknown signal '{v}'", key.get_ref()))),
            })?;
        }
        let mut actions = vec![Vec::new(); net.places.len()];
        for (key, sets) in &spec.actions {
            let Some(p) = net.place(key.get_ref()) else {
                return Err(b.at(key, format!("actions.{}: the net has no such place", key.get_ref())));
            };
            for (signal, level) in sets {
                match find(signal.get_ref()) {
                    Some(i) if signals[i].direction == Direction::Output => actions[p].push((i, level.0)),
                    Some(_) => {
                        return Err(b.at(
                            signal,
                            format!("actions.{}: '{}' is an input", key.get_ref(), signal.get_ref()),
                        ))
                    }
                    None => {
                        return Err(b.at(
                            signal,
                            format!("actions.{}: unknown signal '{}'", key.get_ref(), signal.get_ref()),
                        ))
                    }
                }
            }
            actions[p].sort_unstable();
        }
        let mut delays = vec![0; net.transitions.len()];
        for (key, ms) in &spec.delays {
            delays[b.transition(&net, key, "delays")?] = *ms;
        }
        Ok(Interpretation { net, signals, edges, conditions, actions, delays })
    }

    /// The global event that sets `signal` to `value`, if an automaton has one.
    pub fn event_for(&self, signal: usize, value: bool) -> Option<EventId> {
        self.edges.iter().position(|&e| e == (signal, value)).map(|i| EventId::from_u32(i as u32))
    }
}

/// `name` as a signal edge by the seed paper's convention: a last character `1` rises, `0` falls.
fn by_convention(name: &str) -> Option<(String, bool)> {
    let value = match name.as_bytes().last()? {
        b'1' => true,
        b'0' => false,
        _ => return None,
    };
    let signal = &name[..name.len() - 1];
    by_name_check(signal).ok().map(|()| (signal.to_owned(), value))
}

/// Whether `name` can be a signal (and a PLC identifier): a letter or `_`, then letters, digits, `_`.
fn by_name_check(name: &str) -> Result<(), ()> {
    let mut chars = name.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return Err(()),
    }
    if chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        Ok(())
    } else {
        Err(())
    }
}

/// Errors at a manifest key.
struct Binder<'a> {
    spec: &'a NetSpec,
    file: &'a Path,
}

impl Binder<'_> {
    fn line<T>(&self, key: &Spanned<T>) -> usize {
        self.spec.line(key.span().start)
    }

    fn at<T>(&self, key: &Spanned<T>, message: String) -> NetError {
        NetError::Spec { file: PathBuf::from(self.file), line: self.line(key), message }
    }

    fn transition(&self, net: &Net, key: &Spanned<String>, section: &str) -> Result<Index, NetError> {
        net.transition(key.get_ref()).ok_or_else(|| {
            self.at(key, format!("{section}.{}: the net has no such transition", key.get_ref()))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::Manifest;
    use crate::model::testing::build;
    use crate::net::model::{Place, Transition};

    fn net() -> Net {
        Net {
            name: "n".into(),
            places: vec![Place { id: "p1".into(), initial: 1 }, Place { id: "p2".into(), initial: 0 }],
            transitions: vec![Transition {
                id: "t1".into(),
                inputs: vec![(0, 1)],
                outputs: vec![(1, 1)],
                ..Default::default()
            }],
        }
    }

    fn bind(section: &str) -> Result<Interpretation, String> {
        let text = format!("name = \"x\"\n[net]\npnml = \"n.pnml\"\n{section}");
        let m = Manifest::parse(Path::new("m.toml"), &text).map_err(|e| e.to_string())?;
        let a = build(
            "A",
            &["0", "1", "2"],
            &["af1", "af0"],
            &[("0", "af1", "1"), ("1", "sf1", "2"), ("2", "af0", "0")],
        );
        let table = EventTable::build([&a]).unwrap();
        Interpretation::bind(m.net.as_ref().unwrap(), &m.file, net(), &table).map_err(|e| e.to_string())
    }

    #[test]
    fn signals_come_from_event_names_and_declarations() {
        let i = bind("free = [\"go\"]\noutputs = [\"lamp\"]\n[net.conditions]\nt1 = \"go AND NOT sf\"\n[net.actions]\np2 = { af = 1, lamp = 1 }\n").unwrap();
        let names: Vec<_> = i.signals.iter().map(|s| (s.name.as_str(), s.direction, s.carried)).collect();
        assert_eq!(
            names,
            vec![
                ("af", Direction::Output, true),
                ("sf", Direction::Input, true),
                ("go", Direction::Input, false),
                ("lamp", Direction::Output, false)
            ]
        );
        assert_eq!(i.actions[1], vec![(0, true), (3, true)]);
        assert_eq!(i.event_for(0, false).map(|e| e.index()), Some(2));
    }

    #[test]
    fn every_name_is_checked_with_its_line() {
        assert_eq!(
            bind("[net.conditions]\nt9 = \"sf\"\n").unwrap_err(),
            "m.toml:5: conditions.t9: the net has no such transition"
        );
        assert_eq!(
            bind("[net.conditions]\nt1 = \"sf AND go\"\n").unwrap_err(),
            "m.toml:5: conditions.t1: unknown signal 'go'"
        );
        assert_eq!(
            bind("[net.conditions]\nt1 = \"af\"\n").unwrap_err(),
            "m.toml:5: conditions.t1: 'af' is an output"
        );
        assert_eq!(
            bind("[net.actions]\np2 = { sf = 1 }\n").unwrap_err(),
            "m.toml:5: actions.p2: 'sf' is an input"
        );
        assert_eq!(
            bind("[net.actions]\np3 = { af = 1 }\n").unwrap_err(),
            "m.toml:5: actions.p3: the net has no such place"
        );
        assert_eq!(bind("free = [\"sf\"]\n").unwrap_err(), "m.toml:4: signal 'sf': an automaton carries it");
        assert_eq!(
            bind("[net.conditions]\nt1 = \"sf AND\"\n").unwrap_err(),
            "m.toml:5: conditions.t1: unexpected end: expected a signal, NOT or '('"
        );
        assert_eq!(
            bind("[net.events]\nzz = { signal = \"z\", value = 1 }\n").unwrap_err(),
            "m.toml:5: events.zz: no automaton has this event"
        );
    }
}
