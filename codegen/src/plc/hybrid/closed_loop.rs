//! A hybrid controller run closed loop (`codegen run --target plc` on a `[hybrid]` manifest): its
//! `.st` text under the scan-cycle interpreter against the plant net's own token game
//! ([`NetPlant`]), scan by scan on the PLC's clock, judged by the same monitor and reported in the
//! same [`Report`] as the other programs' runs.
//!
//! The controller runs the whole net itself — the plant's uncontrollable transitions too, on its
//! timers and on the conditions its sensors make true — so there is no event for a plant to send
//! and no command to wait for: the run is one loop, no link. Each scan the plant sets the sensors,
//! the program scans, and the firing it made (at most one a scan, its place bits before and after) is
//! checked by the plant and becomes its event (`[hybrid.events]`): a controllable one is a command
//! to the monitor, an uncontrollable one the plant's event, judged against plant ‖ supervisor (the
//! net's reachability graph and `SUPER`, whichever controller runs) with its coverage and liveness.
//! The program reads every event the scan it happens, so the monitor's window is zero: no command is
//! decided on stale information. A violation, the monitor's or the plant's (a firing the net cannot
//! make, a condition false, a delay cut short, an actuator the marking does not set), is counted
//! and the run goes on from the initial state (program, plant and monitor reset: a resync) — unless
//! no event passed the monitor since the last reset: then the program fails again at once, and the
//! run ends there. A run
//! with no firing for longer than a correct program can take ([`NetPlant::patience`]) stops with
//! one stall.
//!
//! Nothing depends on the machine's timing: the plant's draws come from the seed, the clock is the
//! scan count (`cycle_ms` each, every scan counted), so the same seed gives the same report.

use super::plant::{Finding, NetPlant};
use super::Plant;
use crate::closed_loop::Options;
use crate::interpreter::Plc;
use crate::model::Automaton;
use crate::monitor::{FirmwareCounters, Monitor, Report, ScanFigures, Verdict};
use crate::net::interpretation::Direction;
use crate::pack::PackSet;
use crate::plc::closed_loop::RunError;
use crate::plc::token_passing::Idents;

/// Most findings a report keeps (as the monitor's).
const MAX_FINDINGS: usize = 10;

/// One hybrid controller and what its run needs of it.
#[derive(Clone, Copy, Debug)]
pub struct Program<'a> {
    /// The `.st` file's text.
    pub text: &'a str,
    /// The static bound on statements per scan.
    pub bound_per_scan: u64,
    /// The task's interval, in milliseconds.
    pub cycle_ms: u32,
}

/// The program as loaded and booted, and the variables of the net's places and signals (named as
/// the controller names them, [`Idents`]), each signal with its direction.
struct Scanned {
    booted: Plc,
    plc: Plc,
    places: Vec<String>,
    signals: Vec<(String, Direction)>,
}

impl Scanned {
    fn marking(&self) -> Result<Vec<u32>, String> {
        self.places.iter().map(|p| self.plc.get_bool(p).map(u32::from)).collect()
    }

    /// Per signal, the program's value (sensors as last written).
    fn signals(&self) -> Result<Vec<bool>, String> {
        self.signals.iter().map(|(v, _)| self.plc.get_bool(v)).collect()
    }

    fn write_sensors(&mut self, levels: &[bool]) -> Result<(), String> {
        for ((v, d), &level) in self.signals.iter().zip(levels) {
            if *d == Direction::Input {
                self.plc.set_bool(v, level)?;
            }
        }
        Ok(())
    }
}

