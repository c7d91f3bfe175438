//! `codegen check`: the implementation problems a supervised closed loop can still hit, each with a
//! trace.

use std::io::Write;
use std::process::ExitCode;

use serde_json::{json, Value};

use codegen::manifest::CheckSpec;
use codegen::model::suggest::did_you_mean;
use codegen::model::Automaton;
use codegen::problems::{run as check, scopes, Finding, Problem, Shape};
use codegen::project::synthesise;
use codegen::synth::{product, Config};

use super::files::Files;
use super::{limits, Error};

/// Check a closed loop for avalanche, choice, inexact synchronisation and simultaneity problems.
///
/// The project is loaded as by every command (a manifest, modules and model files as one project, or
/// --plant/--spec/--sup); where it has specifications their local modular supervisors are synthesised,
/// so the loop checked is plants ‖ supervisors. The closed loop is checked first, then each supervisor
/// with its local plant; the report names the automata of each and which position of a state tuple is
/// which. Every finding names the state, the events and a shortest trace from the initial state.
/// Exit status 1 when a failing kind of finding is found: those given with --check, else the
/// manifest's `[check] fail_on`, else avalanche only; 2 on bad input.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project.
    #[command(flatten)]
    input: Files,
    /// Run only this check (repeatable; each one run fails the command when it finds something):
    /// avalanche, choice, inexact-synchronisation, simultaneity.
    #[arg(long = "check", value_parser = parse_problem)]
    checks: Vec<Problem>,
    /// Findings printed per check and scope (all of them go to --json).
    #[arg(long, default_value_t = 5)]
    max: usize,
    /// Print JSON (schema 2): closed_loop (plants, supervisors, states, transitions, legend), scopes
    /// (name, members, states, transitions, findings: problem, state, events, trace, shape, detail),
    /// fail_on, failed.
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

/// The problems `[check] fail_on` names; an unknown name is refused with the names closest to it.
fn fail_on(spec: &CheckSpec, manifest: &str) -> Result<Vec<Problem>, Error> {
    let names = || Problem::ALL.iter().map(|p| p.name());
    spec.fail_on
        .iter()
        .map(|n| {
            Problem::from_name(n).ok_or_else(|| {
                let all: Vec<&str> = names().collect();
                format!(
                    "{manifest}: check.fail_on: unknown check '{n}'{} (one of: {})",
                    did_you_mean(n, names()),
                    all.join(", ")
                )
                .into()
            })
        })
        .collect()
}

/// One scope's closed loop and what the checks found on it.
struct Checked {
    name: String,
    members: Vec<String>,
    automaton: Automaton,
    findings: Vec<Finding>,
}

/// What the closed loop is made of: its plants and supervisors, and for each synthesised supervisor the
/// automata whose states its own state tuples hold.
struct Loop {
    plants: Vec<String>,
    supervisors: Vec<String>,
    legend: Vec<(String, Vec<String>)>,
}

/// Runs `check`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let loaded = args.input.load()?;
    let failing = match (&args.checks, &loaded.manifest) {
        (given, _) if !given.is_empty() => given.clone(),
        (_, Some(m)) => fail_on(&m.check, &m.file.display().to_string())?,
        (_, None) => fail_on(&CheckSpec::default(), "")?,
    };
    let problems = if args.checks.is_empty() { Problem::ALL.to_vec() } else { args.checks.clone() };
    let (observer, bar) = limits::progress();
    let cfg = Config {
        memory_limit: limits::memory_limit(args.memory_limit),
        observer: Some(observer),
        ..Config::default()
    };
    let (models, synthesised) = synthesise(loaded.models, &cfg)?;
    let (plants, supervisors) = (models.plants, models.supervisors);
    let names = |v: &[Automaton]| v.iter().map(|a| a.name.clone()).collect::<Vec<_>>();
    let closed = Loop {
        plants: names(&plants),
        supervisors: names(&supervisors),
        legend: synthesised
            .iter()
            .map(|s| (s.automaton.name.clone(), s.plants.iter().chain(&s.specs).cloned().collect()))
            .collect(),
    };
    let mut checked = Vec::new();
    for scope in scopes(&plants, &supervisors) {
        let automaton = match scope.members.as_slice() {
            [one] => (*one).clone(),
            many => product(&many.iter().map(|a| (*a).clone()).collect::<Vec<_>>(), &cfg)?,
        };
        let findings = check(&automaton, &problems);
        let members = scope.members.iter().map(|a| a.name.clone()).collect();
        checked.push(Checked { name: scope.name, members, automaton, findings });
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let failed = checked.iter().any(|c| c.findings.iter().any(|f| failing.contains(&f.problem)));
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&to_json(&closed, &checked, &failing, failed))?)?;
    } else {
        write_loop(&mut out, &closed)?;
        for c in &checked {
            write_text(&mut out, c, &problems, args.max)?;
        }
        let names: Vec<&str> = failing.iter().map(|p| p.name()).collect();
        let verdict = if failed { "failed" } else { "passed" };
        writeln!(out, "{verdict} (failing kinds: {})", names.join(", "))?;
    }
    out.flush()?;
    Ok(if failed { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

/// The closed loop's make-up and the legend of its state tuples.
fn write_loop(out: &mut impl Write, l: &Loop) -> std::io::Result<()> {
    let list = |v: &[String]| if v.is_empty() { "none".to_owned() } else { v.join(", ") };
    writeln!(out, "checked: plants {} with supervisors {}", list(&l.plants), list(&l.supervisors))?;
    writeln!(out, "legend: a state is a tuple of one state per automaton, in the order after 'a state is'")?;
    if !l.legend.is_empty() {
        writeln!(
            out,
            "  a synthesised supervisor's own state is a tuple of its plants' and specifications':"
        )?;
    }
    for (name, of) in &l.legend {
        writeln!(out, "  {name} = ({})", of.join(", "))?;
    }
    Ok(())
}

fn write_text(out: &mut impl Write, c: &Checked, problems: &[Problem], max: usize) -> std::io::Result<()> {
    writeln!(
        out,
        "{}: {} states, {} transitions; a state is ({})",
        c.name,
        c.automaton.states.len(),
        c.automaton.transitions.len(),
        c.members.join(", ")
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

fn to_json(l: &Loop, checked: &[Checked], failing: &[Problem], failed: bool) -> Value {
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
                "members": c.members,
                "states": c.automaton.states.len(),
                "transitions": c.automaton.transitions.len(),
                "findings": findings,
            })
        })
        .collect();
    let closed = &checked[0];
    let legend: Vec<Value> =
        l.legend.iter().map(|(name, of)| json!({"supervisor": name, "state": of})).collect();
    json!({
        "schema": 2,
        "closed_loop": {
            "plants": l.plants,
            "supervisors": l.supervisors,
            "states": closed.automaton.states.len(),
            "transitions": closed.automaton.transitions.len(),
            "legend": legend,
        },
        "scopes": scopes,
        "fail_on": failing.iter().map(|p| p.name()).collect::<Vec<_>>(),
        "failed": failed,
    })
}
