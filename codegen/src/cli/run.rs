//! `codegen run`: the main job — the closed loop of a manifest's supervisors under QEMU (or on an emulated
//! RP2040, through the board's pins, or as the PLC program scanned by the interpreter), with its report.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::closed_loop::{run_on_rp2040, run_on_rp2040_link, run_under_qemu, Options};
use codegen::config::{Layout, SamplingSpec, SupervisorChoice};
use codegen::pack::fit::Core;
use codegen::plc::Encoding;
use codegen::project::new_project::Board;
use codegen::project::user_project::UserProject;
use codegen::project::Project;
use codegen::target::rp2040::pin_map;

use super::plant::{finish, Progress, RunArgs};
use super::Error;

/// Synthesise the manifest's supervisors, pack and emit their tables, build the firmware for QEMU, boot
/// it, attach the virtual plant and run the closed loop; print the report (safety, liveness, coverage
/// per supervisor, link). With `--target rp2040`, build the Pico firmware instead and run it on an
/// emulated RP2040: its link build over UART0, in lock-step as under QEMU (`--io link`), or the pin
/// application with the plant on its pins (`--io pins`, `[board]`); with `--target plc`, write the PLC program
/// (`[plc]`) and scan it cycle by cycle under the interpreter instead. Exit status 1 when the run saw a
/// safety violation. With `--project DIR`, build and run a project of your own (`codegen new`) on its board's
/// emulator; with `--elf`, run that firmware instead of building one.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project manifest (plants, specifications or supervisors, `[runtime]`, `[board]`) or a
    /// Supremica module; by default the cell, in the repository's checkout.
    #[arg(default_value = DEFAULT_MANIFEST)]
    manifest: PathBuf,
    /// What runs the firmware: QEMU's lm3s6965evb over its UART, or a Pico application on an
    /// emulated RP2040 (`harness/rp2040/`; `--io` says which).
    #[arg(long, value_enum, default_value_t = Target::Qemu)]
    target: Target,
    /// `--target rp2040`: how the plant reaches the Pico — `link`: the link build over UART0, in
    /// lock-step rounds as under QEMU (liveness measured); `pins`: the pin application (the LED/button
    /// build, the one `codegen new` writes), the plant on the `[board]` pins, with its own timing
    /// [default: link; pins with `--project`].
    #[arg(long, value_enum)]
    io: Option<Io>,
    /// `--target plc`: the program's form and state encoding (`codegen plc --encoding`): the
    /// event-based program in `int` or `bits`, or the state-based program (`state`, from the
    /// manifest's `[state]` section).
    #[arg(long, value_enum, default_value_t = RunEncoding::Int)]
    encoding: RunEncoding,
    /// How the Pico firmware reads its inputs (default: the manifest's `[board] sampling`).
    #[arg(long, value_enum)]
    sampling: Option<Sampling>,
    /// Timer sampling period in µs (default: the manifest's, else 1000).
    #[arg(long, value_name = "US")]
    sample_period_us: Option<u32>,
    /// The tables' layout [default: the manifest's `[runtime] layout`, else the best measured for the
    /// target: `ranked` on QEMU's Cortex-M3, `indexed` on the RP2040].
    #[arg(long, value_enum)]
    layout: Option<Layout>,
    /// Which supervisors to deploy: the full set, each supervisor reduced, or one monolithic supervisor,
    /// full or reduced; proven to give the plants the full set's closed loop first [default: the
    /// manifest's `[runtime] supervisors`, else full].
    #[arg(long = "supervisors", id = "deploy", value_enum, value_name = "CHOICE")]
    deploy: Option<SupervisorChoice>,
    /// Run this firmware ELF instead of building one: a project of your own (`codegen new`, then
    /// `cargo build --release`), built from the same manifest (under QEMU, one that reports other tables
    /// is refused, exit 2).
    #[arg(long, value_name = "ELF")]
    elf: Option<PathBuf>,
    /// Build and run a project of your own (`codegen new DIR --board B`): `cargo build --release` in
    /// DIR, then its ELF on the board's emulator (the Pico's: an emulated RP2040), judged by DIR's
    /// manifest (`model/*.toml`). A board with no emulator here is refused.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["manifest", "elf", "target"])]
    project: Option<PathBuf>,
    /// Save the raw defmt frames the Pico firmware writes over RTT to FILE (`defmt-print -e ELF < FILE`).
    #[arg(long, value_name = "FILE")]
    rtt: Option<PathBuf>,
    /// Plant and report options.
    #[command(flatten)]
    run: RunArgs,
}

