//! The manifest's `[state]` section: the plant's state vector, for state-based programs (state feedback
//! control, docs/design.md §10). Each plant component names its signals — inputs it reads, outputs its
//! commands write, with their PLC addresses and board pins — gives each of its states the conjunction of
//! literals that state means, and each of its controllable events the outputs its command writes.
//!
//! ```toml
//! [state]
//! memory = false                 # keep supervisors' states where the plant state does not decide
//! exact = false                  # F_σ without don't-cares
//! choice = "global-queue"       # one command per scan, chosen by this policy (absent: every rung fires)
//! [state.components.Injector]    # a plant automaton of the manifest
//! inputs = [{ name = "X0", address = "%IX0.0", pin = 2 }, { name = "X1", address = "%IX0.1", pin = 3 }]
//! outputs = [{ name = "Y2", address = "%QX0.2", pin = 18 }]
//! states = { I2B = ["!Y2", "X0", "!X1"], IMD = ["Y2", "!X1"] }   # a literal: NAME or !NAME
//! commands = { inject = ["Y2"], reset = ["!Y2"] }                 # outputs written: TRUE or FALSE
//! ```
//!
//! [`StateSpec::check`] turns the section into [`Signals`], refusing what cannot be read back: a signal
//! named twice, a literal over an unknown signal, a state formula that is contradictory or not disjoint
//! from another state's of the same component (the state could not be read from the signals), a command
//! writing an input or another component's output. Every error names its key. Checks against the
//! automata (every state has a formula, a command per controllable event) are the program builder's.

use std::collections::{BTreeMap, BTreeSet};

use serde::Deserialize;

use super::ScanPolicy;

/// At most this many signals: a valuation is one `u64` word.
pub const MAX_SIGNALS: usize = 64;

/// The `[state]` section.
#[derive(Clone, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateSpec {
    /// Where the plant state does not decide the feedback, keep the supervisors' states needed as
    /// further literals instead of failing (the `--memory` option).
    #[serde(default)]
    pub memory: bool,
    /// Minimise each F_σ without don't-cares: the formula is exactly the union of its states' formulas.
    #[serde(default)]
    pub exact: bool,
    /// At most one command per scan, chosen among the rungs that conduct by this policy (as the
    /// event-based program chooses); absent, every rung that conducts fires, in rung order.
    #[serde(default)]
    pub choice: Option<ScanPolicy>,
    /// The components, by the name of their plant automaton.
    #[serde(default)]
    pub components: BTreeMap<String, ComponentSpec>,
}

/// One plant component's state vector.
#[derive(Clone, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComponentSpec {
    /// Signals the component's sensors drive (PLC inputs).
    #[serde(default)]
    pub inputs: Vec<SignalSpec>,
    /// Signals the component's commands write (PLC outputs).
    #[serde(default)]
    pub outputs: Vec<SignalSpec>,
    /// Per state, the conjunction of literals (`X0`, `!X0`) it means.
    pub states: BTreeMap<String, Vec<String>>,
    /// Per controllable event, the outputs its command writes (`Y2`: TRUE, `!Y2`: FALSE).
    #[serde(default)]
    pub commands: BTreeMap<String, Vec<String>>,
}

/// One signal.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SignalSpec {
    /// Name (an IEC identifier: it is the PLC variable's name).
    pub name: String,
    /// Located address on the PLC (`%IX0.0`, `%QX0.2`).
    pub address: Option<String>,
    /// GPIO pin on the board.
    pub pin: Option<u8>,
}

/// A conjunction of literals over the signals, as the bits it fixes (`mask`) and their values
/// (`value`, within `mask`): it holds on a valuation `v` when `v & mask == value`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Cube {
    /// The signals the cube fixes.
    pub mask: u64,
    /// Their values.
    pub value: u64,
}

impl Cube {
    /// Whether the cube holds on valuation `v`.
    pub fn holds(self, v: u64) -> bool {
        v & self.mask == self.value
    }

    /// Whether no valuation satisfies both cubes (some signal fixed to opposite values).
    pub fn disjoint(self, other: Cube) -> bool {
        self.mask & other.mask & (self.value ^ other.value) != 0
    }

    /// The literals, as (signal, value), lowest signal first.
    pub fn literals(self) -> impl Iterator<Item = (usize, bool)> {
        (0..MAX_SIGNALS).filter(move |&i| self.mask >> i & 1 == 1).map(move |i| (i, self.value >> i & 1 == 1))
    }

    /// Number of literals.
    pub fn len(self) -> usize {
        self.mask.count_ones() as usize
    }

    /// Whether the cube has no literal (it always holds).
    pub fn is_empty(self) -> bool {
        self.mask == 0
    }
}

/// Whether a signal is read or written by the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// A sensor: the program reads it.
    Input,
    /// An actuator: commands write it.
    Output,
}

