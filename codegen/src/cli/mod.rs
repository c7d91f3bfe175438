//! Command-line interface: the argument structure (clap derive) and the dispatch to one module per
//! subcommand.

mod bench;
mod check;
mod convert;
mod dot;
mod emit;
mod engine;
mod files;
mod inspect;
mod limits;
mod new;
mod pack;
mod plant;
mod plc;
mod run;
mod sim;
mod synth;
mod verify;

use std::error::Error as StdError;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use codegen::config::SupervisorChoice;
use codegen::project::Project;
use codegen::synth::verify::NoSupervisor;
use codegen::synth::{Config, SynthError};

/// Any error a subcommand reports; `main` prints it with its causes and exits 2.
pub type Error = Box<dyn StdError + Send + Sync>;

/// Supervisory control from paper to silicon: read plant and specification automata (IDES3 .xmd,
/// TCT .ADS, libFAUDES .gen, Supremica .wmod), synthesise supervisors and pack them for a microcontroller.
#[derive(Debug, Parser)]
#[command(name = "codegen", version)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    command: Command,
}

/// The subcommands; each lives in its own module.
#[derive(Debug, Subcommand)]
enum Command {
    Inspect(inspect::Args),
    Convert(convert::Args),
    Dot(dot::Args),
    Pack(pack::Args),
    Check(check::Args),
    Emit(emit::Args),
    Bench(bench::Args),
    New(new::Args),
    Synth(synth::Args),
    Plant(plant::Args),
    Plc(plc::Args),
    Run(run::Args),
    Sim(sim::Args),
    Verify(verify::Args),
}

/// Runs the chosen subcommand; `Ok` carries its exit status (0, or 1 when a check failed). That no
/// supervisor exists for a specification is a verdict, not bad input: said on stderr, exit 1, whichever
/// command synthesised.
pub fn run(cli: Cli) -> Result<ExitCode, Error> {
    let result = subcommand(cli);
    if let Err(e) = &result {
        if let Some(verdict) = no_supervisor(e.as_ref()) {
            eprintln!("{verdict}");
            return Ok(ExitCode::from(1));
        }
    }
    result
}

/// The no-supervisor verdict among `e` and its causes.
fn no_supervisor<'a>(e: &'a (dyn StdError + 'static)) -> Option<&'a NoSupervisor> {
    let mut cur = Some(e);
    while let Some(err) = cur {
        if let Some(SynthError::NoSupervisor(verdict)) = err.downcast_ref::<SynthError>() {
            return Some(verdict);
        }
        cur = err.source();
    }
    None
}

fn subcommand(cli: Cli) -> Result<ExitCode, Error> {
    match cli.command {
        Command::Inspect(args) => inspect::run(args),
        Command::Convert(args) => convert::run(args),
        Command::Dot(args) => dot::run(args),
        Command::Pack(args) => pack::run(args),
        Command::Check(args) => check::run(args),
        Command::Emit(args) => emit::run(args),
        Command::Bench(args) => bench::run(args),
        Command::New(args) => new::run(args),
        Command::Synth(args) => synth::run(args),
        Command::Plant(args) => plant::run(args),
        Command::Plc(args) => plc::run(args),
        Command::Run(args) => run::run(args),
        Command::Sim(args) => sim::run(args),
        Command::Verify(args) => verify::run(args),
    }
}

/// Says on stderr which components of Supremica modules given with `--plant`, `--spec` or `--sup` were
/// left out for being of another kind.
pub fn say_skipped(skipped: &[String]) {
    for s in skipped {
        eprintln!("note: {s} left out: not of the role its module was given in");
    }
}

/// Deploys the supervisors `choice` names, when given (`--supervisors`), and says which the project
/// runs: on stdout as the report's first line, or on stderr when stdout carries JSON.
pub fn deploy(project: &mut Project, choice: Option<SupervisorChoice>, json: bool) -> Result<(), Error> {
    if let Some(choice) = choice {
        project.choose_supervisors(choice, &Config::default())?;
    }
    if json {
        eprintln!("supervisors: {}", project.deployed);
    } else {
        println!("supervisors: {}", project.deployed);
    }
    Ok(())
}

/// Whether `e` (or one of its causes) is a write to a closed pipe.
pub fn is_broken_pipe(e: &(dyn StdError + 'static)) -> bool {
    let mut cur = Some(e);
    while let Some(err) = cur {
        if err.downcast_ref::<std::io::Error>().is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
        {
            return true;
        }
        cur = err.source();
    }
    false
}

pub use codegen::project::build_script::chain;
