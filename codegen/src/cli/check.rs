//! `codegen check`: the implementation problems a supervisor set can still hit, each with a trace.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use serde_json::{json, Value};

use codegen::manifest::{is_manifest, Manifest, ModelSet};
use codegen::model::Automaton;
use codegen::problems::{run as check, scopes, Finding, Problem, Shape};
use codegen::project::supervisors;
use codegen::synth::{product, Config};

use super::{limits, Error};

/// Check a closed loop for avalanche, choice, inexact synchronisation and simultaneity problems.
///
/// The automata of the files are composed: those given with `--sup` or marked as supervisors by their
/// file are supervisors, all others plants. The closed loop (everything together) is checked first, then
/// each supervisor with its local plant. Every finding names the state, the events and a shortest trace
/// from the initial state. Exit status 1 when a requested check finds something.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A project manifest (TOML; supervisors as listed, else synthesised local modular), or model files
    /// (.xmd, .ads, .gen, .wmod).
    #[arg(required_unless_present = "supervisors")]
    files: Vec<PathBuf>,
    /// Supervisor model files.
    #[arg(long = "sup", num_args = 1..)]
    supervisors: Vec<PathBuf>,
    /// Run only this check (repeatable): avalanche, choice, inexact-synchronisation, simultaneity.
    #[arg(long = "check", value_parser = parse_problem)]
    checks: Vec<Problem>,
    /// Findings printed per check and scope (all of them go to --json).
    #[arg(long, default_value_t = 5)]
    max: usize,
    /// Print JSON (schema 1): scopes (name, states, transitions, findings: problem, state, events, trace,
    /// shape, detail), failed.
    #[arg(long)]
    json: bool,
    /// Stop when a closed loop grows the process past this resident size: bytes with K, M or G (512M,
    /// 2G), or none [default: three quarters of the machine's RAM].
    #[arg(long, value_name = "SIZE", value_parser = limits::parse_size)]
    memory_limit: Option<limits::MemoryLimit>,
}

fn parse_problem(name: &str) -> Result<Problem, String> {
    Problem::from_name(name).ok_or_else(|| {
        let names: Vec<_> = Problem::ALL.iter().map(|p| p.name()).collect();
        format!("unknown check '{name}' (one of: {})", names.join(", "))
    })
}

/// One scope's closed loop and what the checks found on it.
struct Checked {
    name: String,
    automaton: Automaton,
    findings: Vec<Finding>,
}

/// Runs `check`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let problems = if args.checks.is_empty() { Problem::ALL.to_vec() } else { args.checks.clone() };
    let closed = match args.files.as_slice() {
        [one] if is_manifest(one) => supervisors(Manifest::load(one)?.read_automata()?)?,
        files => {
            let (mut set, skipped) = ModelSet::from_files(files, &[], &args.supervisors)?;
            super::say_skipped(&skipped);
            set.resolve_controllability()?;
            set
        }
    };
    let (plants, supervisors) = (closed.plants, closed.supervisors);
    let (observer, bar) = limits::progress();
    let cfg = Config {
        memory_limit: limits::memory_limit(args.memory_limit),
        observer: Some(observer),
        ..Config::default()
    };
    let mut checked = Vec::new();
    for scope in scopes(&plants, &supervisors) {
        let automaton = match scope.members.as_slice() {
            [one] => (*one).clone(),
            many => product(&many.iter().map(|a| (*a).clone()).collect::<Vec<_>>(), &cfg)?,
        };
        let findings = check(&automaton, &problems);
        checked.push(Checked { name: scope.name, automaton, findings });
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let failed = checked.iter().any(|c| !c.findings.is_empty());
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&to_json(&checked, failed))?)?;
    } else {
        for c in &checked {
            write_text(&mut out, c, &problems, args.max)?;
        }
    }
    out.flush()?;
    Ok(if failed { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

fn write_text(out: &mut impl Write, c: &Checked, problems: &[Problem], max: usize) -> std::io::Result<()> {
    writeln!(
        out,
        "{}: {} states, {} transitions",
        c.name,
        c.automaton.states.len(),
        c.automaton.transitions.len()
    )?;
    for &p in problems {
        let of: Vec<&Finding> = c.findings.iter().filter(|f| f.problem == p).collect();
        if of.is_empty() {
            writeln!(out, "  {}: none", p.name())?;
            continue;
        }
        let mut shapes: Vec<(Shape, usize)> = Vec::new();
        let mut pairs: Vec<&[String]> = of.iter().map(|f| f.events.as_slice()).collect();
        pairs.sort_unstable();
        pairs.dedup();
        for f in &of {
            match shapes.iter_mut().find(|(s, _)| *s == f.shape) {
                Some((_, n)) => *n += 1,
                None => shapes.push((f.shape, 1)),
            }
        }
        shapes.sort_unstable();
        let shapes: Vec<String> = shapes.iter().map(|(s, n)| format!("{} {n}", s.name())).collect();
        writeln!(
            out,
            "  {}: {} finding(s) over {} event set(s) ({})",
            p.name(),
            of.len(),
            pairs.len(),
            shapes.join(", ")
        )?;
        for f in of.iter().take(max) {
            writeln!(out, "    {f}")?;
        }
        if of.len() > max {
            writeln!(out, "    … {} more (--max, --json)", of.len() - max)?;
        }
    }
    Ok(())
}

fn to_json(checked: &[Checked], failed: bool) -> Value {
    let scopes: Vec<Value> = checked
        .iter()
        .map(|c| {
            let findings: Vec<Value> = c
                .findings
                .iter()
                .map(|f| {
                    json!({
                        "problem": f.problem.name(),
                        "state": f.state,
                        "events": f.events,
                        "trace": f.trace,
                        "shape": f.shape.name(),
                        "detail": f.detail,
                    })
                })
                .collect();
            json!({
                "name": c.name,
                "states": c.automaton.states.len(),
                "transitions": c.automaton.transitions.len(),
                "findings": findings,
            })
        })
        .collect();
    json!({"schema": 1, "scopes": scopes, "failed": failed})
}
