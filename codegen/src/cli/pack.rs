//! `codegen pack`: the bytes every layout takes for a supervisor set, against the floor and the paper.

use std::io::Write;
use std::process::ExitCode;

use codegen::config::{RuntimeConfig, SupervisorChoice};
use codegen::pack::{report::Report, Layout};
use codegen::project::comparison::modular_and_monolithic;
use codegen::project::deployed_set;
use codegen::synth::Config;

use super::files::Files;
use super::Error;

/// Report the size of a supervisor set in every table layout.
///
/// Prints per automaton the bytes of each layout and the information-theoretic floor, then per layout the
/// total with every side table named, for plants and supervisors together (what the firmware holds) and
/// for the supervisors alone (what the reference paper counted), and the paper's matrix, chained-list and
/// memory-safe columns.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project: a manifest, or modules and model files (one project, loaded as by every command),
    /// or files in roles (plants first in the event numbering). Its supervisors are the ready ones and
    /// the local modular ones synthesised from its specifications, which also give the modular and
    /// monolithic rows.
    #[command(flatten)]
    input: Files,
    /// Report only this layout (memory-safe, offset, ranked, indexed or compact). The layouts the
    /// firmware runs — the manifest's `[runtime] layout`, else ranked on the Cortex-M3 and indexed on
    /// the Cortex-M0+ (ranked when indexed does not fit the Pico) — are marked where their tables fit the
    /// board's flash; a core that runs none says why.
    #[arg(long, value_parser = parse_layout)]
    layout: Option<Layout>,
    /// Which supervisors to measure: the full set, each supervisor reduced, or one monolithic
    /// supervisor, full or reduced — the set `emit` and `run` deploy, proven to give the plants the full
    /// set's closed loop first [default: the manifest's `[runtime] supervisors`, else full].
    #[arg(long = "supervisors", id = "deploy", value_enum, value_name = "CHOICE")]
    deploy: Option<SupervisorChoice>,
    /// Print JSON (schema 1): supervisors (the deployed set), layouts (name, bytes, supervisor_bytes, per_automaton, side_tables,
    /// runs_on, fits), cores (core, board, layout or refused), floor_bytes, paper (matrix, chained_list,
    /// memory_safe), comparisons, automata.
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
    let loaded = args.input.load()?;
    let runtime = loaded.manifest.as_ref().map_or_else(RuntimeConfig::default, |m| m.runtime.clone());
    let choice = args.deploy.unwrap_or(runtime.supervisors);
    let (set, deployed) = deployed_set(&loaded, &Config::default(), choice)?;
    let models = &loaded.models;
    let comparisons = if models.specs.is_empty() {
        Vec::new()
    } else {
        modular_and_monolithic(&models.plants, &models.specs, set.events().len(), &Config::default())
    };
    let layouts: Vec<Layout> = match args.layout {
        Some(l) => vec![l],
        None => Layout::ALL.to_vec(),
    };
    let report = Report::new(set, &layouts, comparisons).with_runtime(&runtime);
    let mut out = std::io::stdout().lock();
    if args.json {
        let mut json = report.to_json();
        json["supervisors"] = deployed.to_string().into();
        // Serialised first so a closed pipe surfaces as an io::Error, which `main` treats as success.
        writeln!(out, "{}", serde_json::to_string_pretty(&json)?)?;
    } else {
        writeln!(out, "supervisors: {deployed}")?;
        write!(out, "{report}")?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}
