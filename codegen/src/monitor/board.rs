//! What a run on a board's pins showed that a byte link cannot: the figures the RP2040 harness
//! (`harness/rp2040/`) counts and measures — its stats file, read by
//! [`Harness::figures`](crate::target::rp2040::Harness::figures) — which the closed loop's report
//! ([`Report`](super::Report)) carries as they come.

use std::fmt;

use serde::{Deserialize, Serialize};

/// Cost of one runtime entry point on the emulated Cortex-M0+: calls, and core cycles and instructions
/// per call (interrupt handlers that preempt it left out).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CallCost {
    /// Calls measured.
    pub calls: u64,
    /// Mean cycles per call.
    pub avg_cycles: f64,
    /// Most cycles of one call.
    pub max_cycles: u64,
    /// Mean instructions per call.
    pub avg_instructions: f64,
    /// Most instructions of one call.
    pub max_instructions: u64,
}

/// The runtime's entry points, measured through the run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RuntimeCost {
    /// `apply`: one uncontrollable event.
    pub apply: CallCost,
    /// `decide` that fired a command (enabled set, choice, guard, firing).
    pub decision: CallCost,
    /// `decide` with nothing enabled.
    pub idle_decision: CallCost,
    /// `decide` whose choice the inexact-synchronisation guard dropped.
    pub redecision: CallCost,
}

/// The harness's figures for one run (its `--stats` file).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoardFigures {
    /// The emulated board (`rp2040`).
    pub target: String,
    /// Seed of the ring oscillator's random bit.
    pub seed: u64,
    /// How the firmware read its inputs (`interrupt` or `timer`).
    pub sampling: String,
    /// Sampling period in µs (timer sampling; 0 otherwise).
    pub sample_period_us: u64,
    /// Width of an input pulse, and the least time between two edges of one input pin, in µs.
    pub input_pulse_us: u64,
    /// A command level undone sooner than this (µs) counts as a short pulse.
    pub short_pulse_us: u64,
    /// `apart`: an edge waits until the firmware has read the one before (order kept); `together`: not.
    pub order: String,
    /// Whether input edges may arrive while a command pulse is high.
    pub inputs_during_pulses: bool,
    /// Times the board was powered on (the first boot and one per RESET).
    pub boots: u64,
    /// Emulated time of the run, in milliseconds.
    pub emulated_ms: u64,
    /// Core cycles of the run.
    pub cycles: u64,
    /// Nanoseconds per core cycle (the 125 MHz system clock).
    pub cycle_ns: u64,
    /// Random bits the firmware read from the ring oscillator.
    pub rosc_bits: u64,
    /// Input edges that made an event.
    pub edges: u64,
    /// Events that waited for their pin to be free again (a pin changes at most once per pulse width).
    pub deferred: u64,
    /// Events that waited for a command pulse to end.
    pub after_pulse: u64,
    /// Longest an event waited for its edge, in µs of emulated time.
    pub longest_wait_us: u64,
    /// Most events waiting for their edges at once.
    pub longest_queue: u64,
    /// Events whose edge came while the firmware had not read the one before: two edges in one read
    /// (simultaneity), which the firmware takes in its pin table's order, not in the order they came.
    pub simultaneous: u64,
    /// Of those, the ones that waited for the read because the firmware would have taken them first: on
    /// real pins their order would have been lost.
    pub kept_in_order: u64,
    /// Edges the firmware never saw (a pulse between two samples, or a latch still full).
    pub missed: u64,
    /// Edges that arrived while the firmware was inside `decide` (inexact synchronisation).
    pub during_decide: u64,
    /// Events with no input pin.
    pub unmapped: u64,
    /// Events a level pin could not show (it already had the level).
    pub impossible: u64,
    /// Commands the output pins showed.
    pub commands_seen: u64,
    /// Command levels undone within `short_pulse_us`: a plant filtering shorter levels misses them.
    pub short_pulses: u64,
    /// Commands the firmware counted as fired that no output edge showed.
    pub hidden_commands: u64,
    /// Host bytes the harness does not know.
    pub host_unknown: u64,
    /// STATUS or EXIT answers given before every edge had been read (after a time limit).
    pub forced_answers: u64,
    /// The emulator's first warnings (reads of peripherals it does not model, …).
    pub emulator_warnings: Vec<String>,
    /// Cost of the runtime's entry points.
    pub cost: RuntimeCost,
}

impl fmt::Display for BoardFigures {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let period = if self.sampling == "timer" {
            format!(" every {} µs", self.sample_period_us)
        } else {
            String::new()
        };
        writeln!(
            f,
            "  pins      {} ({} sampling{period}), {} ms emulated, {} boots: {} input edges, {} simultaneous \
             ({} kept in order), {} missed, {} during a decision, {} deferred, {} after a pulse (longest wait \
             {} µs); {} commands seen, {} short pulses (< {} µs), {} fired but not shown",
            self.target,
            self.sampling,
            self.emulated_ms,
            self.boots,
            self.edges,
            self.simultaneous,
            self.kept_in_order,
            self.missed,
            self.during_decide,
            self.deferred,
            self.after_pulse,
            self.longest_wait_us,
            self.commands_seen,
            self.short_pulses,
            self.short_pulse_us,
            self.hidden_commands,
        )?;
        let c = &self.cost;
        writeln!(
            f,
            "  M0+ cost  apply avg {:.0} / max {} cycles ({:.0} / {} instructions), decision avg {:.0} / max {} \
             cycles ({:.0} / {} instructions), nothing enabled {:.0} cycles",
            c.apply.avg_cycles,
            c.apply.max_cycles,
            c.apply.avg_instructions,
            c.apply.max_instructions,
            c.decision.avg_cycles,
            c.decision.max_cycles,
            c.decision.avg_instructions,
            c.decision.max_instructions,
            c.idle_decision.avg_cycles,
        )?;
        for w in &self.emulator_warnings {
            writeln!(f, "            emulator: {w}")?;
        }
        Ok(())
    }
}
