//! `codegen plc`: Structured Text and PLCopen XML for a scan-cycle controller.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::emit::{Input, Provenance};
use codegen::manifest::Manifest;
use codegen::pack::PackSet;
use codegen::plc::{generate, Avalanche, Encoding, PlcOptions, ScanPolicy};

use super::set::{is_manifest, ClosedLoop};
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
    /// A project manifest (TOML; supervisors as listed, else synthesised local modular), or model files
    /// (those marked as supervisors by their file are supervisors, the others plants).
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
    let mut opts = PlcOptions {
        name: args.name.clone(),
        encoding: args.encoding,
        avalanche: args.avalanche,
        ..PlcOptions::default()
    };
    let (closed, inputs, source) = match args.files.as_slice() {
        [one] if is_manifest(one) => {
            let m = Manifest::load(one)?;
            opts = PlcOptions {
                encoding: args.encoding,
                avalanche: args.avalanche,
                ..PlcOptions::from_manifest(&m).map_err(|e| format!("{}: {e}", one.display()))?
            };
            let files = std::iter::once(one.clone())
                .chain(m.plants.iter().chain(&m.specs).chain(&m.supervisors).map(|p| m.resolve(p)));
            (ClosedLoop::from_manifest(one)?, hashed(files)?, one.display().to_string())
        }
        files => {
            let all = files.iter().chain(&args.plants).chain(&args.supervisors).cloned();
            let mut plants = files.to_vec();
            plants.extend(args.plants.iter().cloned());
            (ClosedLoop::from_files(&plants, &[], &args.supervisors)?, hashed(all)?, String::new())
        }
    };
    if let Some(p) = args.policy {
        opts.policy = p;
    }
    let set = PackSet::new(closed.plants, closed.supervisors)?;
    let provenance = Provenance { inputs, command: command(&args, &source, opts.policy) };
    let out = generate(&set, &opts, &provenance)?;
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

/// Every file read and hashed, in order.
fn hashed(files: impl Iterator<Item = PathBuf>) -> Result<Vec<Input>, Error> {
    files.map(|f| Input::read(&f).map_err(|e| format!("{}: {e}", f.display()).into())).collect()
}

/// The command line that reproduces the files, paths as given, every option spelt out.
fn command(args: &Args, manifest: &str, policy: ScanPolicy) -> String {
    let mut words = vec![String::from("codegen plc")];
    if manifest.is_empty() {
        words.push(format!("--name {}", args.name));
        words.extend(args.files.iter().map(|p| p.display().to_string()));
        words.extend(args.plants.iter().map(|p| format!("--plant {}", p.display())));
        words.extend(args.supervisors.iter().map(|p| format!("--sup {}", p.display())));
    } else {
        words.push(manifest.to_owned());
    }
    words.push(format!("--encoding {}", args.encoding.name()));
    words.push(format!("--avalanche {}", args.avalanche.name()));
    words.push(format!("--policy {}", policy.name()));
    words.join(" ").replace('\\', "/")
}
