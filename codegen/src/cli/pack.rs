//! `codegen pack`: the bytes every layout takes for a supervisor set, against the floor and the paper.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use codegen::formats::read_path;
use codegen::model::Automaton;
use codegen::pack::{comparison::modular_and_monolithic, report::Report, Layout, PackSet};
use codegen::synth::Config;

use super::Error;

/// Report the size of a supervisor set in every table layout.
///
/// Prints per automaton the bytes of each layout and the information-theoretic floor, then per layout the
/// total with every side table named, for plants and supervisors together (what the firmware holds) and
/// for the supervisors alone (what the reference paper counted), and the paper's matrix, chained-list and
/// memory-safe columns.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Plant model files, in order (their events are numbered first).
    #[arg(long = "plant", num_args = 1.., required = true)]
    plants: Vec<PathBuf>,
    /// Supervisor model files, in order.
    #[arg(long = "sup", num_args = 1..)]
    supervisors: Vec<PathBuf>,
    /// Specification model files: with them the report adds the paper's columns for the modular and
    /// monolithic supervisors, synthesised from the plants and these specifications.
    #[arg(long = "spec", num_args = 1..)]
    specs: Vec<PathBuf>,
    /// Report only this layout (memory-safe, offset or compact).
    #[arg(long, value_parser = parse_layout)]
    layout: Option<Layout>,
    /// Print JSON (schema 1): layouts (name, bytes, supervisor_bytes, per_automaton, side_tables),
    /// floor_bytes, paper (matrix, chained_list, memory_safe), comparisons, automata.
    #[arg(long)]
    json: bool,
}

fn parse_layout(name: &str) -> Result<Layout, String> {
    Layout::from_name(name).ok_or_else(|| {
        let names: Vec<_> = Layout::ALL.iter().map(|l| l.name()).collect();
        format!("unknown layout '{name}' (one of: {})", names.join(", "))
    })
}

/// Every automaton of every file, in order.
fn read_all(files: &[PathBuf]) -> Result<Vec<Automaton>, Error> {
    let mut out = Vec::new();
    for f in files {
        out.extend(read_path(f)?);
    }
    Ok(out)
}

/// Runs `pack`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let plants = read_all(&args.plants)?;
    let specs = read_all(&args.specs)?;
    let set = PackSet::new(plants.clone(), read_all(&args.supervisors)?)?;
    let comparisons = if specs.is_empty() {
        Vec::new()
    } else {
        modular_and_monolithic(&plants, &specs, set.events().len(), &Config::default())
    };
    let layouts: Vec<Layout> = match args.layout {
        Some(l) => vec![l],
        None => Layout::ALL.to_vec(),
    };
    let report = Report::new(set, &layouts, comparisons);
    let mut out = std::io::stdout().lock();
    if args.json {
        // Serialised first so a closed pipe surfaces as an io::Error, which `main` treats as success.
        writeln!(out, "{}", serde_json::to_string_pretty(&report.to_json())?)?;
    } else {
        write!(out, "{report}")?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}
