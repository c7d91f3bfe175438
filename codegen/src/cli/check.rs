//! `codegen check`: the implementation problems a supervised closed loop can still hit, each with a
//! trace.

use std::io::Write;
use std::process::ExitCode;

use serde_json::{json, Value};

use codegen::manifest::CheckSpec;
use codegen::model::suggest::did_you_mean;
use codegen::model::Automaton;
use codegen::problems::{group, run as check, scopes, Attributor, Concern, Finding, Group, Problem};
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
/// which. Findings are grouped by kind and shape, the groups that can change where the loop goes first,
/// each with its count, its event pairs and a witness (a state and a shortest trace from the initial
/// state); --all lists every finding.
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
    /// List every finding, under its group, of the closed loop and of each supervisor with its local
    /// plant (without it: each group of the closed loop with one witness, each supervisor on one line).
    #[arg(long, visible_alias = "verbose")]
    all: bool,
    /// Print JSON (schema 4): closed_loop (plants, supervisors, states, transitions, legend), scopes
    /// (name, members, states, transitions, findings: problem, state, events, trace, shape, detail,
    /// supervisors;
    /// groups: problem, shape, concern, findings, states, events, witnesses), fail_on, failed.
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
    /// Per finding, the supervisors it involves ([`Attributor`]).
    involves: Vec<Vec<String>>,
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
        let who = Attributor::new(&scope.members, &closed.supervisors);
        let involves = findings.iter().map(|f| who.supervisors(f)).collect();
        let members = scope.members.iter().map(|a| a.name.clone()).collect();
        checked.push(Checked { name: scope.name, members, automaton, findings, involves });
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
        // The closed loop is the first scope; the supervisors' follow.
        if let Some((closed_loop, local)) = checked.split_first() {
            write_scope(&mut out, closed_loop, &problems, args.all)?;
            write_involved(&mut out, closed_loop, &closed.supervisors)?;
            if args.all {
                for c in local {
                    write_scope(&mut out, c, &problems, true)?;
                }
            } else if !local.is_empty() {
                writeln!(out, "each supervisor with its local plant (--all for their findings):")?;
                for c in local {
                    write_summary(&mut out, c)?;
                }
            }
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

/// One scope in full: its findings in groups, most urgent first, each with its count, its states, its
/// event sets and a witness; with `all`, every finding under its group.
fn write_scope(out: &mut impl Write, c: &Checked, problems: &[Problem], all: bool) -> std::io::Result<()> {
    writeln!(
        out,
        "{}: {} states, {} transitions; a state is ({})",
        c.name,
        c.automaton.states.len(),
        c.automaton.transitions.len(),
        c.members.join(", ")
    )?;
    let groups = group(&c.findings);
    let acts = groups.iter().filter(|g| g.concern == Concern::Act).count();
    writeln!(
        out,
        "  {} finding(s) in {} group(s); {} to act on first",
        c.findings.len(),
        groups.len(),
        if acts == 0 { "none".to_owned() } else { format!("{acts} group(s)") }
    )?;
    for concern in Concern::ALL {
        let of: Vec<&Group> = groups.iter().filter(|g| g.concern == concern).collect();
        if of.is_empty() {
            continue;
        }
        writeln!(out, "  {}:", concern.heading())?;
        for g in of {
            write_group(out, c, g, all)?;
        }
    }
    let quiet: Vec<&str> =
        problems.iter().filter(|&&p| c.findings.iter().all(|f| f.problem != p)).map(|p| p.name()).collect();
    if !quiet.is_empty() {
        writeln!(out, "  none: {}", quiet.join(", "))?;
    }
    Ok(())
}

/// Event sets a group line names before it says how many more there are.
const EVENT_SETS_SHOWN: usize = 3;

/// A group: its count, states and event sets on one line, then its nearest witness (or, with `all`,
/// every finding).
fn write_group(out: &mut impl Write, c: &Checked, g: &Group, all: bool) -> std::io::Result<()> {
    let sets: Vec<String> =
        g.events.iter().take(EVENT_SETS_SHOWN).map(|(e, n)| format!("{} {n}", e.join("/"))).collect();
    let more = g.events.len().saturating_sub(EVENT_SETS_SHOWN);
    let more = if more > 0 { format!(", … {more} more") } else { String::new() };
    writeln!(
        out,
        "    {} {}: {} at {} state(s), {} event set(s): {}{more}",
        g.problem.name(),
        g.shape.name(),
        g.findings.len(),
        g.states,
        g.events.len(),
        sets.join(", ")
    )?;
    if all {
        for &i in &g.findings {
            writeln!(out, "      {}", c.findings[i])?;
        }
    } else if let Some(&w) = g.witnesses(&c.findings).first() {
        let f = &c.findings[w];
        let trace = if f.trace.is_empty() { "ε".to_owned() } else { f.trace.join(" ") };
        writeln!(out, "      e.g. at {} (trace: {trace}): {}", f.state, f.detail)?;
    }
    Ok(())
}

/// The closed loop's findings by the supervisors they involve, one line per supervisor (a finding
/// involving several counts for each), then those involving none: the plants' alone.
fn write_involved(out: &mut impl Write, c: &Checked, supervisors: &[String]) -> std::io::Result<()> {
    if supervisors.is_empty() || c.findings.is_empty() {
        return Ok(());
    }
    writeln!(out, "closed-loop findings by the supervisors whose disablement or state they involve:")?;
    let line = |picked: Vec<Finding>| -> String {
        let counts: Vec<String> = group(&picked)
            .iter()
            .map(|g| format!("{} {} {}", g.problem.name(), g.shape.name(), g.findings.len()))
            .collect();
        if counts.is_empty() {
            "none".to_owned()
        } else {
            counts.join(", ")
        }
    };
    let pick = |keep: &dyn Fn(&[String]) -> bool| -> Vec<Finding> {
        c.findings.iter().zip(&c.involves).filter(|(_, i)| keep(i)).map(|(f, _)| f.clone()).collect()
    };
    for s in supervisors {
        writeln!(out, "  {s}: {}", line(pick(&|i| i.contains(s))))?;
    }
    writeln!(out, "  no supervisor (the plants alone): {}", line(pick(&|i| i.is_empty())))
}

/// A supervisor's scope on one line: its size and its groups' counts, most urgent first.
fn write_summary(out: &mut impl Write, c: &Checked) -> std::io::Result<()> {
    let groups = group(&c.findings);
    let counts: Vec<String> = groups
        .iter()
        .map(|g| format!("{} {} {}", g.problem.name(), g.shape.name(), g.findings.len()))
        .collect();
    writeln!(
        out,
        "  {} ({} states, {} transitions): {}",
        c.name,
        c.automaton.states.len(),
        c.automaton.transitions.len(),
        if counts.is_empty() { "nothing found".to_owned() } else { counts.join(", ") }
    )
}

fn to_json(l: &Loop, checked: &[Checked], failing: &[Problem], failed: bool) -> Value {
    let scopes: Vec<Value> = checked
        .iter()
        .map(|c| {
            let findings: Vec<Value> = c
                .findings
                .iter()
                .zip(&c.involves)
                .map(|(f, supervisors)| {
                    json!({
                        "problem": f.problem.name(),
                        "state": f.state,
                        "events": f.events,
                        "trace": f.trace,
                        "shape": f.shape.name(),
                        "detail": f.detail,
                        "supervisors": supervisors,
                    })
                })
                .collect();
            let groups: Vec<Value> = group(&c.findings)
                .iter()
                .map(|g| {
                    let events: Vec<Value> =
                        g.events.iter().map(|(e, n)| json!({"events": e, "findings": n})).collect();
                    json!({
                        "problem": g.problem.name(),
                        "shape": g.shape.name(),
                        "concern": g.concern.name(),
                        "findings": g.findings.len(),
                        "states": g.states,
                        "events": events,
                        "witnesses": g.witnesses(&c.findings),
                    })
                })
                .collect();
            json!({
                "name": c.name,
                "members": c.members,
                "states": c.automaton.states.len(),
                "transitions": c.automaton.transitions.len(),
                "findings": findings,
                "groups": groups,
            })
        })
        .collect();
    let closed = &checked[0];
    let legend: Vec<Value> =
        l.legend.iter().map(|(name, of)| json!({"supervisor": name, "state": of})).collect();
    json!({
        "schema": 4,
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
