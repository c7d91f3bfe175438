//! `codegen synth`: synthesise local modular (or monolithic) supervisors and report their sizes.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use codegen::formats::write_path;
use codegen::model::{Automaton, Kind};
use codegen::synth::as_written::{AsWritten, Verdict};
use codegen::synth::{self, Config, LocalModularResult, Supervisor};
use serde_json::json;

use super::engine::{self, BddOrder, Engine, Monolithic};
use super::files::Files;
use super::{limits, Error};

/// Version of the `--json` output; raised when a field changes meaning or disappears.
const JSON_SCHEMA: u32 = 1;

/// Synthesise supervisors from plants and specifications.
///
/// By default: local modular synthesis (one supervisor per specification against the plant subsystems
/// that share events with it), the conflict check, and the merge of conflicting specifications until the
/// set is nonconflicting. Prints a table of supervisor, specifications, local plant, states and
/// transitions with the totals and the conflict verdict. Exit status 1 when the set is left conflicting
/// (only with --no-merge). The files are loaded as by every command (a manifest, modules and model
/// files as one project, or --plant/--spec); a specification event no plant has is refused (exit 2).
/// When no supervisor exists for a specification, says so with a shortest trace of uncontrollable
/// events into what it forbids (exit 1).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project.
    #[command(flatten)]
    input: Files,
    /// Synthesise the one monolithic supervisor instead.
    #[arg(long)]
    monolithic: bool,
    /// Reduce each supervisor against its (local) plant: Su and Wonham's control congruence, the greedy
    /// merge run in several state orders and again on its result, never larger than TCT supreduce on
    /// the same supervisor; prints each size before reduction and the lower bound (TCT's slb).
    #[arg(long)]
    reduce: bool,
    /// Print each supervisor's control data (TCT condat): per state, the controllable events it
    /// disables against its (local) plant; with --json, the object `condat`.
    #[arg(long)]
    condat: bool,
    /// Report conflicting supervisors instead of merging their specifications.
    #[arg(long)]
    no_merge: bool,
    /// Stop when a product or supervisor exceeds this many states.
    #[arg(long, default_value_t = Config::default().state_limit)]
    state_limit: usize,
    /// Stop when a product grows the process past this resident size: bytes with K, M or G (512M, 2G),
    /// or none [default: three quarters of the machine's RAM].
    #[arg(long, value_name = "SIZE", value_parser = limits::parse_size)]
    memory_limit: Option<limits::MemoryLimit>,
    /// Synthesis engine: explicit states, symbolic (BDDs: monolithic supC, the conflict check of modular
    /// sets), or auto (explicit first, symbolic once a product passes a million states). Stderr says which ran.
    #[arg(long, value_enum, default_value_t = Engine::Explicit)]
    engine: Engine,
    /// The symbolic engine's variable order.
    #[arg(long, value_enum, default_value_t = BddOrder::EventGraph)]
    bdd_order: BddOrder,
    /// Print JSON: schema, supervisors (name, specs, plants, states, transitions, spec_controllable:
    /// its specifications controllable as written, null if undecided), nonconflicting, merged,
    /// total_states, total_transitions, specifications (name, local_plant, controllable as written,
    /// refusal, undecided) (with --reduce, each supervisor's unreduced_states,
    /// unreduced_transitions and lower_bound; with --condat, condat: supervisor → state → disabled events).
    #[arg(long)]
    json: bool,
    /// Write every supervisor to DIR/<name>.xmd (or, with --format nadzoru2, DIR/<name>.xml; with
    /// --format wmod, all to one module).
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    out: Option<PathBuf>,
    /// What -o writes: one IDES3 file per supervisor, one Nadzoru2 file per supervisor, or one Supremica
    /// module DIR/<project>.wmod holding the plants (PLANT) and the supervisors (SUPERVISOR), itself a
    /// project the other commands run.
    #[arg(long, value_enum, default_value_t = OutFormat::Xmd, requires = "out")]
    format: OutFormat,
}

/// `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum OutFormat {
    /// DIR/<supervisor>.xmd, one per supervisor.
    Xmd,
    /// DIR/<supervisor>.xml, one Nadzoru2 file per supervisor.
    Nadzoru2,
    /// DIR/<project>.wmod: plants and supervisors in one Supremica module.
    Wmod,
}

/// One row of the report, with the size before reduction and the lower bound when reduced.
struct Row {
    supervisor: Supervisor,
    unreduced: Option<(usize, usize, usize)>,
    /// The control data, per state of the supervisor (with --condat).
    condat: Option<Vec<Vec<String>>>,
}

