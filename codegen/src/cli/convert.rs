//! `codegen convert`: read a model in one format, write it in another.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::formats::{read_path, write_path};

use super::Error;

/// Convert a model file to another format, chosen by OUT's extension.
///
/// Reads every automaton of IN (any readable format) and writes them to OUT: .xmd, .ads (plus an event
/// map OUT-stem.events when the event names are not TCT's numbers), .gen, .wmod or .dot. Formats that hold
/// one automaton refuse an input with several.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The model to read.
    input: PathBuf,
    /// The file to write; its extension picks the format.
    output: PathBuf,
}

/// Runs `convert`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let automata = read_path(&args.input)?;
    write_path(&args.output, &automata)?;
    Ok(ExitCode::SUCCESS)
}
