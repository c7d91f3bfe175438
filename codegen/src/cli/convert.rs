//! `codegen convert`: read a model in one format, write it in another — never inventing what the input
//! leaves unsaid.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::formats::{read_path, read_paths, write_path, WriteError};
use codegen::model::{resolve_controllability_or, Kind};

use super::Error;

/// Convert a model file to another format, chosen by OUT's extension.
///
/// Reads every automaton of IN (any readable format) and writes them to OUT: .xmd (IDES3), .xml
/// (Nadzoru2), .ads (plus an event map OUT-stem.events when the event names are not TCT's numbers), .gen,
/// .wmod or .dot. Formats that hold one automaton refuse an input with several. What IN leaves unsaid and
/// OUT must say is refused unless given: controllability (a libFAUDES generator without +C+ takes it from
/// the plant; every format but .gen and .dot says it for every event) from --plant or --assume, and the
/// role (a .wmod component is a PLANT, SPEC or SUPERVISOR) from --kind. --component picks one automaton
/// of IN; without it, a format that holds one automaton takes IN's supervisor when IN holds exactly one
/// (the module `synth --format wmod` writes holds its plants beside it) and says so.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The model to read.
    input: PathBuf,
    /// The file to write; its extension picks the format.
    output: PathBuf,
    /// Plant model files to take controllability from, for the events IN leaves it unsaid (read, not
    /// written; every event must be one of theirs, unless --assume says the rest).
    #[arg(long = "plant", num_args = 1.., value_name = "FILE")]
    plants: Vec<PathBuf>,
    /// The controllability of the events IN leaves unsaid and no --plant file says.
    #[arg(long, value_enum, value_name = "WHAT")]
    assume: Option<Assume>,
    /// The role of the automata whose file gives none (a .gen, .xmd, .xml or .ads file): what a .wmod
    /// component must say.
    #[arg(long, value_enum)]
    kind: Option<Role>,
    /// Convert only the automaton of IN with this name (a module's component, such as the supervisor
    /// `synth --format wmod` writes beside its plants).
    #[arg(long, value_name = "NAME")]
    component: Option<String>,
}

/// `--assume`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Assume {
    /// Every such event is controllable.
    Controllable,
    /// Every such event is uncontrollable.
    Uncontrollable,
}

/// `--kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Role {
    /// A plant component.
    Plant,
    /// A specification.
    Spec,
    /// A supervisor.
    Supervisor,
}

/// Runs `convert`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let mut automata = read_path(&args.input)?;
    if let Some(name) = &args.component {
        let names: Vec<&str> = automata.iter().map(|a| a.name.as_str()).collect();
        let Some(i) = names.iter().position(|n| n == name) else {
            return Err(format!(
                "{}: no automaton '{name}' (it holds {})",
                args.input.display(),
                names.join(", ")
            )
            .into());
        };
        automata = vec![automata.swap_remove(i)];
    }
    if let Some(role) = args.kind {
        let kind = match role {
            Role::Plant => Kind::Plant,
            Role::Spec => Kind::Spec,
            Role::Supervisor => Kind::Supervisor,
        };
        automata.iter_mut().filter(|a| a.kind == Kind::Unknown).for_each(|a| a.kind = kind);
    }
    if automata.iter().any(|a| a.controllability_unsaid) && (!args.plants.is_empty() || args.assume.is_some())
    {
        let mut plants = read_paths(&args.plants)?;
        let assume = args.assume.map(|a| a == Assume::Controllable);
        resolve_controllability_or(plants.iter_mut().chain(automata.iter_mut()), assume)
            .map_err(|e| format!("{}: {e}", args.input.display()))?;
    }
    match write_path(&args.output, &automata) {
        Err(e @ WriteError::Unsaid { .. }) => {
            let role = matches!(&e, WriteError::Unsaid { unsaid, .. } if unsaid.iter().any(|u| u.role));
            let controllability =
                matches!(&e, WriteError::Unsaid { unsaid, .. } if unsaid.iter().any(|u| u.controllability));
            let mut say = Vec::new();
            if role {
                say.push("the role with --kind plant|spec|supervisor");
            }
            if controllability {
                say.push(
                    "controllability with --plant FILE… (the plants to take it from) or --assume \
                     controllable|uncontrollable",
                );
            }
            Err(format!("{e}: give {}", say.join(", and ")).into())
        }
        Err(e @ WriteError::TooMany { .. }) => {
            let supervisors: Vec<usize> =
                (0..automata.len()).filter(|&i| automata[i].kind == Kind::Supervisor).collect();
            if let [only] = supervisors[..] {
                let supervisor = automata.swap_remove(only);
                eprintln!(
                    "{}: {} holds one automaton: wrote the supervisor '{}' (another with --component NAME)",
                    args.input.display(),
                    args.output.display(),
                    supervisor.name
                );
                return Ok(write_path(&args.output, std::slice::from_ref(&supervisor))
                    .map(|()| ExitCode::SUCCESS)?);
            }
            let names: Vec<&str> = automata.iter().map(|a| a.name.as_str()).collect();
            Err(format!("{e}: pick one with --component NAME ({})", names.join(", ")).into())
        }
        other => Ok(other.map(|()| ExitCode::SUCCESS)?),
    }
}
