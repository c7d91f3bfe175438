//! `codegen plant`: the virtual plant against a firmware that is already running (QEMU started by hand,
//! or a board on a serial port); and the options and output it shares with `codegen run`.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use codegen::closed_loop::{attach, Options, SessionConfig};
use codegen::config::RuntimeConfig;
use codegen::link::Endpoint;
use codegen::monitor::{ChoiceModel, Report};
use codegen::plant::PlantConfig;
use codegen::project::user_project::UserProject;
use codegen::project::Project;

use super::Error;

/// Run the virtual plant against a running firmware: it answers the firmware's commands with the plant
/// models' events, judges every event against plants ‖ supervisors and prints the closed-loop report.
///
/// The firmware must run the tables of the same manifest (`codegen emit`, or a project of your own
/// built from it: `--project DIR`): it is asked which it runs, and one that runs others is refused
/// (exit 2). Exit status 1 when the run saw a safety violation.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project manifest (plants, specifications or supervisors, `[runtime]`).
    #[arg(default_value = "examples/cell/cell.toml")]
    manifest: PathBuf,
    /// A project of your own (`codegen new DIR --board B`) running on its board: the plant and the
    /// monitor take DIR's manifest (`model/*.toml`), the one its tables were built from.
    #[arg(long, value_name = "DIR", conflicts_with = "manifest")]
    project: Option<PathBuf>,
    /// The firmware's link: unix:PATH (QEMU's UART socket), tcp:HOST:PORT or serial:DEVICE[@BAUD].
    #[arg(long, value_name = "ENDPOINT", env = "CODEGEN_CONNECT")]
    connect: Endpoint,
    /// Plant and report options.
    #[command(flatten)]
    run: RunArgs,
}

/// Options of a closed-loop run, shared by `plant` and `run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Events to run for (the firmware's commands plus the plant's events).
    #[arg(long, default_value_t = 100_000)]
    pub events: u64,
    /// Seed of the virtual plant (default: the manifest's `[runtime] seed`).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Bursts of plant events between two controller reads: PER_MILLE[,MAX] = chance per emission, and
    /// the longest burst.
    #[arg(long, value_name = "PER_MILLE[,MAX]", value_parser = parse_burst, default_value = "100,4")]
    pub burst: Burst,
    /// Races: chance (per mille) that the plant answers a command at once, racing the next decision.
    #[arg(long, value_name = "PER_MILLE", default_value_t = 100)]
    pub race: u32,
    /// Steering: chance (per mille) that the plant picks the event that brings the closed loop soonest
    /// to a supervisor transition not covered yet (0: no steering, the plant's own timing alone).
    #[arg(long, value_name = "PER_MILLE", default_value_t = 1000)]
    pub guide: u32,
    /// Delay before each plant event, in microseconds: MIN..MAX (uniform).
    #[arg(long, value_name = "MIN..MAX", value_parser = parse_delay, default_value = "0..100")]
    pub delay_us: Delay,
    /// A command answered at a rate of its own: the plant's answer to COMMAND comes MIN..MAX µs after
    /// it (uniform; MIN..MIN a fixed delay) instead of after --delay-us. Repeat for several commands.
    #[arg(long, value_name = "COMMAND=MIN..MAX", value_parser = parse_answer_delay)]
    pub answer_delay_us: Vec<(String, Delay)>,
    /// Print the report as JSON (schema version in its `schema` field).
    #[arg(long)]
    pub json: bool,
    /// How plant and firmware take turns: `lockstep` rounds (the same seeds give the same trace,
    /// whatever the table layout or the machine's load; --delay-us and --race play no part), or the
    /// plant's own `realtime` timing, racing the controller's decisions. The RP2040 runs realtime.
    #[arg(long, value_enum, default_value_t = Timing::Lockstep)]
    pub timing: Timing,
}

/// `--timing`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Timing {
    /// Rounds: the plant's events, then the firmware's decisions until it is idle.
    Lockstep,
    /// The plant's delays, bursts and races.
    Realtime,
}

/// `--burst` parsed.
#[derive(Clone, Copy, Debug)]
pub struct Burst {
    per_mille: u32,
    max: usize,
}

/// `--delay-us` parsed.
#[derive(Clone, Copy, Debug)]
pub struct Delay(u64, u64);

fn parse_burst(s: &str) -> Result<Burst, String> {
    let (p, m) = s.split_once(',').unwrap_or((s, "4"));
    let per_mille: u32 = p.parse().map_err(|_| format!("'{p}' is not a per-mille chance"))?;
    let max: usize = m.parse().map_err(|_| format!("'{m}' is not a burst length"))?;
    if per_mille > 1000 {
        return Err(format!("{per_mille} per mille is more than certain"));
    }
    Ok(Burst { per_mille, max })
}