/// Runs `program` against `plant`'s net for `options.events` events, judged by `set` (the net's
/// reachability graph ‖ the supervisor); see the module documentation. The report's target is `plc`,
/// its time the PLC's clock (scans × `cycle_ms`).
pub fn run(
    program: Program<'_>,
    plant: &Plant,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, RunError> {
    let mut plc = Plc::load(program.text).map_err(RunError::Program)?;
    plc.set_cycle_ms(program.cycle_ms);
    // The boot scan: network 0 sets the initial marking and the supervisor's initial state.
    plc.scan().map_err(RunError::Program)?;
    let id = Idents::new(&plant.net);
    let signals = id.signal.into_iter().zip(plant.net.signals.iter().map(|s| s.direction)).collect();
    let mut prog = Scanned { booted: plc.clone(), plc, places: id.place, signals };
    let of = |role| -> Vec<&Automaton> {
        set.members().iter().filter(|m| m.role == role).map(|m| &m.automaton).collect()
    };
    let mut monitor =
        Monitor::new(&of(crate::pack::Role::Plant), &of(crate::pack::Role::Supervisor), set.events(), 0)
            .map_err(crate::closed_loop::ClosedLoopError::from)?;
    let report = monitor.report_mut();
    report.target = "plc".into();
    report.name = name.to_owned();
    report.seed = options.plant.seed;
    let mut net = NetPlant::new(&plant.net, program.cycle_ms, options.plant.seed);
    if prog.marking().map_err(RunError::Program)? != net.marking() {
        return Err(RunError::Program("the boot scan does not set the net's initial marking".into()));
    }
    let (mut scans, mut max_statements, mut last_firing) = (0u64, 0u64, 0u64);
    let mut counters = FirmwareCounters::default();
    // Events the monitor accepted since the (re)start.
    let mut accepted = 0u64;
    // The scan number since the last reset (the plant's clock; the boot scan is 0).
    let mut clock = 0u64;
    while monitor.report().events < options.events {
        clock += 1;
        scans += 1;
        let outputs = prog.signals().map_err(RunError::Program)?;
        let levels = net.sense(clock, &outputs);
        prog.write_sensors(&levels).map_err(RunError::Program)?;
        let before = prog.marking().map_err(RunError::Program)?;
        let statements = prog.plc.scan().map_err(RunError::Program)?;
        max_statements = max_statements.max(statements);
        let after = prog.marking().map_err(RunError::Program)?;
        let t_us = scans * u64::from(program.cycle_ms) * 1000;
        let mut failed = None;
        if before != after {
            last_firing = scans;
            match net.fire(clock, &before, &after, &levels) {
                Err(Finding(why)) => failed = Some(why),
                Ok(t) => {
                    let event = &plant.labels.events[t];
                    let id = set
                        .events()
                        .id(event)
                        .ok_or_else(|| RunError::Program(format!("event {event} is not in the set")))?;
                    let verdict = if set.events().is_controllable(id) {
                        counters.commands_out += 1;
                        monitor.command(id, t_us)
                    } else {
                        counters.events_in += 1;
                        monitor.uncontrollable(id, t_us)
                    };
                    if matches!(verdict, Verdict::Ok | Verdict::Desync { resolved: true }) {
                        accepted += 1;
                    } else {
                        failed = Some(String::new());
                    }
                    progress(monitor.report());
                }
            }
        }
        if failed.is_none() {
            if let Err(Finding(why)) = net.check_outputs(&prog.signals().map_err(RunError::Program)?) {
                failed = Some(why);
            }
        }
        if let Some(why) = failed {
            // The monitor has counted its own; the plant's are counted here.
            if !why.is_empty() {
                plant_violation(&mut monitor, &format!("scan {scans}: {why}"));
            }
            if std::mem::take(&mut accepted) == 0 {
                break;
            }
            prog.plc = prog.booted.clone();
            net.reset();
            monitor.reset();
            monitor.report_mut().resyncs += 1;
            clock = 0;
            last_firing = scans;
        } else if scans - last_firing > net.patience() {
            monitor.report_mut().stalls += 1;
            break;
        }
    }
    monitor.firmware_counters(counters);
    monitor.list_uncovered();
    let mut report = monitor.report().clone();
    report.scan = Some(ScanFigures {
        scans,
        max_statements,
        bound_per_scan: program.bound_per_scan,
        cycle_ms: program.cycle_ms,
    });
    report.finish(scans as f64 * f64::from(program.cycle_ms) / 1000.0);
    Ok(report)
}

/// Counts a violation only the plant saw, with its message, as the monitor counts its own.
fn plant_violation(monitor: &mut Monitor, message: &str) {
    let report = monitor.report_mut();
    report.violations += 1;
    if report.findings.len() < MAX_FINDINGS {
        report.findings.push(format!("event {}: the plant: {message}", report.events));
    }
}