/// The manifest `run` takes when none is named: the cell, a path in the repository's checkout.
const DEFAULT_MANIFEST: &str = "examples/cell/cell.toml";

/// `--target`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Target {
    /// qemu-system-arm, lm3s6965evb (Cortex-M3).
    Qemu,
    /// The Pico application on rp2040js (Cortex-M0+).
    Rp2040,
    /// The PLC program (`codegen plc`, event-based) scanned cycle by cycle by the interpreter.
    Plc,
}

/// `--io`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Io {
    /// The link build (`cell-pico-link`): the firmware link protocol on UART0.
    Link,
    /// The pin application (`cell-pico`): the plant on the manifest's `[board]` pins.
    Pins,
}

/// `--encoding` of `run --target plc`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum RunEncoding {
    /// The event-based program, an `INT` per automaton.
    Int,
    /// The event-based program, a `BOOL` per state.
    Bits,
    /// The state-based program: one rung per controllable event over the plant's signals.
    State,
}

/// `--sampling`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Sampling {
    /// GPIO edge interrupts.
    Interrupt,
    /// A timer samples every input.
    Timer,
}

/// Refuses a project with `[[timers]]` before `run --target rp2040 --io pins`: the Pico's pin build
/// runs its timers on its own millisecond tick, in the emulator's wall-clock time, where a timeout's
/// millisecond cannot be judged the same from run to run. Every link build (QEMU's, the Pico's over
/// UART0, a board's link build behind `codegen plant`) runs them on the host's TIME instead, and the PLC
/// program on its `TON`s.
fn refuse_timers_on_pins(project: &Project, manifest: &std::path::Path) -> Result<(), Error> {
    if project.timers.is_empty() {
        return Ok(());
    }
    Err(format!(
        "{}: [[timers]] with --io pins: the Pico's pin build runs its timers on its own millisecond tick, \
         in the emulator's wall-clock time, where the monitor cannot judge a timeout's millisecond \
         reproducibly; run the link build (`--io link`, the default), whose timers run on the host's \
         virtual clock (TIME)",
        manifest.display()
    )
    .into())
}

/// Runs `run`.
pub fn run(mut args: Args) -> Result<ExitCode, Error> {
    if let Some(dir) = args.project.take() {
        let user = UserProject::open(&dir)?;
        args.target = match user.board {
            Board::Pico => Target::Rp2040,
            other => {
                return Err(format!(
                    "{}: the project is for the {} board, which has no emulator here: build it \
                     (`cargo build --release` in {0}) and flash it (`cargo run --release`, probe-rs)",
                    dir.display(),
                    other.name()
                )
                .into())
            }
        };
        if args.io == Some(Io::Link) {
            return Err(format!(
                "{}: --io link: the project's application drives pins; its board runs with --io pins",
                dir.display()
            )
            .into());
        }
        args.io = Some(Io::Pins);
        eprintln!("codegen run: building {} (cargo build --release in {})", user.name, dir.display());
        args.elf = Some(user.build()?);
        args.manifest = user.manifest;
    }
    if args.manifest.as_os_str() == DEFAULT_MANIFEST && !args.manifest.exists() {
        return Err(format!(
            "no project named, and the default {DEFAULT_MANIFEST} is not here (it is in the repository's \
             checkout): name your manifest or module, `codegen run PROJECT`"
        )
        .into());
    }
    let mut project = match args.target {
        Target::Rp2040 => Project::load_for(&args.manifest, Board::Pico)?,
        Target::Qemu | Target::Plc => Project::load(&args.manifest)?,
    };
    if args.target == Target::Rp2040 && args.io == Some(Io::Pins) {
        refuse_timers_on_pins(&project, &args.manifest)?;
    }
    project.runtime.layout = args.layout.or(project.runtime.layout);
    if args.target == Target::Plc && project.hybrid.is_some() {
        return run_plc_hybrid(&args, &project);
    }
    super::deploy(&mut project, args.deploy, args.run.json)?;
    if args.target == Target::Rp2040 {
        return match args.io.unwrap_or(Io::Link) {
            Io::Link => run_rp2040_link(args, project),
            Io::Pins => run_rp2040(args, project),
        };
    }
    if args.io.is_some() {
        return Err("--io goes with --target rp2040".into());
    }
    if args.target == Target::Plc {
        return run_plc(&args, &project);
    }
    if args.encoding != RunEncoding::Int {
        return Err("--encoding goes with --target plc".into());
    }
    if args.sampling.is_some() || args.sample_period_us.is_some() || args.rtt.is_some() {
        return Err("--sampling, --sample-period-us and --rtt go with --target rp2040".into());
    }
    // A firmware (`--elf`) that runs other tables is refused before the run (`Options::tables`). The
    // timers run on the session's virtual clock, sent to the firmware as TIME; it raises each timeout
    // on the millisecond (slack 0).
    let options = Options {
        tables: project.table_digests()?,
        timers: project.timers.clone(),
        timer_slack_ms: 0,
        ..args.run.options(&project.runtime)
    };
    let scratch = Scratch::new()?;
    let elf = match &args.elf {
        Some(elf) => elf.clone(),
        None => {
            eprintln!("codegen run: building the {} firmware for QEMU", project.name);
            project.image(&scratch.0)?
        }
    };
    eprintln!(
        "codegen run: closed loop under QEMU for {} events, plant seed {}",
        options.events, options.plant.seed
    );
    let mut progress = Progress::new(options.events);
    let report = run_under_qemu(&elf, &project.set, &project.name, &options, &mut |r| progress.show(r));
    progress.clear();
    finish(&report?, args.run.json)
}

