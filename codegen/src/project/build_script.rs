//! Tables at build time: what a firmware project's `build.rs` calls, with `codegen` as a
//! build-dependency, so that editing the manifest or a model and running `cargo build` is the whole
//! step from model to image (as prost-build or defmt generate their code).
//!
//! [`main`] loads the project's manifest (paths relative to the package, where cargo runs build
//! scripts), emits its tables into `$OUT_DIR/tables.rs`, tells cargo to run it again when the manifest or
//! any model file it names changes, and hands the file to the application as `SCT_TABLES_FILE` (the name
//! the cell's applications in `apps/cell/` read, so one `main.rs` serves both), with the digests of the
//! table images it checked as `SCT_TABLES_CHECKED` (`firmware::table::image`: the emitted tables do not
//! compile without them). A bad manifest or model fails the build with the message the CLI prints, file
//! and line included.

use std::error::Error as StdError;
use std::path::{Path, PathBuf};

use super::user_project::UserProject;
use super::{Project, ProjectError};
use crate::maps::Board;
use crate::pack::fit::Core;
use crate::target::flash::Flash;

/// Name of the emitted file in `$OUT_DIR`.
pub const TABLES_FILE: &str = "tables.rs";

/// The build-script step failed.
#[derive(Debug, thiserror::Error)]
pub enum BuildScriptError {
    /// Cargo did not set `OUT_DIR`: the function runs outside a build script.
    #[error("OUT_DIR is not set: call this from a build script")]
    NoOutDir,
    /// The project could not be loaded or emitted.
    #[error(transparent)]
    Project(Box<ProjectError>),
    /// The tables could not be written.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The tables written fail the runtime's check (a fault of codegen: it checks them as it emits).
    #[error("{}: {source}", path.display())]
    Check {
        /// The file.
        path: PathBuf,
        /// Why.
        source: firmware::build::image::SourceError,
    },
}

/// What [`emit_into`] wrote.
#[derive(Debug)]
pub struct Emitted {
    /// The tables file.
    pub tables: PathBuf,
    /// The files cargo must watch: the manifest and every model file it names.
    pub inputs: Vec<String>,
    /// The digests of the table images checked (`SCT_TABLES_CHECKED`).
    pub checked: String,
}

impl From<ProjectError> for BuildScriptError {
    fn from(e: ProjectError) -> Self {
        BuildScriptError::Project(Box::new(e))
    }
}

/// Emits the tables of the manifest at `manifest` into `out_dir/tables.rs` and checks them as the
/// firmware compiles them; with `board`, its pins are checked against that board's; with `fits`, refuses
/// first tables its core cannot run within its flash.
pub fn emit_into(
    manifest: &Path,
    out_dir: &Path,
    board: Option<Board>,
    fits: Option<(Core, Flash)>,
) -> Result<Emitted, BuildScriptError> {
    let project = match board {
        Some(board) => Project::load_for(manifest, board)?,
        None => Project::load(manifest)?,
    };
    project.for_board()?;
    if let Some((core, flash)) = fits {
        project.fit(core, &flash)?;
    }
    let text = project.emit()?;
    let path = out_dir.join(TABLES_FILE);
    // Written only when changed, so a build that changed nothing recompiles nothing.
    if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
        std::fs::write(&path, &text)
            .map_err(|source| BuildScriptError::Write { path: path.clone(), source })?;
    }
    let checked = firmware::build::image::check_source(&text)
        .map_err(|source| BuildScriptError::Check { path: path.clone(), source })?;
    Ok(Emitted { tables: path, inputs: project.input_paths(), checked })
}

/// A firmware project's whole `build.rs`: emits the tables of `manifest` into `$OUT_DIR`, prints the
/// cargo directives (watch the inputs, `SCT_TABLES_FILE`, `SCT_TABLES_CHECKED`), and on error prints
/// `error: …` with its causes, as the CLI does, and fails the build (exit status 2).
pub fn main(manifest: &str) {
    let out_dir = std::env::var_os("OUT_DIR").map(PathBuf::from).ok_or(BuildScriptError::NoOutDir);
    // The board of the package being built, as `codegen new` wrote it (its `.cargo/config.toml`).
    let board = std::env::var_os("CARGO_MANIFEST_DIR")
        .and_then(|dir| UserProject::open(Path::new(&dir)).ok())
        .map(|p| p.board);
    match out_dir.and_then(|dir| emit_into(Path::new(manifest), &dir, board, fits())) {
        Ok(emitted) => {
            println!("cargo:rerun-if-changed={manifest}");
            for input in emitted.inputs {
                println!("cargo:rerun-if-changed={input}");
            }
            println!("cargo:rustc-env=SCT_TABLES_FILE={}", emitted.tables.display());
            println!("cargo:rustc-env=SCT_TABLES_CHECKED={}", emitted.checked);
        }
        Err(e) => {
            // Watch the manifest even now: fixing it must rerun the script.
            println!("cargo:rerun-if-changed={manifest}");
            eprintln!("error: {}", chain(&e));
            std::process::exit(2);
        }
    }
}