/// Runs `synth`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let loaded = args.input.load()?;
    let (name, plants, specs) = (loaded.name, loaded.models.plants, loaded.models.specs);
    if specs.is_empty() {
        return Err("no specification to synthesise a supervisor for".into());
    }
    let (observer, bar) = limits::progress();
    let cfg = Config {
        state_limit: args.state_limit,
        memory_limit: limits::memory_limit(args.memory_limit),
        merge_conflicting: !args.no_merge,
        observer: Some(observer),
        nonblocking: None,
    };
    let check = if args.monolithic { None } else { args.engine.conflict_check(args.bdd_order.options()) };
    let cfg = Config { nonblocking: check.clone().map(|c| c as _), ..cfg };
    let mut ran_symbolic = false;
    let result = if args.monolithic {
        let s = match args.engine.monolithic(&plants, &specs, &cfg, &args.bdd_order.options())? {
            Monolithic::Explicit(s) => s,
            Monolithic::Symbolic(r) => {
                ran_symbolic = true;
                match r.to_supervisor() {
                    Some(s) => s,
                    None if args.out.is_some() || args.reduce => {
                        return Err(format!(
                            "{}: {} states, more than the {} listed as an automaton: -o and --reduce need one",
                            r.name,
                            r.states,
                            codegen::symbolic::EXPLICIT_LIMIT
                        )
                        .into());
                    }
                    None => {
                        bar.inspect(|b| b.finish_and_clear());
                        return engine::report_counts(&name, &r, args.json, JSON_SCHEMA);
                    }
                }
            }
        };
        LocalModularResult { supervisors: vec![s], nonconflicting: true, merged: Vec::new() }
    } else {
        let r = synth::local_modular(&plants, &specs, &cfg)?;
        ran_symbolic = engine::say_conflict_check(check.as_ref());
        r
    };
    let (nonconflicting, merged) = (result.nonconflicting, result.merged);
    let mut rows = Vec::new();
    for mut s in result.supervisors {
        let mut unreduced = None;
        let local: Vec<Automaton> = plants.iter().filter(|p| s.plants.contains(&p.name)).cloned().collect();
        if args.reduce {
            cfg.observer.as_ref().inspect(|o| o.stage(&format!("reducing {}", s.automaton.name)));
            let r = synth::reduction(&local, &s.automaton, &cfg)?;
            unreduced = Some((s.automaton.states.len(), s.automaton.transitions.len(), r.lower_bound));
            s.automaton = r.automaton;
        }
        let condat = if args.condat { Some(synth::condat(&local, &s.automaton, &cfg)?) } else { None };
        rows.push(Row { supervisor: s, unreduced, condat });
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if let Some(dir) = &args.out {
        match args.format {
            OutFormat::Xmd => write_all(dir, &rows, "xmd")?,
            OutFormat::Nadzoru2 => write_all(dir, &rows, "xml")?,
            OutFormat::Wmod => write_module(dir, &name, &plants, &rows)?,
        }
    }
    let conflict = if nonconflicting { None } else { Some(Conflict::find(&rows, &cfg)?) };
    let as_written = synth::as_written::specifications(&plants, &specs, &cfg)?;
    let mut out = std::io::stdout().lock();
    if args.json {
        let mut value = to_json(&name, &rows, nonconflicting, &merged);
        value["engine"] = json!(if ran_symbolic { "symbolic" } else { "explicit" });
        value["specifications"] = as_written
            .iter()
            .map(|v| {
                json!({
                    "name": v.spec,
                    "local_plant": v.plants,
                    "controllable": v.controllable(),
                    "refusal": match &v.verdict {
                        Verdict::Refuses(r) => json!({ "trace": r.trace, "state": r.state, "event": r.event }),
                        _ => serde_json::Value::Null,
                    },
                    "undecided": match &v.verdict {
                        Verdict::Undecided(why) => json!(why),
                        _ => serde_json::Value::Null,
                    },
                })
            })
            .collect();
        // Per supervisor: its specifications all controllable as written (true), one not (false), else
        // undecided (null).
        if let Some(supervisors) = value["supervisors"].as_array_mut() {
            for (o, r) in supervisors.iter_mut().zip(&rows) {
                let verdicts =
                    r.supervisor.specs.iter().map(|spec| {
                        as_written.iter().find(|v| &v.spec == spec).and_then(|v| v.controllable())
                    });
                let verdicts: Vec<Option<bool>> = verdicts.collect();
                o["spec_controllable"] = if verdicts.contains(&Some(false)) {
                    json!(false)
                } else if verdicts.iter().all(|v| *v == Some(true)) {
                    json!(true)
                } else {
                    serde_json::Value::Null
                };
            }
        }
        if let Some(c) = &conflict {
            value["conflict"] = json!({ "supervisors": c.supervisors, "trace": c.trace, "state": c.state });
        }
        let text = serde_json::to_string_pretty(&value)?;
        writeln!(out, "{text}")?;
    } else {
        write_table(&mut out, &rows, &as_written, nonconflicting, &merged)?;
        if let Some(c) = &conflict {
            writeln!(out, "{c}")?;
        }
        for r in &rows {
            if let Some(data) = &r.condat {
                write_condat(&mut out, &r.supervisor.automaton, data)?;
            }
        }
    }
    out.flush()?;
    Ok(if nonconflicting { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// `DIR/<supervisor>.EXT`, one file per supervisor in the format of `ext`.
fn write_all(dir: &Path, rows: &[Row], ext: &str) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for r in rows {
        let a = &r.supervisor.automaton;
        write_path(&dir.join(format!("{}.{ext}", a.name)), std::slice::from_ref(a))?;
    }
    Ok(())
}

/// `DIR/<name>.wmod`: the plants as PLANT components, then the supervisors as SUPERVISOR components,
/// as Supremica's own synthesis leaves them beside the plants; read back, the module is a project whose
/// supervisors are ready (nothing is synthesised again).
fn write_module(dir: &Path, name: &str, plants: &[Automaton], rows: &[Row]) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let with_kind = |a: &Automaton, kind| Automaton { kind, ..a.clone() };
    let module: Vec<Automaton> = plants
        .iter()
        .map(|p| with_kind(p, Kind::Plant))
        .chain(rows.iter().map(|r| with_kind(&r.supervisor.automaton, Kind::Supervisor)))
        .collect();
    write_path(&dir.join(format!("{name}.wmod")), &module)?;
    Ok(())
}

/// Why supervisors synthesised without merging (`--no-merge`) conflict: the fewest of them whose
/// product blocks (two, when two do), and a shortest trace into a state of that product from which no
/// marked state can be reached.
struct Conflict {
    /// The supervisors whose product blocks.
    supervisors: Vec<String>,
    /// A shortest string of events into the blocking state.
    trace: Vec<String>,
    /// The blocking state, as the tuple of the supervisors' states.
    state: String,
}

impl Conflict {
    /// The first pair of `rows`' supervisors (in order) whose product blocks, else all of them.
    fn find(rows: &[Row], cfg: &Config) -> Result<Conflict, Error> {
        let sups: Vec<&Automaton> = rows.iter().map(|r| &r.supervisor.automaton).collect();
        let blocks = |group: &[&Automaton]| -> Result<Option<Conflict>, Error> {
            let automata: Vec<Automaton> = group.iter().map(|a| (*a).clone()).collect();
            Ok(synth::verify::nonblocking(&automata, cfg)?.map(|b| Conflict {
                supervisors: group.iter().map(|a| a.name.clone()).collect(),
                trace: b.trace,
                state: b.state,
            }))
        };
        for (i, a) in sups.iter().enumerate() {
            for b in &sups[i + 1..] {
                if let Some(c) = blocks(&[a, b])? {
                    return Ok(c);
                }
            }
        }
        Ok(blocks(&sups)?.ok_or("the conflict check and its trace disagree: please report")?)
    }
}

impl std::fmt::Display for Conflict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let trace =
            if self.trace.is_empty() { "ε (the initial state)".to_owned() } else { self.trace.join(" ") };
        write!(
            f,
            "  {} block together: after {trace} their product is at state ({}), from which no marked state \
             can be reached\n  merge them (run without --no-merge: their specifications are synthesised as one) \
             or change the specifications",
            self.supervisors.join(" and "),
            self.state
        )
    }
}

