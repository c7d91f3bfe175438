//! `codegen pack`: the bytes every layout takes for a supervisor set, against the floor and the paper.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use codegen::config::RuntimeConfig;
use codegen::pack::{report::Report, Layout, PackSet};
use codegen::project::comparison::modular_and_monolithic;
use codegen::project::{supervisors, Sources};
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
    /// Project manifest (TOML): its plants and its supervisors (listed, else synthesised local modular
    /// from its specifications, which also give the modular and monolithic rows).
    #[arg(required_unless_present = "plants", conflicts_with_all = ["plants", "supervisors", "specs"])]
    manifest: Option<PathBuf>,
    /// Plant model files, in order (their events are numbered first).
    #[arg(long = "plant", num_args = 1..)]
    plants: Vec<PathBuf>,
    /// Supervisor model files, in order.
    #[arg(long = "sup", num_args = 1..)]
    supervisors: Vec<PathBuf>,
    /// Specification model files: with them the report adds the paper's columns for the modular and
    /// monolithic supervisors, synthesised from the plants and these specifications.
    #[arg(long = "spec", num_args = 1..)]
    specs: Vec<PathBuf>,
    /// Report only this layout (memory-safe, offset, ranked, indexed or compact). The layouts the
    /// firmware runs — the manifest's `[runtime] layout`, else ranked on the Cortex-M3 and indexed on
    /// the Cortex-M0+ — are marked.
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

/// Runs `pack`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let sources = Sources {
        files: args.manifest.iter().cloned().collect(),
        plants: args.plants.clone(),
        specs: args.specs.clone(),
        supervisors: args.supervisors.clone(),
    };
    let loaded = sources.load()?;
    super::say_skipped(&loaded.left_out);
    let targets =
        loaded.manifest.as_ref().map_or_else(|| RuntimeConfig::default().layouts(), |m| m.runtime.layouts());
    // A manifest's supervisors are synthesised from its specifications; given files, the specifications
    // only add the comparison rows.
    let closed = if loaded.manifest.is_some() { supervisors(loaded.models)? } else { loaded.models };
    let set = PackSet::new(closed.plants.clone(), closed.supervisors)?;
    let comparisons = if closed.specs.is_empty() {
        Vec::new()
    } else {
        modular_and_monolithic(&closed.plants, &closed.specs, set.events().len(), &Config::default())
    };
    let layouts: Vec<Layout> = match args.layout {
        Some(l) => vec![l],
        None => Layout::ALL.to_vec(),
    };
    let report = Report::new(set, &layouts, comparisons).with_targets(targets);
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
