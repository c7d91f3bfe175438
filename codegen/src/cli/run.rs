//! `codegen run`: the main job — the closed loop of a manifest's supervisors under QEMU, with its report.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::closed_loop::run_under_qemu;
use codegen::project::Project;

use super::plant::{finish, Progress, RunArgs};
use super::Error;

/// Synthesise the manifest's supervisors, pack and emit their tables, build the firmware for QEMU, boot
/// it, attach the virtual plant and run the closed loop; print the report (safety, liveness, coverage
/// per supervisor, link). Exit status 1 when the run saw a safety violation.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project manifest (plants, specifications or supervisors, `[runtime]`).
    #[arg(default_value = "examples/cell/cell.toml")]
    manifest: PathBuf,
    /// Plant and report options.
    #[command(flatten)]
    run: RunArgs,
}

/// Runs `run`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let project = Project::load(&args.manifest)?;
    let options = args.run.options(&project.runtime);
    let scratch = Scratch::new()?;
    eprintln!("codegen run: building the {} firmware for QEMU", project.name);
    let elf = project.image(&scratch.0)?;
    eprintln!(
        "codegen run: closed loop under QEMU for {} events, plant seed {}",
        options.events, options.plant.seed
    );
    let mut progress = Progress::new(options.events);
    let report = run_under_qemu(&elf, &project.set, &project.name, &options, &mut |r| progress.show(r));
    progress.clear();
    finish(&report?, args.run.json)
}

/// A private scratch directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Result<Self, Error> {
        let dir = std::env::temp_dir().join(format!("codegen-run-{}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(Scratch(dir))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
