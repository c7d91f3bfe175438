//! `codegen emit`: write the Rust tables the firmware compiles.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::config::{ChoicePolicy, Layout, OnFault, RuntimeConfig};
use codegen::project::Project;

use super::Error;

/// Emit the Rust tables (in their layout, with side tables, policy, configuration, board pins) the
/// firmware includes.
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
    #[arg(long, value_enum, default_value_t = RuntimeConfig::default().policy)]
    policy: ChoicePolicy,
    /// Seed of the random policies (QEMU; a board reseeds from its own entropy).
    #[arg(long, default_value_t = RuntimeConfig::default().seed)]
    seed: u64,
    /// Inexact-synchronisation guard.
    #[arg(long, default_value_t = RuntimeConfig::default().guard, action = clap::ArgAction::Set)]
    guard: bool,
    /// Reaction to a fault.
    #[arg(long, value_enum, default_value_t = RuntimeConfig::default().on_fault)]
    on_fault: OnFault,
    /// Input buffer capacity in events.
    #[arg(long, default_value_t = RuntimeConfig::default().input_buffer)]
    input_buffer: usize,
    /// Random draws between two reseeds (0: never) [default: the manifest's `reseed_every`, else 1024].
    #[arg(long)]
    reseed_every: Option<u16>,
    /// The tables' layout on every core [default: the manifest's `[runtime] layout`, else `ranked` on
    /// the Cortex-M3 and `indexed` on the Cortex-M0+].
    #[arg(long, value_enum)]
    layout: Option<Layout>,
    /// A TOML file with a `[board]` table: the pin map of a real board.
    #[arg(long, value_name = "FILE")]
    board: Option<PathBuf>,
    /// The Rust file to write.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
}

/// Runs `emit`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let mut project = match &args.manifest {
        Some(path) => Project::load(path)?,
        None => {
            let runtime = RuntimeConfig {
                policy: args.policy,
                seed: args.seed,
                guard: args.guard,
                on_fault: args.on_fault,
                input_buffer: args.input_buffer,
                ..RuntimeConfig::default()
            };
            Project::from_files(&args.name, &args.plants, &args.supervisors, args.board.as_deref(), runtime)?
        }
    };
    super::say_skipped(&project.left_out);
    if let Some(n) = args.reseed_every {
        project.runtime.reseed_every = n;
    }
    if args.layout.is_some() {
        project.runtime.layout = args.layout;
    }
    let text = project.emit()?;
    std::fs::write(&args.output, &text).map_err(|e| format!("{}: {e}", args.output.display()))?;
    for line in text.lines().take_while(|l| l.starts_with("//")) {
        if let Some(fact) = line.strip_prefix("// Set ").or_else(|| line.strip_prefix("// Choice-policy ")) {
            println!("{fact}");
        }
    }
    println!("written to {}", args.output.display());
    Ok(ExitCode::SUCCESS)
}