fn totals(rows: &[Row]) -> (usize, usize) {
    rows.iter().fold((0, 0), |(s, t), r| {
        (s + r.supervisor.automaton.states.len(), t + r.supervisor.automaton.transitions.len())
    })
}

fn to_json(name: &str, rows: &[Row], nonconflicting: bool, merged: &[Vec<String>]) -> serde_json::Value {
    let (states, transitions) = totals(rows);
    let supervisors: Vec<_> = rows
        .iter()
        .map(|r| {
            let a = &r.supervisor.automaton;
            let mut o = json!({
                "name": a.name,
                "specs": r.supervisor.specs,
                "plants": r.supervisor.plants,
                "states": a.states.len(),
                "transitions": a.transitions.len(),
            });
            if let Some((s, t, bound)) = r.unreduced {
                o["unreduced_states"] = json!(s);
                o["unreduced_transitions"] = json!(t);
                o["lower_bound"] = json!(bound);
            }
            o
        })
        .collect();
    let mut value = json!({
        "schema": JSON_SCHEMA,
        "name": name,
        "supervisors": supervisors,
        "nonconflicting": nonconflicting,
        "merged": merged,
        "total_states": states,
        "total_transitions": transitions,
    });
    if rows.iter().any(|r| r.condat.is_some()) {
        let per_supervisor: serde_json::Map<String, serde_json::Value> = rows
            .iter()
            .filter_map(|r| {
                let a = &r.supervisor.automaton;
                let states: serde_json::Map<String, serde_json::Value> = a
                    .states
                    .iter()
                    .zip(r.condat.as_ref()?)
                    .filter(|(_, d)| !d.is_empty())
                    .map(|(s, d)| (s.name.clone(), json!(d)))
                    .collect();
                Some((a.name.clone(), serde_json::Value::Object(states)))
            })
            .collect();
        value["condat"] = serde_json::Value::Object(per_supervisor);
    }
    value
}