/// The board a build script builds for: its core from cargo's `TARGET` (the Cortex-M0+ for thumbv6m,
/// else the Cortex-M3's tables) and its flash from the project's `memory.x`, if there is one.
fn fits() -> Option<(Core, Flash)> {
    let dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR")?);
    let memory = std::fs::read_to_string(dir.join("memory.x")).ok()?;
    println!("cargo:rerun-if-changed={}", dir.join("memory.x").display());
    let target = std::env::var("TARGET").unwrap_or_default();
    let core = if target.starts_with("thumbv6m") { Core::CortexM0Plus } else { Core::CortexM3 };
    Some((core, Flash::of("this project's board", &memory)?))
}

/// `e` followed by each of its causes, separated by `: ` (a cause its parent's text already ends with
/// is not repeated): the one form in which the CLI and build scripts print errors.
pub fn chain(e: &(dyn StdError + 'static)) -> String {
    let mut out = e.to_string();
    let mut cur = e.source();
    while let Some(cause) = cur {
        let text = cause.to_string();
        if !out.ends_with(&text) {
            out.push_str(": ");
            out.push_str(&text);
        }
        cur = cause.source();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("build-script-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn cell() -> PathBuf {
        [env!("CARGO_MANIFEST_DIR"), "..", "examples", "cell", "cell.toml"].iter().collect()
    }

    /// The file written is what `codegen emit` writes for the same manifest, and the inputs to watch are
    /// the manifest and its model files.
    #[test]
    fn writes_the_emitted_tables_and_names_every_input() {
        let out = scratch("ok");
        let Emitted { tables: path, inputs, checked } = emit_into(&cell(), &out, None, None).unwrap();
        assert_eq!(path, out.join(TABLES_FILE));
        let expected = Project::load(&cell()).unwrap().emit().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), expected);
        // Two images (the Cortex-M3's and the Cortex-M0+'s), each a digest the emitted file names.
        let digests: Vec<&str> = checked.split(' ').collect();
        assert_eq!(digests.len(), 2, "{checked}");
        assert!(digests.iter().all(|d| expected.contains(&format!("const DIGEST: &str = \"{d}\";"))));
        assert!(inputs[0].ends_with("cell/cell.toml"), "{inputs:?}");
        assert!(inputs.len() > 1 && inputs[1..].iter().all(|i| !i.ends_with(".toml")), "{inputs:?}");
        std::fs::remove_dir_all(out).unwrap();
    }

    /// A model error names the file and line, as the CLI's message does.
    #[test]
    fn a_bad_model_fails_with_its_file_and_line() {
        let dir = scratch("bad");
        std::fs::write(dir.join("p.gen"), "not an automaton\n").unwrap();
        std::fs::write(dir.join("sct.toml"), "name = \"x\"\nplants = [\"p.gen\"]\n").unwrap();
        let e = emit_into(&dir.join("sct.toml"), &dir, None, None).unwrap_err();
        let text = chain(&e);
        assert!(text.contains("p.gen"), "{text}");
        assert!(!dir.join(TABLES_FILE).exists());
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A state-based manifest is refused by name: no board application runs state tables.
    #[test]
    fn a_state_based_manifest_is_refused_naming_the_mode() {
        let out = scratch("state");
        let manifest: PathBuf =
            [env!("CARGO_MANIFEST_DIR"), "..", "examples", "distribution", "distribution-state.toml"]
                .iter()
                .collect();
        let text = chain(&emit_into(&manifest, &out, None, None).unwrap_err());
        assert!(text.contains("distribution-state.toml") && text.contains("runtime.mode"), "{text}");
        assert!(!out.join(TABLES_FILE).exists());
        std::fs::remove_dir_all(out).unwrap();
    }
}
