//! `codegen emit`: write the Rust tables the firmware compiles.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::config::{ChoicePolicy, Layout, OnFault, RuntimeConfig, SupervisorChoice};
use codegen::project::Project;

use super::files::{Files, NO_INPUT};
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
    /// The project: a manifest (then no run-time options or --board: its `[runtime]` and `[board]`
    /// hold them), or modules and model files (one project, loaded as by every command; supervisors
    /// synthesised local modular where it has specifications), or files in roles.
    #[command(flatten)]
    input: Files,
    /// Name of the set, without a manifest.
    #[arg(long, default_value = "set")]
    name: String,
    /// Choice policy [default: random-local-queue].
    #[arg(long, value_enum)]
    policy: Option<ChoicePolicy>,
    /// Seed of the random policies (QEMU; a board reseeds from its own entropy) [default: 0].
    #[arg(long)]
    seed: Option<u64>,
    /// Inexact-synchronisation guard [default: true].
    #[arg(long, action = clap::ArgAction::Set)]
    guard: Option<bool>,
    /// Reaction to a fault [default: continue].
    #[arg(long, value_enum)]
    on_fault: Option<OnFault>,
    /// Input buffer capacity in events [default: 32].
    #[arg(long)]
    input_buffer: Option<usize>,
    /// Random draws between two reseeds (0: never) [default: the manifest's `reseed_every`, else 1024].
    #[arg(long)]
    reseed_every: Option<u16>,
    /// The tables' layout on every core [default: the manifest's `[runtime] layout`, else `ranked` on
    /// the Cortex-M3 and `indexed` on the Cortex-M0+].
    #[arg(long, value_enum)]
    layout: Option<Layout>,
    /// Which supervisors to deploy: the full set, each supervisor reduced, or one monolithic supervisor,
    /// full or reduced; proven to give the plants the full set's closed loop first [default: the
    /// manifest's `[runtime] supervisors`, else full].
    #[arg(long = "supervisors", id = "deploy", value_enum, value_name = "CHOICE")]
    deploy: Option<SupervisorChoice>,
    /// A TOML file with a `[board]` table: the pin map of a real board.
    #[arg(long, value_name = "FILE")]
    board: Option<PathBuf>,
    /// The Rust file to write.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
}

/// Runs `emit`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let sources = args.input.sources();
    if sources.is_empty() {
        return Err(NO_INPUT.into());
    }
    let given = args.policy.is_some()
        || args.seed.is_some()
        || args.guard.is_some()
        || args.on_fault.is_some()
        || args.input_buffer.is_some()
        || args.board.is_some();
    if let (Some(manifest), true) = (sources.manifest(), given) {
        return Err(format!(
            "{}: a manifest's [runtime] and [board] set the run-time options; --policy, --seed, --guard, --on-fault, --input-buffer and --board are for model files",
            manifest.display()
        )
        .into());
    }
    let d = RuntimeConfig::default();
    let runtime = RuntimeConfig {
        policy: args.policy.unwrap_or(d.policy),
        seed: args.seed.unwrap_or(d.seed),
        guard: args.guard.unwrap_or(d.guard),
        on_fault: args.on_fault.unwrap_or(d.on_fault),
        input_buffer: args.input_buffer.unwrap_or(d.input_buffer),
        supervisors: args.deploy.unwrap_or(d.supervisors),
        ..d
    };
    let mut project = Project::from_sources(&args.name, &sources, args.board.as_deref(), runtime)?;
    super::say_skipped(&project.left_out);
    if let Some(n) = args.reseed_every {
        project.runtime.reseed_every = n;
    }
    if args.layout.is_some() {
        project.runtime.layout = args.layout;
    }
    super::deploy(&mut project, args.deploy, false)?;
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
