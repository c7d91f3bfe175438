//! `codegen verify`: a sequence drawn as a Petri net, verified under the project's supervisors.

use std::path::PathBuf;
use std::process::ExitCode;

use codegen::manifest::Manifest;
use codegen::net::{dot, verdict::returning, verify, Limits, Report};
use codegen::project::supervisors;

use super::{limits, Error};

/// Verify that the net of a manifest's `[net]` section is nonblocking under its supervisors.
///
/// Builds the IO-reachability graph of the net (PNML, with the conditions, actions and signals of
/// `[net]`) under the admissible behaviour — the plants with the supervisors (as listed, else synthesised
/// local modular from the specifications) — and judges it by Mušič & Matko's Definition 2: every net
/// transition fires somewhere, and the initial node stays reachable from every node. For a blocking net it
/// prints a shortest trace to a node that cannot return, the places marked there and the actions the
/// supervisors refuse. Exit status 0 nonblocking, 1 blocking, 2 bad input.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project manifest (TOML) with a `[net]` section.
    manifest: PathBuf,
    /// Print JSON: verdict, nodes, edges, dead_transitions, blocking_nodes, admissible {states,
    /// transitions}, and for a blocking net trace, marking and refused.
    #[arg(long)]
    json: bool,
    /// Write the graph in Graphviz DOT to FILE.
    #[arg(long, value_name = "FILE")]
    dot: Option<PathBuf>,
    /// Stop when the graph (or the admissible behaviour) has more nodes than this.
    #[arg(long, default_value_t = 1_000_000)]
    state_limit: usize,
    /// Stop when the process grows past this resident size: bytes with K, M or G (512M, 2G), or none
    /// [default: three quarters of the machine's RAM].
    #[arg(long, value_name = "SIZE", value_parser = limits::parse_size)]
    memory_limit: Option<limits::MemoryLimit>,
}

/// Runs `verify`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let manifest = Manifest::load(&args.manifest)?;
    let Some(spec) = &manifest.net else {
        return Err(format!("{}: no [net] section: nothing to verify", args.manifest.display()).into());
    };
    let read = manifest.read_automata()?;
    codegen::maps::check(&manifest, &read, None)?;
    let models = supervisors(read)?;
    let automata: Vec<_> = models.plants.iter().chain(&models.supervisors).collect();
    let limits =
        Limits { state_limit: args.state_limit, memory_limit: limits::memory_limit(args.memory_limit) };
    let v = verify(spec, &manifest.file, &automata, limits)?;
    if let Some(path) = &args.dot {
        let text = dot::write(
            &v.graph,
            &v.net,
            &v.table,
            &returning(&v.graph).iter().map(|r| !r).collect::<Vec<_>>(),
        );
        std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&Report { verdict: &v.verdict, admissible: v.admissible })?
        );
    } else {
        println!(
            "admissible behaviour: {} states, {} transitions",
            v.admissible.states, v.admissible.transitions
        );
        print!("{}", v.verdict.text());
    }
    Ok(if v.verdict.verdict == "nonblocking" { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
