//! `codegen plc`: Structured Text and PLCopen XML for a scan-cycle controller.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use codegen::config::{RuntimeConfig, ScanPolicy, SupervisorChoice};
use codegen::plc::state_based::{Engine, StateOptions};
use codegen::plc::{Avalanche, Encoding, Form, Written};
use codegen::project::{Project, ProjectError};
use codegen::scan::vendor::Vendor;
use codegen::symbolic::Options;
use codegen::synth::Config;

use super::files::Files;
use super::{engine, limits, Error};

/// Write an IEC 61131-3 program (ST and PLCopen XML) running the supervisors on a PLC.
///
/// Writes `DIR/<name>.st` (a FUNCTION_BLOCK with plants, supervisors and interface, and a PROGRAM
/// instantiating it), `DIR/<name>_config.st` (CONFIGURATION, RESOURCE and cyclic TASK) and
/// `DIR/<name>.xml` (the same as PLCopen TC6 XML 2.01), and prints the report: variables, statements,
/// a bound on the statements per scan, memory bits, the avalanche method per event, simultaneity.
/// I/O and policy come from the manifest's `[plc]` section; events it does not map are internal. With
/// a `[net]` section the sequence net runs beside the interlocks in the same program: a token-passing
/// block in the ST, an SFC in the XML, requesting the commands the supervisors allow. A manifest with a
/// `[hybrid]` section is a hybrid controller instead (docs/hybrid.md): its automation net is the plant,
/// and `DIR/<name>_hybrid.{st,xml}` and `_config.st` (reduced supervisor) and the same three
/// `DIR/<name>_hybrid_full` files (unreduced) are written, the XML with a Ladder Diagram body, and the
/// two compared in the report. A net whose place can hold two tokens is refused (exit 2).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project: a manifest (supervisors as listed, else synthesised local modular), or modules and
    /// model files (one project, loaded as by every command), or files in roles.
    #[command(flatten)]
    input: Files,
    /// Name of the set, without a manifest (file and POU names derive from it).
    #[arg(long, default_value = "set")]
    name: String,
    /// State encoding: `int` (an integer per automaton, a CASE per event), `bits` (a BOOL per state) or
    /// `state` (no state tracked: one rung per controllable event over the plant's signals, from the
    /// manifest's `[state]` section; also writes a Ladder Diagram body in the XML).
    #[arg(long, value_enum, default_value_t = EncodingArg::Int)]
    encoding: EncodingArg,
    /// `--encoding state`: where the supervisors' memory decides, keep the supervisors needed instead of
    /// failing (as `[state] memory = true`).
    #[arg(long)]
    memory: bool,
    /// `--encoding state`: F_σ exactly the union of its states' formulas, no don't-cares (as
    /// `[state] exact = true`).
    #[arg(long)]
    exact: bool,
    /// `--encoding state`: where f comes from — `explicit` (the closed loop of the local modular set,
    /// listed state by state) or `symbolic` (a guard per controllable event read off the BDDs of the
    /// monolithic supervisor of the manifest's specifications: for plants whose closed loop is too large
    /// to list).
    #[arg(long, value_enum, default_value_t = StateEngine::Explicit)]
    engine: StateEngine,
    /// `--encoding state --engine symbolic`: stop when the BDDs grow the process past this resident
    /// size (512M, 2G, none) [default: three quarters of the machine's RAM].
    #[arg(long, value_name = "SIZE", value_parser = limits::parse_size)]
    memory_limit: Option<limits::MemoryLimit>,
    /// `--encoding state`: fire at most one command per scan, chosen among the rungs that conduct by
    /// this policy, so that every command allowed with others may be the one that fires (as
    /// `[state] choice`; the XML then carries the ST body only).
    #[arg(long, value_enum, value_name = "POLICY")]
    choice: Option<ScanPolicy>,
    /// Avalanche elimination in the bits encoding (`aeem` also writes the supervisors' rungs as a Ladder
    /// Diagram body in the XML).
    #[arg(long, value_enum, default_value_t = Avalanche::Auto)]
    avalanche: Avalanche,
    /// Choice policy (default: the manifest's `[plc]` or `[runtime]` policy, else random).
    #[arg(long, value_enum)]
    policy: Option<ScanPolicy>,
    /// Which supervisors to deploy: the full set, each supervisor reduced, or one monolithic supervisor,
    /// full or reduced; proven to give the plants the full set's closed loop first [default: the
    /// manifest's `[runtime] supervisors`, else full].
    #[arg(long = "supervisors", id = "deploy", value_enum, value_name = "CHOICE")]
    deploy: Option<SupervisorChoice>,
    /// Write the program as a vendor's project files instead of the generic ST and PLCopen XML
    /// (docs/plc.md: what each vendor gets and how to import it): `twincat` (`.TcPOU`, `.TcDUT`,
    /// `.TcGVL`, `.TcTTO`), `codesys` (PLCopen XML with CODESYS' project structure), `tia` (SCL
    /// sources and a PLC tag table) or `rockwell` (a Studio 5000 `.L5X` project).
    #[arg(long, value_enum)]
    vendor: Option<Vendor>,
    /// Print the report as JSON (schema 1).
    #[arg(long)]
    json: bool,
    /// The directory to write to (created if missing).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
}

