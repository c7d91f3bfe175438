//! `codegen new`: write a firmware project of the user's own for a board.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::project::new_project::{new_project, Board};

use super::Error;

/// Write a standalone firmware project for a board: Cargo.toml, memory.x, .cargo/config.toml (target,
/// probe-rs runner), build.rs (the tables emitted from the manifest at build time), src/main.rs, the
/// manifest with its model files under model/, README.md with the flash command.
///
/// Then `cargo build --release` in DIR builds it, and `cargo run --release` flashes it. Without
/// --manifest, the starter manifest is the manufacturing cell.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project's directory (created; must be empty if it exists).
    dir: PathBuf,
    /// The board.
    #[arg(long, value_enum)]
    board: Board,
    /// The project manifest to start from (copied, with the model files it names, into DIR/model/).
    #[arg(long, value_name = "FILE")]
    manifest: Option<PathBuf>,
}

/// Runs `new`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let made = new_project(&args.dir, args.board, args.manifest.as_deref())?;
    println!("{} written to {} (manifest {})", made.name, args.dir.display(), made.manifest);
    println!("build: cd {} && cargo build --release", args.dir.display());
    Ok(ExitCode::SUCCESS)
}
