//! This module is the home of [`RuntimeConfig`]: what the firmware runs its tables with besides the
//! tables — the choice policy, the fault reaction, the seed, the guard, the input buffer, the reseed
//! period, the tables' [`Layout`] and which supervisors run ([`SupervisorChoice`]).

use std::collections::BTreeMap;
use std::fmt;

use clap::ValueEnum;
use serde::Deserialize;

/// A choice policy of the runtime (`firmware::choice`, design notes §4.1). The manifest, the command
/// line and the emitted header name it in kebab case (`random-local-queue`), as derived from the
/// variant: [`fmt::Display`] writes that name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ChoicePolicy {
    /// Lowest enabled event id.
    First,
    /// Uniform among the enabled.
    Random,
    /// One cursor over all controllable events.
    GlobalQueue,
    /// A random order of all controllable events per round.
    RandomGlobalQueue,
    /// A cursor per choice site.
    LocalQueue,
    /// A random order per choice site and round.
    #[default]
    RandomLocalQueue,
}

impl ChoicePolicy {
    /// Every policy, in the order of the design notes.
    pub const ALL: [ChoicePolicy; 6] = [
        ChoicePolicy::First,
        ChoicePolicy::Random,
        ChoicePolicy::GlobalQueue,
        ChoicePolicy::RandomGlobalQueue,
        ChoicePolicy::LocalQueue,
        ChoicePolicy::RandomLocalQueue,
    ];
}

/// The reaction to a fault (`firmware::fault::FaultPolicy`), named in kebab case like [`ChoicePolicy`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OnFault {
    /// Count, report, keep deciding.
    #[default]
    Continue,
    /// Count, report, outputs off, stop deciding until a reset.
    SafeState,
}

/// A layout of the tables (`firmware::table::layout`): every one is packed by `codegen pack` and run by
/// the firmware; named in kebab case like [`ChoicePolicy`] (`memory-safe`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, ValueEnum, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Layout {
    /// The reference tool's vector, to the byte; a step walks to the target's record.
    MemorySafe,
    /// The same records with targets as offsets: a step jumps.
    Offset,
    /// Out-mask pool and rank-addressed targets: the Cortex-M3's default.
    Ranked,
    /// Targets addressed by the event's place in the alphabet, masks of whole words: the Cortex-M0+'s
    /// default.
    Indexed,
    /// Bit-packed over local alphabets: the smallest.
    Compact,
}

/// Writes the name clap and serde derive from the variant (`random-local-queue`).
fn kebab(value: &impl ValueEnum, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    value.to_possible_value().map_or(Ok(()), |v| f.write_str(v.get_name()))
}

impl fmt::Display for ChoicePolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        kebab(self, f)
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        kebab(self, f)
    }
}

impl fmt::Display for OnFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        kebab(self, f)
    }
}

/// What the firmware runs (`[runtime] mode`): the supervisors' tables, or the state feedback f.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// Event-based: plants and supervisors as tables, their states tracked from events (design notes §4).
    #[default]
    Event,
    /// State-based: F_σ per controllable event as cubes over the packed signal word, no supervisor
    /// tables (design notes §10; needs the manifest's `[state]`).
    State,
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        kebab(self, f)
    }
}

/// Which supervisors a project deploys (`[runtime] supervisors`, `--supervisors`): the set as
/// synthesised, each of its supervisors reduced, or one monolithic supervisor, full or reduced. Every
/// choice but `full` is proven to give the plants the full set's closed loop before it is used
/// (`synth::deploy`). Named in kebab case like [`ChoicePolicy`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SupervisorChoice {
    /// The local modular supervisors as synthesised (conflicting specifications merged), with the ready
    /// supervisors.
    #[default]
    Full,
    /// Each supervisor of the full set reduced against its local plant (supervisor reduction, as TCT
    /// `supreduce`).
    Reduced,
    /// One supervisor: supC of all plants and all specifications (ready supervisors counted as
    /// specifications).
    Monolithic,
    /// The monolithic supervisor reduced against the whole plant.
    MonolithicReduced,
}

