//! `codegen plc`: Structured Text and PLCopen XML for a scan-cycle controller.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::config::{RuntimeConfig, ScanPolicy};
use codegen::manifest::is_manifest;
use codegen::plc::{Avalanche, Encoding};
use codegen::project::Project;

use super::Error;

/// Write an IEC 61131-3 program (ST and PLCopen XML) running the supervisors on a PLC.
///
/// Writes `DIR/<name>.st` (a FUNCTION_BLOCK with plants, supervisors and interface, and a PROGRAM
/// instantiating it), `DIR/<name>_config.st` (CONFIGURATION, RESOURCE and cyclic TASK) and
/// `DIR/<name>.xml` (the same as PLCopen TC6 XML 2.01), and prints the report: variables, statements,
/// a bound on the statements per scan, memory bits, the avalanche method per event, simultaneity.
/// I/O and policy come from the manifest's `[plc]` section; events it does not map are internal.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A project: a manifest (TOML; supervisors as listed, else synthesised local modular) or a Supremica
    /// module; or plant model files.
    #[arg(required_unless_present = "plants")]
    files: Vec<PathBuf>,
    /// A plant model file (repeat).
    #[arg(long = "plant", value_name = "FILE")]
    plants: Vec<PathBuf>,
    /// A supervisor model file (repeat).
    #[arg(long = "sup", value_name = "FILE")]
    supervisors: Vec<PathBuf>,
    /// Name of the set, without a manifest (file and POU names derive from it).
    #[arg(long, default_value = "set")]
    name: String,
    /// State encoding: `int` (an integer per automaton, a CASE per event) or `bits` (a BOOL per state).
    #[arg(long, value_enum, default_value_t = Encoding::Int)]
    encoding: Encoding,
    /// Avalanche elimination in the bits encoding.
    #[arg(long, value_enum, default_value_t = Avalanche::Auto)]
    avalanche: Avalanche,
    /// Choice policy (default: the manifest's `[plc]` or `[runtime]` policy, else local-queue).
    #[arg(long, value_enum)]
    policy: Option<ScanPolicy>,
    /// Print the report as JSON (schema 1).
    #[arg(long)]
    json: bool,
    /// The directory to write to (created if missing).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
}

/// Runs `plc`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let project = match args.files.as_slice() {
        [one] if is_manifest(one) && args.plants.is_empty() && args.supervisors.is_empty() => {
            Project::load(one)?
        }
        files => {
            let plants: Vec<PathBuf> = files.iter().chain(&args.plants).cloned().collect();
            Project::from_files(&args.name, &plants, &args.supervisors, None, RuntimeConfig::default())?
        }
    };
    super::say_skipped(&project.left_out);
    let out = project.plc(args.encoding, args.avalanche, args.policy)?;
    std::fs::create_dir_all(&args.output).map_err(|e| format!("{}: {e}", args.output.display()))?;
    for (name, text) in &out.files {
        let path = args.output.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&out.report)?);
    } else {
        print!("{}", out.report.text());
        println!("written to {}", args.output.display());
    }
    Ok(ExitCode::SUCCESS)
}
