//! What a state-based project's program (`[state]`, docs/state-based.md) sees at the simulation's
//! current point: the signal word — each sensor and actuator signal's value, as the plant's transitions
//! of the trace have written it — and each rung's value, F_σ evaluated on that word as the program's
//! rung does. The signals' meaning is the one [`crate::feedback::Vector`] binds from the `[state]`
//! section, and the formulas are [`crate::feedback::rules`] — the ones the program's rungs are written
//! from — so the page shows no second mapping.

use crate::config::{Cube, Direction, Signals};
use crate::feedback::memory::Layout;
use crate::feedback::{self, Vector};
use crate::pack::{PackSet, Role};

use super::Sim;

/// The state vectors and the formulas of a state-based program for the simulated set.
#[derive(Clone, Debug)]
pub struct Program {
    vector: Vector,
    /// Per controllable event: its name and F_σ over the signals and memory bits.
    rules: Vec<(String, Vec<Cube>)>,
    /// Where the kept supervisors' states sit in the word (empty when the plant state decides).
    layout: Layout,
    /// The kept supervisors, as indices into [`Sim::automata`].
    kept: Vec<usize>,
}

/// One signal in [`Word`].
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct SignalValue {
    /// The signal's name.
    pub name: String,
    /// The plant component it belongs to.
    pub component: String,
    /// `input` (a sensor) or `output` (an actuator).
    pub direction: &'static str,
    /// Its value now.
    pub value: bool,
}

/// One rung in [`Word`].
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct RungValue {
    /// The controllable event the rung commands.
    pub event: String,
    /// Whether the rung conducts now: F_σ holds on the word.
    pub conducts: bool,
}

/// The program's view at the current point of the trace.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Word {
    /// The signals, in the program's variable order.
    pub signals: Vec<SignalValue>,
    /// The rungs, in the program's order.
    pub rungs: Vec<RungValue>,
    /// The memory bits' values (kept supervisors' states), when the program keeps memory.
    pub memory: Vec<bool>,
}

impl Program {
    /// The program of `set` under `signals`, as the state-based program is written: memory kept when
    /// `[state] memory` says so, F_σ exact when `[state] exact` does. An error says why there is none
    /// (the section does not fit the plants, or the plant state does not decide and no memory is kept).
    pub fn new(set: &PackSet, signals: Signals) -> Result<Program, String> {
        let exact = signals.exact;
        let (vector, f) = feedback::analyse(set, signals, false, &[]).map_err(|e| e.to_string())?;
        let layout = match &f.memory {
            Some(m) => Layout::new(set, &m.kept, vector.signals.signals.len()).map_err(|e| e.to_string())?,
            None if !f.conflicts.is_empty() => {
                return Err(format!(
                    "the plant state does not decide the feedback in {} states (set `[state] memory`)",
                    f.conflicts.len()
                ))
            }
            None => Layout::default(),
        };
        let members = set.members();
        let plants = members.iter().filter(|m| m.role == Role::Plant).count();
        let kept = f.memory.as_ref().map_or_else(Vec::new, |m| {
            m.kept
                .iter()
                .map(|&s| plants + members[..s].iter().filter(|m| m.role == Role::Supervisor).count())
                .collect()
        });
        let rules = feedback::rules(&vector, &f, &layout, exact)
            .into_iter()
            .map(|r| (set.events().name(r.event).to_owned(), r.cubes))
            .collect();
        Ok(Program { vector, rules, layout, kept })
    }

    /// The signal word after `sim`'s trace: the initial states' values, then each step's plant
    /// transitions writing theirs (a command its outputs, a sensor event the inputs its target fixes),
    /// with the kept supervisors' states on the memory bits.
    pub fn word(&self, sim: &Sim) -> u64 {
        let mut v = self.vector.initial;
        for (k, step) in sim.trace.iter().enumerate() {
            let next = &sim.states[k + 1];
            for p in (0..sim.plants).filter(|&p| sim.closed.has_event(p, step.event)) {
                v = self.vector.after(p, step.event, next[p] as usize, v);
            }
        }
        let kept: Vec<u32> = self.kept.iter().map(|&i| sim.state()[i]).collect();
        let m = self.layout.cube(&kept);
        (v & !m.mask) | m.value
    }

