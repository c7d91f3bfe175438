//! The state-based program run closed loop (`codegen run --target plc --encoding state`): its `.st`
//! text under the scan-cycle interpreter, behind the same wrapper as the event-based program
//! ([`crate::plc::closed_loop::spawn_plc`]), so the same session, monitor and report judge it.
//!
//! The program reads sensor signals and writes actuator signals, so the driver ([`StateDriver`])
//! translates between the plant's events and the program's signal image with the state vectors the
//! program is generated from ([`Vector`], the manifest's `[state]` section): an uncontrollable event
//! byte moves the driver's copy of its plant and sets the input signals the target state's formula
//! fixes ([`Vector::after`]); after a scan, the rungs that conducted as the program ran (the `IF`s of
//! its `rungs` section that took their arm, [`Plc::arms_taken`]; with a choice policy, the rung the
//! program chose, its `c`) are the commands fired, in rung order, each moving its plant. The outputs must then be what those commands wrote, else the run stops (the
//! program's error). The event trace the monitor judges is recovered from these signal changes.
//!
//! A program keeping supervisors' memory reads each tracked component's sensor changes scan by scan,
//! so it must see every change in a scan of its own, as a PLC does when its sensors change between
//! scans; it has a `hold` input ([`super::memory::HOLD`]) for that: held, the driver sets it and makes
//! one event's change per scan, the memory following each while no rung fires, as the event-based
//! driver does. A program without memory has no `hold`: held, it is not scanned (a PLC in STOP), and
//! the events sent meanwhile all change the image before the next scan reads it — as the firmware
//! takes a whole write before it decides; its decisions depend on the image alone. Unheld, one event
//! changes the image per scan. The scan figures count the scans that read a changed input or fired a
//! command.

use std::collections::BTreeSet;

use firmware::link::MAX_EVENT;

use super::memory::HOLD;
use super::Output;
use crate::closed_loop::Options;
use crate::config::ScanPolicy;
use crate::feedback::Vector;
use crate::interpreter::{Plc, Stmt};
use crate::link::memory;
use crate::model::EventId;
use crate::monitor::{ChoiceModel, Report};
use crate::pack::{Member, PackSet, Role};
use crate::plc::closed_loop::{run_spawned, spawn_plc, Edge, Facts, RunError, Scan, Scanner};

/// The state-based program, its plants and its signal image, as the wrapper drives them.
pub struct StateDriver {
    /// The interpreter.
    pub plc: Plc,
    /// The program as loaded, for RESET.
    initial: Plc,
    /// The set's plants, in the vector's order.
    plants: Vec<Member>,
    /// Per plant, its uncontrollable events.
    sensed: Vec<BTreeSet<EventId>>,
    vector: Vector,
    /// The signals' variable names, bit `k` of the image being signal `k`.
    names: Vec<String>,
    /// Per rung, its event.
    rungs: Vec<EventId>,
    /// Where the rungs start in the program's body: the statement after the `rungs` section's marker.
    first_rung: usize,
    /// The program fires the one rung its policy chooses (`c`), not every rung that conducts.
    chooses: bool,
    /// The program has a `hold` input (it keeps memory): held, it is scanned once per event.
    holds: bool,
    /// The plants' states.
    states: Vec<u32>,
    /// The signal image.
    image: u64,
    held: bool,
    /// An input changed since the last scan.
    changed: bool,
    events_in: u32,
    commands_out: u32,
}

impl StateDriver {
    /// A driver for the state-based program `out` of `set`, its image written for the initial state.
    pub fn new(out: &Output, set: &PackSet) -> Result<StateDriver, String> {
        let text = out.files.first().map(|(_, text)| text.as_str()).ok_or("no program file")?;
        let plc = Plc::load(text)?;
        let plants: Vec<Member> = set.members().iter().filter(|m| m.role == Role::Plant).cloned().collect();
        let events = set.events();
        let on_link = |e: EventId| {
            u8::try_from(e.as_u32())
                .ok()
                .filter(|&b| b <= MAX_EVENT)
                .map(|_| e)
                .ok_or(format!("event {} has an id beyond the link", events.name(e)))
        };
        let sensed = plants
            .iter()
            .map(|m| m.alphabet().into_iter().filter(|&e| !events.is_controllable(e)).map(on_link).collect())
            .collect::<Result<_, String>>()?;
        let rungs = out
            .rungs
            .iter()
            .map(|r| events.id(&r.event).ok_or(format!("rung event {} is not in the set", r.event)))
            .map(|e| e.and_then(on_link))
            .collect::<Result<_, String>>()?;
        let body = plc.body(&format!("{}_main", out.sources.first().map_or("", |s| s.program.base.as_str())));
        let first_rung = body
            .and_then(|b| b.iter().position(|s| matches!(s, Stmt::Section(l) if l == "rungs")))
            .map(|k| k + 1)
            .ok_or("the program has no rungs section")?;
        let mut d = StateDriver {
            first_rung,
            initial: plc.clone(),
            plc,
            plants,
            sensed,
            vector: out.vector.clone(),
            names: out.vector.signals.signals.iter().map(|s| s.name.clone()).collect(),
            rungs,
            chooses: out.one.is_some(),
            holds: !out.memory.vars.is_empty(),
            states: Vec::new(),
            image: 0,
            held: false,
            changed: false,
            events_in: 0,
            commands_out: 0,
        };
        Scanner::reset(&mut d)?;
        Ok(d)
    }

    /// Writes the image's signals (`mask` of them) into the program.
    fn write(&mut self, mask: u64) -> Result<(), String> {
        for (k, name) in self.names.iter().enumerate().filter(|&(k, _)| mask >> k & 1 == 1) {
            self.plc.set_bool(name, self.image >> k & 1 == 1)?;
        }
        Ok(())
    }