/// `run --target rp2040 --io link`: the Pico's link build over UART0, in lock-step as under QEMU.
fn run_rp2040_link(args: Args, project: Project) -> Result<ExitCode, Error> {
    if args.sampling.is_some() || args.sample_period_us.is_some() {
        return Err(
            "--sampling and --sample-period-us go with --io pins (the link build reads no pins)".into()
        );
    }
    // Tables the Pico cannot run are refused before anything is built, naming what would fit.
    project.fit(Core::CortexM0Plus, &Core::CortexM0Plus.flash())?;
    // A link build (`--elf`) that runs other tables is refused before the run (`Options::tables`). Its
    // timers run on the session's virtual clock (TIME), as under QEMU: each timeout on its millisecond.
    let mut options = Options {
        tables: project.table_digests()?,
        timers: project.timers.clone(),
        timer_slack_ms: 0,
        ..args.run.options(&project.runtime)
    };
    options.rp2040.seed = options.plant.seed;
    options.rp2040.rtt = args.rtt.clone();
    let scratch = Scratch::new()?;
    let elf = match &args.elf {
        Some(elf) => elf.clone(),
        None => {
            eprintln!("codegen run: building the {} link firmware for the Pico", project.name);
            project.pico_link_image(&scratch.0)?
        }
    };
    eprintln!(
        "codegen run: closed loop on an emulated RP2040 over UART0 for {} events, plant seed {}",
        options.events, options.plant.seed
    );
    let mut progress = Progress::new(options.events);
    let report = run_on_rp2040_link(&elf, &project.set, &project.name, &options, &mut |r| progress.show(r));
    progress.clear();
    finish(&report?, args.run.json)
}