fn parse_delay(s: &str) -> Result<Delay, String> {
    let (lo, hi) = s.split_once("..").ok_or_else(|| format!("'{s}' is not MIN..MAX"))?;
    let lo: u64 = lo.parse().map_err(|_| format!("'{lo}' is not a number of microseconds"))?;
    let hi: u64 = hi.parse().map_err(|_| format!("'{hi}' is not a number of microseconds"))?;
    if hi < lo {
        return Err(format!("empty range {lo}..{hi}"));
    }
    Ok(Delay(lo, hi))
}

fn parse_answer_delay(s: &str) -> Result<(String, Delay), String> {
    let (command, range) = s.split_once('=').ok_or_else(|| format!("'{s}' is not COMMAND=MIN..MAX"))?;
    if command.is_empty() {
        return Err(format!("'{s}' names no command"));
    }
    Ok((command.to_owned(), parse_delay(range)?))
}

impl RunArgs {
    /// The answer delays per command: `--answer-delay-us`, and the manifest's `[runtime] answer_ms`
    /// for the commands it does not name.
    fn answer_delays_us(&self, runtime: &RuntimeConfig) -> Vec<(String, (u64, u64))> {
        let mut out: Vec<(String, (u64, u64))> =
            self.answer_delay_us.iter().map(|(c, d)| (c.clone(), (d.0, d.1))).collect();
        for (command, [lo, hi]) in &runtime.answer_ms {
            if !out.iter().any(|(c, _)| c == command) {
                out.push((command.clone(), (lo.saturating_mul(1000), hi.saturating_mul(1000))));
            }
        }
        out
    }

    /// The closed-loop options for a firmware running `runtime`, with its seed unless `--seed`
    /// overrides it.
    pub fn options(&self, runtime: &RuntimeConfig) -> Options {
        Options {
            choices: ChoiceModel::of(runtime.policy),
            plant: PlantConfig {
                seed: self.seed.unwrap_or(runtime.seed),
                delay_us: (self.delay_us.0, self.delay_us.1),
                answer_delay_us: self.answer_delays_us(runtime),
                burst_per_mille: self.burst.per_mille,
                burst_max: self.burst.max,
                race_per_mille: self.race,
                guide_per_mille: self.guide,
            },
            session: SessionConfig { lockstep: self.timing == Timing::Lockstep, ..SessionConfig::default() },
            ..Options::for_events(self.events)
        }
    }
}

/// Runs `plant`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let manifest = match &args.project {
        Some(dir) => UserProject::open(dir)?.manifest,
        None => args.manifest,
    };
    let project = Project::load(&manifest)?;
    // A firmware that runs other tables is refused before the run (`Options::tables`; the digest holds
    // the timers' specs too). A link build — QEMU's, or a board's on a serial port — runs the tables'
    // timers on the TIME the session sends (no clock of its own there), so the monitor judges each
    // timeout on the session's virtual clock, on its millisecond (slack 0), as `run --target qemu` does.
    let options = Options {
        tables: project.table_digests()?,
        timers: project.timers.clone(),
        timer_slack_ms: 0,
        ..args.run.options(&project.runtime)
    };
    let mut link = args.connect.connect().map_err(|e| format!("connecting to {:?}: {e}", args.connect))?;
    let mut progress = Progress::new(options.events);
    let report = attach(&mut link, &project.set, &project.name, &options, &mut |r| progress.show(r));
    progress.clear();
    finish(&report?, args.run.json)
}

/// Prints the report (table or JSON) and turns its verdict into the exit status.
pub fn finish(report: &Report, json: bool) -> Result<ExitCode, Error> {
    let mut out = std::io::stdout().lock();
    if json {
        serde_json::to_writer_pretty(&mut out, report)?;
        writeln!(out)?;
    } else {
        write!(out, "{report}")?;
    }
    Ok(if report.violations == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// The live one-line progress display on stderr, shown only when stderr is a terminal.
pub struct Progress {
    target: u64,
    live: bool,
    shown: bool,
}

impl Progress {
    /// A display for a run of `target` events.
    pub fn new(target: u64) -> Self {
        Progress { target, live: std::io::stderr().is_terminal(), shown: false }
    }

    /// Redraws the line.
    pub fn show(&mut self, report: &Report) {
        if self.live {
            eprint!("\r{}\x1b[K", report.progress_line(self.target));
            self.shown = true;
        }
    }

    /// Removes the line before the report is printed.
    pub fn clear(&mut self) {
        if self.shown {
            eprint!("\r\x1b[K");
            self.shown = false;
        }
    }
}