    /// The signals, rungs and memory bits at `sim`'s current point.
    pub fn shown(&self, sim: &Sim) -> Word {
        let word = self.word(sim);
        let signals = &self.vector.signals;
        let bit = |i: usize| word >> i & 1 == 1;
        Word {
            signals: signals
                .signals
                .iter()
                .enumerate()
                .map(|(i, s)| SignalValue {
                    name: s.name.clone(),
                    component: signals.components[s.component].name.clone(),
                    direction: match s.direction {
                        Direction::Input => "input",
                        Direction::Output => "output",
                    },
                    value: bit(i),
                })
                .collect(),
            rungs: self
                .rules
                .iter()
                .map(|(event, cubes)| RungValue {
                    event: event.clone(),
                    conducts: cubes.iter().any(|c| c.holds(word)),
                })
                .collect(),
            memory: (signals.signals.len()..signals.signals.len() + self.layout.count()).map(bit).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use serde_json::Value;

    use super::*;
    use crate::manifest::Manifest;
    use crate::sim::api::handle;
    use crate::synth::{local_modular, Config};

    /// The distribution station (examples/distribution): its four plants and their local modular
    /// supervisors (as the project's default deployment), and its `[state]` section; no memory kept.
    fn distribution() -> (Sim, Signals) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/distribution/distribution.toml");
        let manifest = Manifest::load(&path).unwrap();
        let models = manifest.read_automata().unwrap();
        let synthesised = local_modular(&models.plants, &models.specs, &Config::default()).unwrap();
        let supervisors = synthesised.supervisors.into_iter().map(|s| s.automaton).collect();
        let set = PackSet::new(models.plants, supervisors).unwrap();
        let signals = manifest.state.as_ref().unwrap().check().unwrap();
        let sim = Sim::new(&manifest.name, set, manifest.runtime.clone()).unwrap();
        (sim.with_signals(Ok(signals.clone())), signals)
    }

    /// The `program` of the API's state.
    fn program_of(sim: &mut Sim) -> Value {
        let r = handle(sim, "GET", "/api/state?depth=1", "");
        assert_eq!(r.status, 200);
        let v: Value = serde_json::from_str(&r.body).unwrap();
        v["program"].clone()
    }

    fn program(sim: &mut Sim) -> Value {
        program_of(sim)["Ok"].clone()
    }

    /// At every point of a run the API's signal word reads as each plant's current state (its state's
    /// formula holds), the outputs are those the trace's commands wrote, and each rung conducts exactly
    /// where the feedback f_σ allows σ in that plant state — the program's own formulas, and the table
    /// they were minimised from.
    #[test]
    fn the_api_answers_the_signal_word_and_the_rungs_of_the_distribution_station() {
        let (mut sim, signals) = distribution();
        let (vector, f) = feedback::analyse(&sim.set, signals, false, &[]).unwrap();
        assert!(f.memory.is_none() && f.conflicts.is_empty());
        let rules = feedback::rules(&vector, &f, &Layout::default(), vector.signals.exact);
        let names: Vec<&str> = vector.signals.signals.iter().map(|s| s.name.as_str()).collect();
        let mut outputs = vector.initial & vector.signals.outputs();
        let mut seen = std::collections::BTreeSet::new();
        for step in 0..40 {
            let shown = program(&mut sim);
            let listed: Vec<&str> =
                shown["signals"].as_array().unwrap().iter().map(|s| s["name"].as_str().unwrap()).collect();
            assert_eq!(listed, names);
            let word = shown["signals"]
                .as_array()
                .unwrap()
                .iter()
                .enumerate()
                .fold(0u64, |w, (i, s)| w | u64::from(s["value"].as_bool().unwrap()) << i);
            let x = &sim.state()[..sim.plants];
            for (p, &s) in x.iter().enumerate() {
                assert!(
                    vector.cubes[p][s as usize].holds(word),
                    "step {step}: plant {p} state {s}, {word:#b}"
                );
            }
            assert_eq!(word & vector.signals.outputs(), outputs, "step {step}");
            let entry = f.entries.iter().find(|e| e.state == x).expect("a reachable plant state");
            let rungs = shown["rungs"].as_array().unwrap();
            assert_eq!(rungs.len(), f.controllable.len());
            for (k, (rung, rule)) in rungs.iter().zip(&rules).enumerate() {
                assert_eq!(rung["event"], sim.set.events().name(rule.event));
                let conducts = rung["conducts"].as_bool().unwrap();
                assert_eq!(conducts, rule.cubes.iter().any(|c| c.holds(word)), "step {step}");
                assert_eq!(conducts, entry.allowed[k], "step {step}: rung {}", rung["event"]);
                if conducts {
                    seen.insert(k);
                }
            }
            let r = handle(&mut sim, "POST", "/api/run", r#"{"events": 1, "depth": 1}"#);
            assert_eq!(r.status, 200);
            let event = sim.trace.last().unwrap().event;
            let cmd = vector.command(event);
            outputs = (outputs & !cmd.mask) | (cmd.value & vector.signals.outputs());
        }
        // The run went round the station: every rung conducted somewhere.
        assert_eq!(seen.len(), f.controllable.len());
        // Revert replays the word from the trace.
        let before = program(&mut sim);
        handle(&mut sim, "POST", "/api/revert", r#"{"to": 0}"#);
        let initial = program(&mut sim);
        let word = initial["signals"]
            .as_array()
            .unwrap()
            .iter()
            .enumerate()
            .fold(0u64, |w, (i, s)| w | u64::from(s["value"].as_bool().unwrap()) << i);
        assert_eq!(word, vector.initial);
        assert_ne!(before, Value::Null);
        // A section that does not fit the plants is said, not fatal; no section is `null`.
        let mut sim = crate::sim::tests::small();
        assert_eq!(program_of(&mut sim), Value::Null);
        let mut sim = crate::sim::tests::small().with_signals(Ok(vector.signals));
        assert!(program_of(&mut sim)["Err"].as_str().unwrap().contains("no state vector"));
    }
}
