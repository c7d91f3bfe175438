//! A run of N events from the simulation's current state, made of the parts `codegen run` drives a
//! firmware with: the virtual plant ([`crate::plant::VirtualPlant`]) producing the plant's events and
//! steered by the monitor ([`crate::monitor::Monitor::next_move`], `rank_after`) towards supervisor
//! transitions not taken yet, and the controller deciding by the firmware's own choice policy
//! ([`super::controller`]). The turns are those of a session in steps
//! ([`crate::closed_loop::SessionConfig::step`]): the plant produces what the steering prefers to the
//! controller's choice (at most a burst), then the controller decides once.

use crate::closed_loop::{parts, Options};
use crate::model::ModelError;
use crate::monitor::{ChoiceModel, Move};
use crate::plant::PlantConfig;

use super::controller::Controller;
use super::{Actor, Sim};

/// Most plant events in one turn before the controller decides (the session's steered burst).
const MAX_BURST: usize = 8;
/// The monitor's clock per event: far beyond its read window, so the controller has read every event
/// before it decides (as in lock-step).
const TICK_US: u64 = 1 << 32;

/// Runs `events` events from `sim`'s current state; see the module documentation.
pub fn run(sim: &mut Sim, events: u64) -> Result<usize, ModelError> {
    let seed = sim.runtime.seed.wrapping_add(sim.runs);
    sim.runs += 1;
    let options = Options {
        plant: PlantConfig { seed, ..PlantConfig::default() },
        choices: ChoiceModel::of(sim.runtime.policy),
        ..Options::default()
    };
    let (mut plant, mut monitor) = parts(&sim.set, &options)?;
    monitor.plant_answers_commands(true);
    let runtime = crate::config::RuntimeConfig { seed, ..sim.runtime.clone() };
    let Some(mut controller) = Controller::new(&runtime, &sim.closed, sim.plants, sim.set.events()) else {
        return Ok(0);
    };
    // The monitor learns the trace so far (its coverage steers), the plant takes its state.
    let mut t = 0u64;
    for step in &sim.trace {
        t += TICK_US;
        if sim.set.events().is_controllable(step.event) {
            monitor.command(step.event, t);
        } else {
            monitor.uncontrollable(step.event, t);
        }
    }
    plant.set_state(&sim.state()[..sim.plants]);
    let mut taken = 0usize;
    let target = usize::try_from(events).unwrap_or(usize::MAX);
    while taken < target {
        let mut moved = false;
        let mut burst = 0;
        while taken < target && burst < MAX_BURST && monitor.next_move() != Move::Controller {
            let Some(e) = plant.emit_one(|e| monitor.rank_after(e)) else { break };
            t += TICK_US;
            monitor.uncontrollable(e, t);
            if sim.step(e, Actor::Plant).is_err() {
                return Ok(taken); // the plant's event refused by a supervisor: the run stops there
            }
            taken += 1;
            burst += 1;
            moved = true;
        }
        if taken >= target {
            break;
        }
        if let Some(c) = controller.decide(&sim.closed, sim.state()) {
            t += TICK_US;
            monitor.command(c, t);
            // The command is enabled by every automaton, the plant's included.
            let _ = plant.command(c);
            if sim.step(c, Actor::Controller).is_err() {
                return Ok(taken);
            }
            taken += 1;
        } else if !moved {
            // No command: the plant moves on its own timing, or the loop is blocked.
            let Some(e) = plant.emit_one(|_| None) else { break };
            t += TICK_US;
            monitor.uncontrollable(e, t);
            if sim.step(e, Actor::Plant).is_err() {
                return Ok(taken);
            }
            taken += 1;
        }
    }
    Ok(taken)
}