/// A checked signal.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signal {
    /// Name.
    pub name: String,
    /// Input or output.
    pub direction: Direction,
    /// Index of its component in [`Signals::components`].
    pub component: usize,
    /// PLC address, if any.
    pub address: Option<String>,
    /// Board pin, if any.
    pub pin: Option<u8>,
}

/// A checked component.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Component {
    /// The plant automaton's name.
    pub name: String,
    /// Per state name, its formula.
    pub states: BTreeMap<String, Cube>,
    /// Per controllable event, the outputs its command writes, as a cube over output signals.
    pub commands: BTreeMap<String, Cube>,
}

/// The `[state]` section, checked: signals numbered (components in name order, each component's inputs
/// then outputs), formulas as cubes over them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signals {
    /// Every signal; a cube's bit `i` is signal `i`.
    pub signals: Vec<Signal>,
    /// Every component.
    pub components: Vec<Component>,
    /// `[state] memory`.
    pub memory: bool,
    /// `[state] exact`.
    pub exact: bool,
    /// `[state] choice`.
    pub choice: Option<ScanPolicy>,
}

/// A `[state]` section that cannot be read back from the signals.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{key}: {message}")]
pub struct SignalsError {
    /// The key it is about (`state.components.Injector.states.I2B`).
    pub key: String,
    /// What is wrong.
    pub message: String,
}

fn fail<T>(key: String, message: impl Into<String>) -> Result<T, SignalsError> {
    Err(SignalsError { key, message: message.into() })
}

impl StateSpec {
    /// The section checked; see the module documentation for what is refused.
    pub fn check(&self) -> Result<Signals, SignalsError> {
        let mut signals: Vec<Signal> = Vec::new();
        let mut index: BTreeMap<String, usize> = BTreeMap::new();
        for (c, (name, spec)) in self.components.iter().enumerate() {
            let key = format!("state.components.{name}");
            let lists =
                [(Direction::Input, &spec.inputs, "inputs"), (Direction::Output, &spec.outputs, "outputs")];
            for (direction, list, field) in lists {
                for (i, s) in list.iter().enumerate() {
                    let here = format!("{key}.{field}[{i}]");
                    if let Some(&other) = index.get(&s.name.to_ascii_uppercase()) {
                        let owner = &signals[other];
                        let first = self.components.keys().nth(owner.component).map_or("", String::as_str);
                        return fail(here, format!("signal '{}' is named twice (also in {first})", s.name));
                    }
                    if signals.len() == MAX_SIGNALS {
                        return fail(here, format!("more than {MAX_SIGNALS} signals"));
                    }
                    index.insert(s.name.to_ascii_uppercase(), signals.len());
                    signals.push(Signal {
                        name: s.name.clone(),
                        direction,
                        component: c,
                        address: s.address.clone(),
                        pin: s.pin,
                    });
                }
            }
        }
        let mut components = Vec::new();
        for (c, (name, spec)) in self.components.iter().enumerate() {
            let key = format!("state.components.{name}");
            if spec.states.is_empty() {
                return fail(format!("{key}.states"), "no states");
            }
            let mut states = BTreeMap::new();
            for (state, literals) in &spec.states {
                let here = format!("{key}.states.{state}");
                let cube = cube(literals, &index, &here)?;
                if let Some((other, _)) = states.iter().find(|(_, &o): &(&String, &Cube)| !cube.disjoint(o)) {
                    return fail(
                        here,
                        format!("not disjoint from state {other}: both hold on some signals, so the state cannot be read"),
                    );
                }
                states.insert(state.clone(), cube);
            }
            let mut commands = BTreeMap::new();
            for (event, literals) in &spec.commands {
                let here = format!("{key}.commands.{event}");
                let cube = cube(literals, &index, &here)?;
                for (s, _) in cube.literals() {
                    let sig = &signals[s];
                    if sig.direction == Direction::Input {
                        return fail(
                            here,
                            format!("'{}' is an input: a command writes outputs only", sig.name),
                        );
                    }
                    if sig.component != c {
                        let owner = self.components.keys().nth(sig.component).map_or("", String::as_str);
                        return fail(
                            here,
                            format!(
                                "'{}' is an output of {owner}: a command writes its own component's outputs",
                                sig.name
                            ),
                        );
                    }
                }
                if cube.is_empty() {
                    return fail(here, "writes no output");
                }
                commands.insert(event.clone(), cube);
            }
            components.push(Component { name: name.clone(), states, commands });
        }
        Ok(Signals { signals, components, memory: self.memory, exact: self.exact, choice: self.choice })
    }
}

