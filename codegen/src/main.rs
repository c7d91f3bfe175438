//! The `codegen` command: read automata, convert and draw them (and, from the other subcommands,
//! synthesise, pack and test supervisors).
//!
//! Exit status: 0 success, 1 a check failed, 2 bad input or usage. Errors go to stderr with their
//! chain of causes; a closed stdout (`codegen inspect … | head`) counts as success.

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(code) => code,
        Err(e) if cli::is_broken_pipe(e.as_ref()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", cli::chain(e.as_ref()));
            ExitCode::from(2)
        }
    }
}