/// The control data in TCT's form: `condat S:` then `state: events` for every state that disables
/// something, four to a line, two spaces apart (`0: 61 71  1: 71 …` when names are TCT's numbers).
fn write_condat(out: &mut impl Write, sup: &Automaton, data: &[Vec<String>]) -> std::io::Result<()> {
    writeln!(out, "condat {}:", sup.name)?;
    let entries: Vec<String> = sup
        .states
        .iter()
        .zip(data)
        .filter(|(_, d)| !d.is_empty())
        .map(|(s, d)| format!("{}: {}", s.name, d.join(" ")))
        .collect();
    if entries.is_empty() {
        writeln!(out, "  (disables nothing)")?;
    }
    for line in entries.chunks(4) {
        writeln!(out, "  {}", line.join("  "))?;
    }
    Ok(())
}

fn write_table(
    out: &mut impl Write,
    rows: &[Row],
    as_written: &[AsWritten],
    nonconflicting: bool,
    merged: &[Vec<String>],
) -> std::io::Result<()> {
    let reduced = rows.iter().any(|r| r.unreduced.is_some());
    let mut lines: Vec<[String; 7]> = vec![[
        "supervisor".into(),
        "specs".into(),
        "local plant".into(),
        "states".into(),
        "transitions".into(),
        if reduced { "before reduction".into() } else { String::new() },
        if reduced { "lower bound".into() } else { String::new() },
    ]];
    for r in rows {
        let a = &r.supervisor.automaton;
        lines.push([
            a.name.clone(),
            r.supervisor.specs.join(","),
            r.supervisor.plants.join(","),
            a.states.len().to_string(),
            a.transitions.len().to_string(),
            r.unreduced.map(|(s, t, _)| format!("{s}/{t}")).unwrap_or_default(),
            r.unreduced.map(|(_, _, bound)| bound.to_string()).unwrap_or_default(),
        ]);
    }
    let (states, transitions) = totals(rows);
    lines.push([
        "total".into(),
        String::new(),
        String::new(),
        states.to_string(),
        transitions.to_string(),
        String::new(),
        String::new(),
    ]);
    let width: Vec<usize> =
        (0..7).map(|c| lines.iter().map(|l| l[c].chars().count()).max().unwrap_or(0)).collect();
    for l in &lines {
        let mut line = String::new();
        for c in 0..7 {
            let pad = width[c] - l[c].chars().count();
            if c >= 3 {
                line.push_str(&" ".repeat(pad));
                line.push_str(&l[c]);
            } else {
                line.push_str(&l[c]);
                line.push_str(&" ".repeat(pad));
            }
            line.push_str("  ");
        }
        writeln!(out, "{}", line.trim_end())?;
    }
    let controllable = as_written.iter().filter(|v| v.controllable() == Some(true)).count();
    writeln!(
        out,
        "controllable as written (each specification against its local plant): {controllable} of {}",
        as_written.len()
    )?;
    for v in as_written {
        match &v.verdict {
            Verdict::Controllable => {}
            Verdict::Refuses(r) => {
                let after = if r.trace.is_empty() {
                    String::from("initially")
                } else {
                    format!("after {}", r.trace.join(" "))
                };
                writeln!(
                    out,
                    "  not {}: {after}, in state {}, it refuses the uncontrollable '{}' its plant generates",
                    v.spec, r.state, r.event
                )?;
            }
            Verdict::Undecided(why) => writeln!(out, "  undecided {}: {why}", v.spec)?,
        }
    }
    for group in merged {
        writeln!(out, "merged: {} (their supervisors conflicted)", group.join(" + "))?;
    }
    writeln!(out, "{}", if nonconflicting { "nonconflicting" } else { "conflicting" })
}
