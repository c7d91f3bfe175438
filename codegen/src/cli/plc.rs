//! `codegen plc`: Structured Text and PLCopen XML for a scan-cycle controller.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use codegen::config::{RuntimeConfig, ScanPolicy, SupervisorChoice};
use codegen::manifest::{is_manifest, Manifest};
use codegen::net::{interpretation, Interpretation};
use codegen::plc::state_based::{StateError, StateOptions};
use codegen::plc::{Avalanche, Encoding};
use codegen::project::{Project, ProjectError};
use codegen::symbolic::Options;
use codegen::synth::Config;

use super::files::Files;
use super::{engine, limits, Error};

/// The sequence net of the manifest `path` when it has a `[net]` section, bound to the project's
/// events: it runs beside the interlocks in the one program ([`codegen::plc::net_program`]).
fn sequence(path: &Path, project: &Project) -> Result<Option<Interpretation>, Error> {
    if !is_manifest(path) {
        return Ok(None);
    }
    let manifest = Manifest::load(path)?;
    let Some(spec) = &manifest.net else { return Ok(None) };
    let automata: Vec<_> = project.set.members().iter().map(|m| &m.automaton).collect();
    Ok(Some(interpretation(spec, &manifest.file, &automata)?))
}

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
/// and `DIR/<name>_hybrid.{st,xml}` (reduced supervisor) and `DIR/<name>_hybrid_full.{st,xml}`
/// (unreduced) are written, the XML with a Ladder Diagram body, and the two compared in the report.
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
    /// Avalanche elimination in the bits encoding.
    #[arg(long, value_enum, default_value_t = Avalanche::Auto)]
    avalanche: Avalanche,
    /// Choice policy (default: the manifest's `[plc]` or `[runtime]` policy, else local-queue).
    #[arg(long, value_enum)]
    policy: Option<ScanPolicy>,
    /// Which supervisors to deploy: the full set, each supervisor reduced, or one monolithic supervisor,
    /// full or reduced; proven to give the plants the full set's closed loop first [default: the
    /// manifest's `[runtime] supervisors`, else full].
    #[arg(long = "supervisors", id = "deploy", value_enum, value_name = "CHOICE")]
    deploy: Option<SupervisorChoice>,
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

/// The names of the files written, for the JSON report.
fn names(files: &[(String, String)]) -> Vec<&str> {
    files.iter().map(|(n, _)| n.as_str()).collect()
}

