//! `codegen dot`: draw a model with Graphviz.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use codegen::formats::{dot, read_path};

use super::Error;

/// Write a Graphviz drawing of every automaton in a model file.
///
/// Marked states are double circles, the initial state has an arrow from nowhere, controllable
/// transitions carry a bar at their tail and uncontrollable ones are dashed. Render with
/// `dot -Tsvg`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The model to draw.
    input: PathBuf,
    /// Where to write the DOT text (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// Runs `dot`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let text = dot::write(&read_path(&args.input)?);
    match args.output {
        Some(path) => {
            std::fs::write(&path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))?
        }
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(text.as_bytes())?;
            out.flush()?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
