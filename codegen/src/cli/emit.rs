//! `codegen emit`: write the Rust tables the firmware compiles.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::emit::{emit, BoardSpec, Input, OnFault, Options, Policy, Provenance};
use codegen::formats::read_path;
use codegen::manifest::Manifest;
use codegen::model::Automaton;
use codegen::pack::{ranked, PackSet};

use super::Error;

/// Emit the Rust tables (ranked layout, side tables, policy, configuration, board pins) the firmware
/// includes.
///
/// From a manifest (its supervisors, or the local modular ones synthesised from its plants and
/// specifications; its `[runtime]` and `[board]`), or from model files given one by one. The output starts
/// with a provenance header (SHA-256 of every input, tool version, the command). Same inputs, same bytes.
/// Build the QEMU firmware on it with `SCT_TABLES=FILE cargo qemu-build`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project manifest (then no --plant, --sup or run-time options).
    #[arg(conflicts_with_all = ["plants", "supervisors", "board", "policy", "seed", "guard", "on_fault", "input_buffer"])]
    manifest: Option<PathBuf>,
    /// A plant model file (repeat; plants come first in the tables, in this order).
    #[arg(long = "plant", value_name = "FILE", required_unless_present = "manifest")]
    plants: Vec<PathBuf>,
    /// A supervisor model file (repeat).
    #[arg(long = "sup", value_name = "FILE")]
    supervisors: Vec<PathBuf>,
    /// Name of the set.
    #[arg(long, default_value = "set")]
    name: String,
    /// Choice policy.
    #[arg(long, value_enum, default_value_t = Policy::RandomLocalQueue)]
    policy: Policy,
    /// Seed of the random policies (QEMU; a board reseeds from its own entropy).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Inexact-synchronisation guard.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set)]
    guard: bool,
    /// Reaction to a fault.
    #[arg(long, value_enum, default_value_t = OnFault::Continue)]
    on_fault: OnFault,
    /// Input buffer capacity in events.
    #[arg(long, default_value_t = 32)]
    input_buffer: usize,
    /// Random draws between two reseeds (0: never).
    #[arg(long, default_value_t = 1024)]
    reseed_every: u16,
    /// A TOML file with a `[board]` table: the pin map of a real board.
    #[arg(long, value_name = "FILE")]
    board: Option<PathBuf>,
    /// The Rust file to write.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
}

/// Runs `emit`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    if let Some(path) = &args.manifest {
        return from_manifest(path, &args);
    }
    let mut inputs = Vec::new();
    let mut read = |paths: &[PathBuf]| -> Result<Vec<Automaton>, Error> {
        let mut out = Vec::new();
        for p in paths {
            out.extend(read_path(p)?);
            inputs.push(Input::read(p).map_err(|e| format!("{}: {e}", p.display()))?);
        }
        Ok(out)
    };
    let plants = read(&args.plants)?;
    let supervisors = read(&args.supervisors)?;
    let board = match &args.board {
        Some(path) => {
            inputs.push(Input::read(path).map_err(|e| format!("{}: {e}", path.display()))?);
            Some(read_board(path)?)
        }
        None => None,
    };
    let packed = ranked::encode(&PackSet::new(plants, supervisors)?)?;
    let options = Options {
        name: args.name.clone(),
        policy: args.policy,
        seed: args.seed,
        guard: args.guard,
        on_fault: args.on_fault,
        input_buffer: args.input_buffer,
        reseed_every: args.reseed_every,
        board,
    };
    let provenance = Provenance { inputs, command: command(&args) };
    let text = emit(&packed, &options, &provenance)?;
    write(&args.output, &text)
}

/// `emit MANIFEST`: the manifest's ready supervisors and the local modular ones of its specifications.
fn from_manifest(path: &std::path::Path, args: &Args) -> Result<ExitCode, Error> {
    let m = Manifest::load(path)?;
    let set = m.read_automata()?;
    let supervisors = set.all_supervisors()?;
    let mut inputs = vec![Input::read(path).map_err(|e| format!("{}: {e}", path.display()))?];
    for f in m.plants.iter().chain(&m.specs).chain(&m.supervisors) {
        let file = m.resolve(f);
        inputs.push(Input::read(&file).map_err(|e| format!("{}: {e}", file.display()))?);
    }
    let packed = ranked::encode(&PackSet::new(set.plants, supervisors)?)?;
    let r = &m.runtime;
    let options = Options {
        name: m.name.clone(),
        policy: r.policy,
        seed: r.seed,
        guard: r.guard,
        on_fault: r.on_fault,
        input_buffer: r.input_buffer,
        reseed_every: args.reseed_every,
        board: m.board.clone(),
    };
    let command =
        format!("codegen emit {} --reseed-every {}", path.display(), args.reseed_every).replace('\\', "/");
    let text = emit(&packed, &options, &Provenance { inputs, command })?;
    write(&args.output, &text)
}

/// Writes the file and prints its summary lines (set, policy RAM) from its header.
fn write(output: &std::path::Path, text: &str) -> Result<ExitCode, Error> {
    std::fs::write(output, text).map_err(|e| format!("{}: {e}", output.display()))?;
    for line in text.lines().take_while(|l| l.starts_with("//")) {
        if let Some(fact) = line.strip_prefix("// Set ").or_else(|| line.strip_prefix("// Choice-policy ")) {
            println!("{fact}");
        }
    }
    println!("written to {}", output.display());
    Ok(ExitCode::SUCCESS)
}

/// The command line that reproduces the output, paths as given, every option spelt out.
fn command(args: &Args) -> String {
    let mut words = vec![String::from("codegen emit"), format!("--name {}", args.name)];
    words.extend(args.plants.iter().map(|p| format!("--plant {}", p.display())));
    words.extend(args.supervisors.iter().map(|p| format!("--sup {}", p.display())));
    words.push(format!("--policy {}", args.policy));
    words.push(format!("--seed {}", args.seed));
    words.push(format!("--guard {}", args.guard));
    words.push(format!("--on-fault {}", args.on_fault.name()));
    words.push(format!("--input-buffer {}", args.input_buffer));
    words.push(format!("--reseed-every {}", args.reseed_every));
    if let Some(board) = &args.board {
        words.push(format!("--board {}", board.display()));
    }
    words.join(" ").replace('\\', "/")
}

/// The `[board]` table of a TOML file.
fn read_board(path: &std::path::Path) -> Result<BoardSpec, Error> {
    #[derive(serde::Deserialize)]
    struct File {
        board: BoardSpec,
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let file: File = toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(file.board)
}
