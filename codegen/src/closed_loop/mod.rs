//! The closed loop: a supervisor set's plants as the [virtual plant](crate::plant), its plants ‖
//! supervisors as the [monitor](crate::monitor), attached to a firmware over a [link](crate::link) — one
//! that is already running ([`attach`]), or a firmware image booted under an emulator for the run: QEMU
//! ([`run_under_qemu`]), or a Pico image on an emulated RP2040: the link build over its UART0
//! ([`run_on_rp2040_link`]) or the pin application through its pins ([`run_on_rp2040`]).
//! The [`Session`] drives the link protocol's control side.

mod session;

pub use session::{OwnDelays, Session, SessionConfig, SessionError};

use std::path::Path;
use std::time::Duration;

use crate::link::protocol::EXIT;
use crate::link::ByteLink;
use crate::manifest::TimerSpec;
use crate::model::{Automaton, ModelError};
use crate::monitor::{ChoiceModel, Monitor, Report, Timers};
use crate::pack::{PackSet, Role};
use crate::plant::{PlantConfig, VirtualPlant};
use crate::target::qemu::{Qemu, QemuConfig, QemuError};
use crate::target::rp2040::{Harness, HarnessConfig, HarnessError};

/// How long an emulator has to leave once the firmware was told to (EXIT): it takes milliseconds; the
/// rest is margin for a loaded machine (the wait ends as soon as it is gone).
const EXIT_WITHIN: Duration = Duration::from_secs(30);

/// Everything a closed-loop run is configured by, besides the supervisor set.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// Events (commands plus plant events) to run for.
    pub events: u64,
    /// The virtual plant's timing and seed.
    pub plant: PlantConfig,
    /// The session's timeouts.
    pub session: SessionConfig,
    /// How long (µs) an event may stay unread by the controller before a command must account for it.
    pub window_us: u64,
    /// How to start QEMU.
    pub qemu: QemuConfig,
    /// How to start the RP2040 harness.
    pub rp2040: HarnessConfig,
    /// The controller's choice policy as the plant's steering models it.
    pub choices: ChoiceModel,
    /// The digests of the tables the firmware must run ([`crate::project::Project::table_digests`]):
    /// asked over the link before the run ([`Session::check_tables`]), a firmware that runs others is
    /// refused. Empty: not asked — the RP2040 pin harness and the PLC driver do not speak TABLES.
    pub tables: Vec<String>,
    /// The project's `[[timers]]`: their timeouts are the target's to raise (the plant withholds them)
    /// and the monitor judges them against deadlines in the session's virtual time (see
    /// [`Session`]'s documentation). Empty: no virtual time, no TIME message.
    pub timers: Vec<TimerSpec>,
    /// How long after its deadline the target may raise a timeout, in ms: 0 for a firmware (it counts
    /// whole milliseconds), a scan cycle for a PLC program ([`crate::plc::closed_loop`]).
    pub timer_slack_ms: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            events: 10_000,
            plant: PlantConfig::default(),
            session: SessionConfig::default(),
            window_us: 500_000,
            qemu: QemuConfig::default(),
            rp2040: HarnessConfig::default(),
            choices: ChoiceModel::RandomLocalQueue,
            tables: Vec::new(),
            timers: Vec::new(),
            timer_slack_ms: 0,
        }
    }
}

impl Options {
    /// The default options for a run of `events` events, with QEMU's deadline stretched to match: one
    /// minute plus 10 ms per event (a floor of 100 events per second, well below what the loop sustains).
    pub fn for_events(events: u64) -> Self {
        let mut options = Options { events, ..Options::default() };
        options.qemu.timeout = Duration::from_secs(60)
            + Duration::from_millis(10).saturating_mul(u32::try_from(events).unwrap_or(u32::MAX));
        options.rp2040.timeout = options.qemu.timeout;
        options
    }
}