impl fmt::Display for SupervisorChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        kebab(self, f)
    }
}

/// The run-time configuration of a firmware: the manifest's `[runtime]` section, which `codegen emit`'s
/// options override and the emitted tables carry (`CONFIG`, `SEED`, `INPUT_SLOTS`, the `Policy` type).
/// Every key is optional; unknown keys are refused.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RuntimeConfig {
    /// Choice policy.
    pub policy: ChoicePolicy,
    /// Seed of the random policies under QEMU (a board reseeds from its own entropy).
    pub seed: u64,
    /// Whether the inexact-synchronisation guard is on.
    pub guard: bool,
    /// Reaction to faults.
    pub on_fault: OnFault,
    /// Capacity of the input event buffer.
    pub input_buffer: usize,
    /// Random draws between two reseeds (0: never).
    pub reseed_every: u16,
    /// The tables' layout on every core (default: the best measured per core, `ranked` on the
    /// Cortex-M3 and `indexed` on the Cortex-M0+).
    pub layout: Option<Layout>,
    /// Event-based tables or the state feedback (default: event-based).
    pub mode: Mode,
    /// Which supervisors run (default: the full set).
    pub supervisors: SupervisorChoice,
    /// The virtual plant's answer delay per command, in ms of virtual time: `answer_ms = { extend =
    /// [1000, 3000] }` draws the plant's next event after `extend` uniformly in 1–3 s. It is how a
    /// sensor that stops a `[[timers]]` timer comes before or after the timeout in `codegen run`, so
    /// that both paths are run; the firmware never reads it. `--answer-delay-us` overrides it per
    /// command.
    pub answer_ms: BTreeMap<String, [u64; 2]>,
}

impl RuntimeConfig {
    /// The layout each core runs, Cortex-M3 then Cortex-M0+: [`RuntimeConfig::layout`] on both, else
    /// the best measured per core (docs/layouts.md) — `ranked` and `indexed`.
    pub fn layouts(&self) -> (Layout, Layout) {
        match self.layout {
            Some(layout) => (layout, layout),
            None => (Layout::Ranked, Layout::Indexed),
        }
    }
}

impl Default for RuntimeConfig {
    fn default() -> Self {
        RuntimeConfig {
            policy: ChoicePolicy::default(),
            seed: 0,
            guard: true,
            on_fault: OnFault::default(),
            input_buffer: 32,
            reseed_every: 1024,
            layout: None,
            mode: Mode::Event,
            supervisors: SupervisorChoice::Full,
            answer_ms: BTreeMap::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The name written for a value is the one the manifest and the command line read back.
    fn reads_back<T: ValueEnum + fmt::Display + PartialEq + fmt::Debug + for<'de> Deserialize<'de>>(
        all: &[T],
    ) {
        #[derive(Deserialize)]
        struct Key<T> {
            key: T,
        }
        for v in all {
            let name = v.to_string();
            assert_eq!(&T::from_str(&name, false).unwrap(), v, "command line: {name}");
            let parsed: Key<T> = toml::from_str(&format!("key = \"{name}\"")).unwrap();
            assert_eq!(&parsed.key, v, "manifest: {name}");
        }
    }

    #[test]
    fn names_are_kebab_case_and_read_back() {
        reads_back(&ChoicePolicy::ALL);
        reads_back(OnFault::value_variants());
        reads_back(Layout::value_variants());
        reads_back(Mode::value_variants());
        reads_back(SupervisorChoice::value_variants());
        assert_eq!(SupervisorChoice::MonolithicReduced.to_string(), "monolithic-reduced");
        assert_eq!(Layout::MemorySafe.to_string(), "memory-safe");
        assert_eq!(ChoicePolicy::RandomGlobalQueue.to_string(), "random-global-queue");
        assert_eq!(OnFault::SafeState.to_string(), "safe-state");
    }
}
