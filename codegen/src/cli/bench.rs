//! `codegen bench`: the LED/button bench's `[board]` section, written from a manifest's events.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::maps::bench::{board_section, Bench};
use codegen::project::Project;

use super::Error;

/// Write the `[board]` section of the LED/button bench for the Raspberry Pi Pico: every uncontrollable
/// event a push-button from a pin to ground (pull-up, falling edge), every command an LED (a pulse),
/// on the Pico's free pins in ascending order, the buttons debounced by timer sampling.
///
/// Put the section in the manifest in place of its `[board]` (or give it to `codegen emit --board`),
/// then build the pin application (`codegen new --board pico`, `cargo pico-build`). Exit 2 when the set
/// has more events than the Pico has free pins.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project manifest whose events the bench shows.
    #[arg(default_value = "examples/cell/cell.toml")]
    manifest: PathBuf,
    /// How often the buttons are read, in microseconds: longer than a button bounces (a few ms).
    #[arg(long, default_value_t = Bench::default().sample_period_us)]
    sample_period_us: u32,
    /// How long an LED lights for a command, in milliseconds.
    #[arg(long, default_value_t = Bench::default().pulse_ms)]
    pulse_ms: u16,
    /// The file to write [default: stdout].
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

/// Runs `bench`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let project = Project::load(&args.manifest)?;
    let bench = Bench { sample_period_us: args.sample_period_us, pulse_ms: args.pulse_ms };
    let section = board_section(&project.name, project.set.events(), &bench)
        .map_err(|e| format!("{}: {e}", args.manifest.display()))?;
    match &args.output {
        Some(path) => std::fs::write(path, section).map_err(|e| format!("{}: {e}", path.display()))?,
        None => print!("{section}"),
    }
    Ok(ExitCode::SUCCESS)
}