/// The literals at `key` as a cube; an unknown signal or a signal given both ways is an error.
fn cube(literals: &[String], index: &BTreeMap<String, usize>, key: &str) -> Result<Cube, SignalsError> {
    let mut c = Cube::default();
    let mut seen = BTreeSet::new();
    for l in literals {
        let (positive, name) = match l.trim().strip_prefix('!').or_else(|| l.trim().strip_prefix('¬')) {
            Some(rest) => (false, rest.trim()),
            None => (true, l.trim()),
        };
        let Some(&i) = index.get(&name.to_ascii_uppercase()) else {
            return fail(key.to_owned(), format!("'{name}' is not a signal of the section"));
        };
        if !seen.insert(i) {
            return fail(
                key.to_owned(),
                format!("'{name}' appears twice: the conjunction would be contradictory or repeat itself"),
            );
        }
        c.mask |= 1 << i;
        c.value |= u64::from(positive) << i;
    }
    Ok(c)
}

impl Signals {
    /// The component of plant `name`, with its index.
    pub fn component(&self, name: &str) -> Option<(usize, &Component)> {
        self.components.iter().enumerate().find(|(_, c)| c.name == name)
    }

    /// The mask of the output signals.
    pub fn outputs(&self) -> u64 {
        self.signals
            .iter()
            .enumerate()
            .filter(|(_, s)| s.direction == Direction::Output)
            .fold(0, |m, (i, _)| m | 1 << i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(text: &str) -> Result<Signals, SignalsError> {
        #[derive(Deserialize)]
        struct File {
            state: StateSpec,
        }
        toml::from_str::<File>(text).unwrap().state.check()
    }

    const INJECTOR: &str = "[state.components.Injector]\n\
        inputs = [{ name = \"X0\", address = \"%IX0.0\" }, { name = \"X1\" }]\n\
        outputs = [{ name = \"Y2\", pin = 18 }]\n\
        states = { I2B = [\"!Y2\", \"X0\", \"!X1\"], IMD = [\"Y2\", \"!X1\"], I2D = [\"Y2\", \"!X0\", \"X1\"], IMB = [\"!Y2\", \"!X0\"] }\n\
        commands = { inject = [\"Y2\"], reset = [\"!Y2\"] }\n";

    #[test]
    fn the_seed_injector_reads_as_cubes() {
        let s = spec(INJECTOR).unwrap();
        assert_eq!(s.signals.iter().map(|s| s.name.as_str()).collect::<Vec<_>>(), ["X0", "X1", "Y2"]);
        let inj = &s.components[0];
        // I2B = ¬Y2 ∧ X0 ∧ ¬X1: bits 0 (X0), 1 (X1), 2 (Y2).
        assert_eq!(inj.states["I2B"], Cube { mask: 0b111, value: 0b001 });
        assert_eq!(inj.commands["reset"], Cube { mask: 0b100, value: 0 });
        assert!(inj.states["I2B"].holds(0b001) && !inj.states["I2B"].holds(0b011));
        assert_eq!(s.outputs(), 0b100);
    }

    #[test]
    fn what_cannot_be_read_back_is_refused_with_its_key() {
        let overlapping = INJECTOR.replace("IMB = [\"!Y2\", \"!X0\"]", "IMB = [\"!Y2\", \"!X1\"]");
        let e = spec(&overlapping).unwrap_err();
        assert_eq!(e.key, "state.components.Injector.states.IMB");
        assert!(e.message.contains("not disjoint from state I2B"), "{e}");
        let twice = format!("{INJECTOR}[state.components.Barrel]\ninputs = [{{ name = \"x1\" }}]\nstates = {{ BE = [\"x1\"] }}\n");
        let e = spec(&twice).unwrap_err();
        assert_eq!(e.key, "state.components.Injector.inputs[1]", "Barrel comes first: {e}");
        let foreign = format!(
            "{INJECTOR}[state.components.Boom]\noutputs = [{{ name = \"Y0\" }}]\nstates = {{ B = [\"Y0\"] }}\ncommands = {{ go = [\"Y2\"] }}\n"
        );
        let e = spec(&foreign).unwrap_err();
        assert_eq!(e.key, "state.components.Boom.commands.go");
        assert!(e.message.contains("output of Injector"), "{e}");
        let input = INJECTOR.replace("inject = [\"Y2\"]", "inject = [\"X0\"]");
        assert!(spec(&input).unwrap_err().message.contains("is an input"));
        let unknown = INJECTOR.replace("IMD = [\"Y2\", \"!X1\"]", "IMD = [\"Y9\"]");
        assert!(spec(&unknown).unwrap_err().message.contains("'Y9' is not a signal"));
        let repeated = INJECTOR.replace("IMD = [\"Y2\", \"!X1\"]", "IMD = [\"Y2\", \"!Y2\"]");
        assert!(spec(&repeated).unwrap_err().message.contains("appears twice"));
    }
}