/// A closed-loop run failed (as opposed to finding violations, which are in its report).
#[derive(Debug, thiserror::Error)]
pub enum ClosedLoopError {
    /// The set's automata do not compose.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The emulator did not start.
    #[error(transparent)]
    Qemu(#[from] QemuError),
    /// The RP2040 harness did not start, or its figures could not be read.
    #[error(transparent)]
    Harness(#[from] HarnessError),
    /// The firmware did not leave cleanly when the run was over.
    #[error("the firmware's exit after the run: {status}{}", if stderr.is_empty() { String::new() } else { format!("\nemulator stderr: {stderr}") })]
    Exit {
        /// The emulator's exit status, or why there is none.
        status: String,
        /// What the emulator printed on stderr.
        stderr: String,
    },
    /// Talking to the firmware failed.
    #[error("{source}{}", if stderr.is_empty() { String::new() } else { format!("\nemulator stderr: {stderr}") })]
    Session {
        /// Why.
        source: SessionError,
        /// What the emulator printed on stderr, if it ran.
        stderr: String,
    },
}

impl ClosedLoopError {
    /// `self` with what the emulator printed on stderr, if it is a session's failure: what the firmware
    /// did before the link failed is often only there.
    fn with_stderr(self, stderr: impl FnOnce() -> String) -> Self {
        match self {
            ClosedLoopError::Session { source, .. } => ClosedLoopError::Session { source, stderr: stderr() },
            other => other,
        }
    }
}

impl From<SessionError> for ClosedLoopError {
    fn from(source: SessionError) -> Self {
        ClosedLoopError::Session { source, stderr: String::new() }
    }
}

/// The virtual plant and the monitor for `set` (plants drive, plants ‖ supervisors judge).
pub fn parts(set: &PackSet, options: &Options) -> Result<(VirtualPlant, Monitor), ModelError> {
    let of = |role| -> Vec<&Automaton> {
        set.members().iter().filter(|m| m.role == role).map(|m| &m.automaton).collect()
    };
    let (plants, supervisors) = (of(Role::Plant), of(Role::Supervisor));
    let mut plant = VirtualPlant::new(&plants, set.events(), options.plant.clone())?;
    let mut monitor = Monitor::new(&plants, &supervisors, set.events(), options.window_us)?;
    let timers = Timers::new(&options.timers, set.events(), options.timer_slack_ms);
    plant.withhold(timers.timeouts());
    monitor.set_timers(timers);
    monitor.model_choices(options.choices);
    monitor.plant_answers_commands(options.session.step && plant.steers());
    Ok((plant, monitor))
}

/// Runs the closed loop over an open `link` to a firmware running `set`; returns the report. The
/// firmware is left on hold. With [`Options::tables`], a firmware that does not report one of them is
/// refused before anything runs.
pub fn attach(
    link: &mut dyn ByteLink,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, ClosedLoopError> {
    let (mut plant, mut monitor) = parts(set, options)?;
    monitor.report_mut().target = "link".into();
    monitor.report_mut().name = name.to_owned();
    monitor.report_mut().seed = options.plant.seed;
    let mut session = Session::new(link, &mut plant, &mut monitor, options.session.clone());
    if !options.tables.is_empty() {
        session.check_tables(&options.tables)?;
    }
    session.sync(false)?;
    session.run(options.events, progress)?;
    Ok(session.finish()?)
}

/// Boots `elf` under QEMU, runs the closed loop, tells the firmware to exit and stops QEMU.
pub fn run_under_qemu(
    elf: &Path,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, ClosedLoopError> {
    let (mut qemu, mut link) = Qemu::start(elf, &options.qemu)?;
    let mut report =
        attach(&mut link, set, name, options, progress).map_err(|e| e.with_stderr(|| qemu.stderr()))?;
    report.target = "qemu".into();
    // The firmware must leave when told, with status 0 — or 1 where it ended in the safe state, which
    // the monitor has counted as a violation. Anything else (a panic, a hang, a crash of the emulator)
    // fails the run.
    let sent = link.send(&[EXIT]);
    let status = qemu.wait(EXIT_WITHIN);
    match status.and_then(|s| s.code()) {
        Some(0) if sent.is_ok() => Ok(report),
        Some(1) if sent.is_ok() && report.violations > 0 => Ok(report),
        _ => Err(ClosedLoopError::Exit {
            status: status.map_or_else(
                || format!("still running {} s after EXIT (killed)", EXIT_WITHIN.as_secs()),
                |s| s.to_string(),
            ),
            stderr: qemu.stderr(),
        }),
    }
}

/// Runs the Pico image `elf` on the RP2040 harness with the pin map file `pins`
/// ([`crate::target::rp2040::pin_map`]), runs the closed loop through its pins, ends the run and adds the
/// harness's figures (what only pins show, the runtime's cost on the M0+) to the report.
/// The harness has no lock-step rounds nor steps: the run takes the plant's realtime timing whatever
/// `options` say.
pub fn run_on_rp2040(
    elf: &Path,
    pins: &Path,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, ClosedLoopError> {
    let (mut harness, mut link) = Harness::start(elf, pins, &options.rp2040)?;
    // The harness speaks the protocol for the board's pins, without lock-step rounds, STEP or TABLES.
    let options = &Options {
        session: SessionConfig { lockstep: false, step: false, ..options.session.clone() },
        tables: Vec::new(),
        ..options.clone()
    };
    let mut report =
        attach(&mut link, set, name, options, progress).map_err(|e| e.with_stderr(|| harness.stderr()))?;
    report.target = "rp2040".into();
    let _ = link.send(&[EXIT]);
    drop(link);
    harness.wait(EXIT_WITHIN);
    report.board = Some(harness.figures()?);
    Ok(report)
}

/// Runs the Pico's link build `elf` (`cell-pico-link`) on the RP2040 harness, its UART0 the link, and
/// runs the closed loop as [`run_under_qemu`] does — in lock-step rounds and steps unless `options` say
/// otherwise, so the report has the same liveness and coverage as QEMU's. The board cannot obey EXIT:
/// the run ends by closing the link, and the harness must then leave cleanly.
pub fn run_on_rp2040_link(
    elf: &Path,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, ClosedLoopError> {
    let (mut harness, mut link) = Harness::start_uart(elf, &options.rp2040)?;
    let mut report =
        attach(&mut link, set, name, options, progress).map_err(|e| e.with_stderr(|| harness.stderr()))?;
    report.target = "rp2040".into();
    drop(link);
    match harness.wait(EXIT_WITHIN).and_then(|s| s.code()) {
        Some(0) => Ok(report),
        status => Err(ClosedLoopError::Exit {
            status: status.map_or_else(
                || format!("no exit code {} s after the link closed", EXIT_WITHIN.as_secs()),
                |c| format!("the harness exited with status {c}"),
            ),
            stderr: harness.stderr(),
        }),
    }
}