    /// Plant `p` takes `e`: its state and the signals `e` changes.
    fn take(&mut self, p: usize, e: EventId) -> Result<(), String> {
        let plant = &self.plants[p];
        let target = plant.dfa.step(self.states[p], e.as_u32()).ok_or_else(|| {
            format!("{} cannot take event {} in state {}", plant.name(), e.as_u32(), self.states[p])
        })?;
        self.image = self.vector.after(p, e, target as usize, self.image);
        self.states[p] = target;
        Ok(())
    }
}

impl Scanner for StateDriver {
    fn has_input(&self, e: u8) -> bool {
        self.sensed.iter().any(|s| s.contains(&EventId::from_u32(u32::from(e))))
    }

    fn edge(&mut self, e: u8, used: &mut Vec<String>) -> Result<Edge, String> {
        // One change per scan, unless the program is held and cannot be (it is not scanned then).
        let scanned = !self.held || self.holds;
        if scanned && !used.is_empty() {
            return Ok(Edge::Busy);
        }
        let e = EventId::from_u32(u32::from(e));
        for p in 0..self.plants.len() {
            if self.sensed[p].contains(&e) {
                self.take(p, e)?;
            }
        }
        let inputs = !self.vector.signals.outputs();
        self.write(inputs)?;
        self.changed = true;
        self.events_in += 1;
        if scanned {
            used.push("image".into());
        }
        Ok(Edge::Made)
    }

    fn hold(&mut self, on: bool) -> Result<(), String> {
        self.held = on;
        if self.holds {
            self.plc.set_bool(HOLD, on)?;
        }
        Ok(())
    }

    fn held(&self) -> Result<bool, String> {
        Ok(self.held)
    }

    fn pending(&self) -> Result<bool, String> {
        Ok(false)
    }

    fn safe(&self) -> Result<bool, String> {
        Ok(false)
    }

    fn scan(&mut self) -> Result<Scan, String> {
        if self.held && !self.holds {
            return Ok(Scan::default());
        }
        let statements = self.plc.scan()?;
        let mut after = 0u64;
        for (k, name) in self.names.iter().enumerate() {
            after |= u64::from(self.plc.get_bool(name)?) << k;
        }
        let chosen = if self.chooses { Some(self.plc.get_int("c")?) } else { None };
        let conducted = self.plc.arms_taken().get(self.first_rung..).unwrap_or_default().to_vec();
        let mut commands = Vec::new();
        for k in 0..self.rungs.len() {
            let e = self.rungs[k];
            let Some((p, _)) = self.vector.commands.get(e.index()).copied().flatten() else { continue };
            let fired = match chosen {
                Some(c) => c == k as i64,
                // Without a policy every rung that conducts on the image as the rungs above left it
                // writes its command, in rung order: one scan firing σ1 then σ2 is the trace σ1σ2,
                // whatever outputs σ2 writes over σ1's.
                None => conducted.get(k).copied().unwrap_or(false),
            };
            // A rung conducting where its plant has no such transition is no event (f leaves the
            // physically impossible free); its outputs are checked below.
            let possible = self.plants[p].dfa.step(self.states[p], e.as_u32()).is_some();
            if fired && possible {
                self.take(p, e)?;
                commands.push(e.as_u32() as u8);
            }
        }
        let outputs = self.vector.signals.outputs();
        if after & outputs != self.image & outputs {
            return Err(format!(
                "the outputs ({:#x}) are not what the commands fired ({commands:?}) wrote ({:#x})",
                after & outputs,
                self.image & outputs
            ));
        }
        self.commands_out += commands.len() as u32;
        let worked = std::mem::take(&mut self.changed) || !commands.is_empty();
        Ok(Scan { timeouts: Vec::new(), commands, statements: worked.then_some(statements) })
    }

    fn reset(&mut self) -> Result<(), String> {
        self.plc = self.initial.clone();
        if self.holds {
            // RESET does not release the program: it stays held as it was.
            self.plc.set_bool(HOLD, self.held)?;
        }
        self.states = self.plants.iter().map(|m| m.initial().as_u32()).collect();
        self.image = self.vector.initial;
        self.write(u64::MAX)?;
        self.changed = false;
        self.events_in = 0;
        self.commands_out = 0;
        Ok(())
    }

    fn status(&self, unknown: u32) -> Result<[u32; 6], String> {
        Ok([self.events_in, self.commands_out, 0, 0, 0, unknown])
    }
}

/// Runs the state-based program `out` of `set` closed loop against `set`'s plants, judged by plants ‖
/// supervisors, for `options.events` events, as [`crate::plc::closed_loop::run`] runs the event-based
/// one: the same session in lock-step rounds and steps, the same report with the scan figures (the
/// static bound: every POU's body run once). The monitor models `first` as the firmware's; the other
/// policies, and the rung order without one, as a uniform choice.
pub fn run(
    out: &Output,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, RunError> {
    let mut driver = StateDriver::new(out, set).map_err(RunError::Program)?;
    driver.plc.set_cycle_ms(out.report.cycle_ms);
    let facts = Facts {
        bound_per_scan: out.sources.iter().flat_map(|s| &s.program.pous).map(|(pou, _)| pou.bound()).sum(),
        cycle_ms: out.report.cycle_ms,
        choices: match out.one.as_ref().map(|o| o.policy) {
            Some(ScanPolicy::First) => ChoiceModel::First,
            _ => ChoiceModel::Uniform,
        },
    };
    let (host, target) = memory::pair();
    let plc = spawn_plc(driver, target);
    run_spawned(host, plc, &facts, set, name, options, progress)
}