/// `--engine`: where the state-based program's feedback comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum StateEngine {
    /// The explicit closed loop.
    Explicit,
    /// Guards off the symbolic engine's BDDs.
    Symbolic,
}

/// `--encoding`: the event-based encodings, or the state-based program.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum EncodingArg {
    /// One integer per automaton, a `CASE` per event.
    Int,
    /// One `BOOL` per state, one statement per transition.
    Bits,
    /// State feedback control: one rung per controllable event.
    State,
}

/// Writes `files` into `dir` (created if missing).
fn write(dir: &Path, files: &[(String, String)]) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// Prints the report — its JSON with `--json`, else its text and where the files went — through a
/// locked stdout, so that a closed pipe (`codegen plc … | head`) ends the command as any write error
/// does instead of panicking as `println!` would.
fn report(args: &Args, name: &str, written: &Written) -> Result<ExitCode, Error> {
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&written.json(name))?)?;
    } else {
        write!(out, "{}", written.text())?;
        writeln!(out, "written to {}", args.output.display())?;
    }
    // A finding (the scan longer than the task's cycle) is a failed check: the files are written, exit 1.
    Ok(if written.has_finding() { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

/// The form the arguments ask for, for `project`: a `[hybrid]` manifest is a hybrid controller whatever
/// the encoding.
fn form(args: &Args, project: &Project) -> Result<Form, Error> {
    if project.hybrid.is_some() {
        return Ok(Form::Hybrid);
    }
    let options = StateOptions { memory: args.memory, exact: args.exact, choice: args.choice };
    Ok(match args.encoding {
        EncodingArg::Int | EncodingArg::Bits => Form::Event {
            encoding: if args.encoding == EncodingArg::Int { Encoding::Int } else { Encoding::Bits },
            avalanche: args.avalanche,
            policy: args.policy,
        },
        EncodingArg::State => match args.engine {
            StateEngine::Explicit => Form::State { options, engine: Engine::Explicit },
            StateEngine::Symbolic => {
                if args.memory {
                    return Err("--memory keeps supervisors as memory: it needs --engine explicit".into());
                }
                let cfg =
                    Config { memory_limit: limits::memory_limit(args.memory_limit), ..Config::default() };
                Form::State { options, engine: Engine::Symbolic { cfg, options: Options::default() } }
            }
        },
    })
}

/// Runs `plc`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let sources = args.input.sources();
    if sources.is_empty() {
        return Err(super::files::NO_INPUT.into());
    }
    let symbolic = args.encoding == EncodingArg::State && args.engine == StateEngine::Symbolic;
    let mut project = match sources.manifest() {
        // Guards off the BDDs are for sets too large to list: the local modular set's conflict check
        // runs on BDDs too.
        Some(one) if symbolic => {
            let check = engine::Engine::Symbolic.conflict_check(Options::default());
            Project::load_with(one, &Config { nonblocking: check.map(|c| c as _), ..Config::default() })?
        }
        _ => Project::from_sources(&args.name, &sources, None, RuntimeConfig::default())?,
    };
    super::say_skipped(&project.left_out);
    super::deploy(&mut project, args.deploy, true)?;
    let mut form = form(&args, &project)?;
    let bar = match &mut form {
        Form::State { engine: Engine::Symbolic { cfg, .. }, .. } => {
            let (observer, bar) = limits::progress();
            cfg.observer = Some(observer);
            bar
        }
        _ => None,
    };
    let written = project.plc(&form);
    bar.inspect(|b| b.finish_and_clear());
    let written = match written {
        Ok(w) => w,
        // The supervisors' memory deciding where memory is not allowed is a finding: exit 1, the plant
        // states with their traces on stderr.
        Err(ProjectError::Plc(e)) if e.is_finding() => {
            eprintln!("{e}");
            return Ok(ExitCode::from(1));
        }
        Err(e) => return Err(e.into()),
    };
    if matches!(written, Written::Symbolic(_)) {
        eprintln!("engine: the guards were read off the symbolic supervisor's BDDs");
    }
    match args.vendor {
        None => write(&args.output, written.files())?,
        Some(v) => write(&args.output, &v.files(written.sources()).map_err(|e| e.to_string())?)?,
    }
    report(&args, &project.name, &written)
}