/// `run --target rp2040 --io pins`: the Pico firmware on the manifest's pins, sampling as asked.
fn run_rp2040(args: Args, mut project: Project) -> Result<ExitCode, Error> {
    // Tables the Pico cannot run are refused before its pins are read: what would fit comes first.
    project.fit(Core::CortexM0Plus, &Core::CortexM0Plus.flash())?;
    let board = project.board.as_mut().ok_or("--target rp2040: the manifest has no [board] section")?;
    match args.sampling {
        Some(Sampling::Interrupt) => {
            board.sampling = SamplingSpec::Interrupt;
            board.sample_period_us = None;
        }
        Some(Sampling::Timer) => board.sampling = SamplingSpec::Timer,
        None => {}
    }
    if board.sampling == SamplingSpec::Timer {
        board.sample_period_us = args.sample_period_us.or(board.sample_period_us).or(Some(1000));
    } else if args.sample_period_us.is_some() {
        return Err("--sample-period-us goes with timer sampling".into());
    }
    let pins = pin_map(board, project.set.events())?;
    let mut options = args.run.options(&project.runtime);
    options.rp2040.seed = options.plant.seed;
    options.rp2040.rtt = args.rtt.clone();
    let scratch = Scratch::new()?;
    let pins_file = scratch.0.join("pins.json");
    std::fs::write(&pins_file, pins).map_err(|e| format!("{}: {e}", pins_file.display()))?;
    let elf = match &args.elf {
        Some(elf) => elf.clone(),
        None => {
            eprintln!("codegen run: building the {} firmware for the Pico", project.name);
            project.pico_image(&scratch.0)?
        }
    };
    eprintln!(
        "codegen run: closed loop on an emulated RP2040 for {} events, plant seed {}",
        options.events, options.plant.seed
    );
    let mut progress = Progress::new(options.events);
    let report =
        run_on_rp2040(&elf, &pins_file, &project.set, &project.name, &options, &mut |r| progress.show(r));
    progress.clear();
    finish(&report?, args.run.json)
}

/// Refuses the firmware's options with `--target plc`.
fn check_plc_options(args: &Args) -> Result<(), Error> {
    if args.elf.is_some() || args.layout.is_some() {
        return Err("--elf and --layout go with a firmware's target (qemu, rp2040), not plc".into());
    }
    if args.sampling.is_some() || args.sample_period_us.is_some() || args.rtt.is_some() {
        return Err("--sampling, --sample-period-us and --rtt go with --target rp2040".into());
    }
    Ok(())
}

/// `run --target plc`: the event-based PLC program's text scanned by the interpreter, the plant and
/// the monitor on the other side of the link as for a firmware.
fn run_plc(args: &Args, project: &Project) -> Result<ExitCode, Error> {
    check_plc_options(args)?;
    // The timers run on the session's virtual clock, their timeouts raised by the program's TONs.
    let options = Options { timers: project.timers.clone(), ..args.run.options(&project.runtime) };
    eprintln!(
        "codegen run: the {} PLC program ({:?} encoding) scanned closed loop for {} events, plant seed {}",
        project.name, args.encoding, options.events, options.plant.seed
    );
    let mut progress = Progress::new(options.events);
    let report = match args.encoding {
        RunEncoding::Int => project.run_plc(Encoding::Int, &options, &mut |r| progress.show(r)),
        RunEncoding::Bits => project.run_plc(Encoding::Bits, &options, &mut |r| progress.show(r)),
        RunEncoding::State => project.run_plc_state(&options, &mut |r| progress.show(r)),
    };
    progress.clear();
    finish(&report?, args.run.json)
}

/// `run --target plc` on a `[hybrid]` manifest: the hybrid controller with the reduced supervisor
/// (`--supervisors full`: the full one) scanned by the interpreter against the plant net's own token
/// game, judged by its reachability graph ‖ `SUPER` (docs/hybrid.md).
fn run_plc_hybrid(args: &Args, project: &Project) -> Result<ExitCode, Error> {
    if args.encoding != RunEncoding::Int {
        return Err("--encoding: a [hybrid] manifest's program is the hybrid controller, in one form".into());
    }
    let full = match args.deploy {
        None | Some(SupervisorChoice::Reduced) => false,
        Some(SupervisorChoice::Full) => true,
        Some(other) => {
            return Err(
                format!("--supervisors {other}: a hybrid controller's supervisor is full or reduced").into()
            )
        }
    };
    check_plc_options(args)?;
    let options = args.run.options(&project.runtime);
    let which = if full { "full" } else { "reduced" };
    eprintln!(
        "codegen run: the {} hybrid controller ({which} supervisor) scanned closed loop against its net for {} events, plant seed {}",
        project.name, options.events, options.plant.seed
    );
    let mut progress = Progress::new(options.events);
    let report = project.run_plc_hybrid(full, &options, &mut |r| progress.show(r));
    progress.clear();
    finish(&report?, args.run.json)
}

/// A private scratch directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Result<Self, Error> {
        let dir = std::env::temp_dir().join(format!("codegen-run-{}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(Scratch(dir))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