/// Prints the report — `json()` with `--json`, else `text` and where the files went — through a locked
/// stdout, so that a closed pipe (`codegen plc … | head`) ends the command as any write error does
/// instead of panicking as `println!` would.
fn report(args: &Args, json: impl FnOnce() -> serde_json::Value, text: &str) -> Result<ExitCode, Error> {
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&json())?)?;
    } else {
        write!(out, "{text}")?;
        writeln!(out, "written to {}", args.output.display())?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The state-based program: files, then the report (JSON under `sfbc`). Memory deciding where memory is
/// not allowed is a finding (exit 1, the plant states with their traces on stderr).
fn state(project: &Project, args: &Args) -> Result<ExitCode, Error> {
    if args.engine == StateEngine::Symbolic {
        return state_symbolic(project, args);
    }
    let out =
        match project.state_plc(StateOptions { memory: args.memory, exact: args.exact, choice: args.choice })
        {
            Ok(out) => out,
            Err(e) if memory_decides(&e) => {
                eprintln!("{e}");
                return Ok(ExitCode::from(1));
            }
            Err(e) => return Err(e.into()),
        };
    write(&args.output, &out.files)?;
    let json = || {
        serde_json::json!({
            "schema": 1,
            "name": project.name,
            "encoding": "state",
            "files": names(&out.files),
            "sfbc": out.report,
        })
    };
    report(args, json, &out.report.text())
}

/// Whether `e` is the supervisors' memory deciding an event (a finding, not bad input).
fn memory_decides(e: &ProjectError) -> bool {
    matches!(e, ProjectError::State { source, .. } if matches!(**source, StateError::Memory(_)))
}

/// The state-based program from guards off the BDDs: files, then the figures (reachable plant states,
/// exact; per rung its products, literals and the guard's BDD nodes), JSON with `--json`.
fn state_symbolic(project: &Project, args: &Args) -> Result<ExitCode, Error> {
    if args.memory {
        return Err("--memory keeps supervisors as memory: it needs --engine explicit".into());
    }
    let (observer, bar) = limits::progress();
    let cfg = Config {
        memory_limit: limits::memory_limit(args.memory_limit),
        observer: Some(observer),
        ..Config::default()
    };
    let choices = StateOptions { memory: false, exact: args.exact, choice: args.choice };
    let result = project.state_plc_guards(choices, &cfg, &Options::default());
    bar.inspect(|b| b.finish_and_clear());
    let (program, guards) = match result {
        Ok(r) => r,
        Err(e) if memory_decides(&e) => {
            eprintln!("{e}");
            return Ok(ExitCode::from(1));
        }
        Err(e) => return Err(e.into()),
    };
    eprintln!("engine: the guards were read off the symbolic supervisor's BDDs");
    write(&args.output, &program.files)?;
    let reachable = guards.count(&guards.reachable);
    let rows: Vec<(String, usize, usize, usize)> = program
        .rungs
        .iter()
        .map(|r| {
            let nodes = guards.guards.iter().find(|g| g.event == r.event).map_or(0, |g| g.allowed.size());
            (r.event.clone(), r.cubes.len(), r.cubes.iter().map(|c| c.len()).sum(), nodes)
        })
        .collect();
    let json = || {
        let rungs: Vec<_> = rows
            .iter()
            .map(|(e, p, l, n)| serde_json::json!({ "event": e, "products": p, "literals": l, "bdd_nodes": n }))
            .collect();
        serde_json::json!({
            "schema": 1,
            "name": project.name,
            "encoding": "state",
            "engine": "symbolic",
            "files": names(&program.files),
            "reachable_plant_states": engine::count(&reachable),
            "rungs": rungs,
        })
    };
    let mut text =
        format!("reachable plant states: {reachable}\nrung  products  literals  guard BDD nodes\n");
    for (e, p, l, n) in &rows {
        text.push_str(&format!("{e}  {p}  {l}  {n}\n"));
    }
    report(args, json, &text)
}

/// The hybrid controller of a manifest with a `[hybrid]` section ([`codegen::plc::hybrid`]): both
/// controllers' files, then the report (JSON under `hybrid`).
fn hybrid(manifest: &Manifest, args: &Args) -> Result<ExitCode, Error> {
    let cycle = manifest.plc.as_ref().and_then(|p| p.cycle_ms).unwrap_or(10);
    let out = codegen::plc::hybrid::generate(manifest, &Config::default(), cycle)?;
    write(&args.output, &out.files)?;
    let json = || {
        serde_json::json!({
            "schema": 1,
            "name": manifest.name,
            "encoding": "hybrid",
            "files": names(&out.files),
            "hybrid": out.report,
        })
    };
    report(args, json, &out.report.text())
}

/// Runs `plc`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let sources = args.input.sources();
    if sources.is_empty() {
        return Err(super::files::NO_INPUT.into());
    }
    if let Some(one) = sources.manifest().filter(|one| is_manifest(one)) {
        let manifest = Manifest::load(one)?;
        if manifest.hybrid.is_some() {
            return hybrid(&manifest, &args);
        }
    }
    let mut project = match (sources.manifest(), args.encoding, args.engine) {
        // Guards off the BDDs are for sets too large to list: the local modular set's conflict check
        // runs on BDDs too.
        (Some(one), EncodingArg::State, StateEngine::Symbolic) => {
            let check = engine::Engine::Symbolic.conflict_check(Options::default());
            Project::load_with(one, &Config { nonblocking: check.map(|c| c as _), ..Config::default() })?
        }
        _ => Project::from_sources(&args.name, &sources, None, RuntimeConfig::default())?,
    };
    super::say_skipped(&project.left_out);
    super::deploy(&mut project, args.deploy, true)?;
    let encoding = match args.encoding {
        EncodingArg::Int => Encoding::Int,
        EncodingArg::Bits => Encoding::Bits,
        EncodingArg::State => return state(&project, &args),
    };
    let net = match sources.manifest() {
        Some(one) => sequence(one, &project)?,
        None => None,
    };
    let out = project.plc_beside(encoding, args.avalanche, args.policy, net.as_ref())?;
    write(&args.output, &out.files)?;
    report(&args, || serde_json::json!(out.report), &out.report.text())
}
