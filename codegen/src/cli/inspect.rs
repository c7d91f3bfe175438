//! `codegen inspect`: what each file holds, one line (or JSON object) per automaton.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use codegen::formats::read_path;
use codegen::model::Automaton;

use super::Error;

/// Show the size, role and alphabet of every automaton in the given files.
///
/// Prints per automaton a line with file, name, kind (plant, spec, supervisor or unknown), states,
/// transitions, events, controllable events, marked states and the initial state, then its alphabet: a
/// line of its controllable events and one of its uncontrollable events, each in the file's order — or,
/// when its file says nothing of controllability (a libFAUDES generator without +C+), one line of its
/// events with controllability unsaid. A file that cannot be read is reported on stderr; the others are
/// still shown, and the exit status is 2.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model files (.xmd, .ads, .gen, .wmod; the format is taken from the extension, else the content).
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Print a JSON array of objects with the fields file, name, kind, states, transitions, events,
    /// controllable (null when unsaid), marked, initial (the initial state's name, or null) and alphabet
    /// (an array of objects name, controllable — null when the file says nothing of it — in the file's
    /// order).
    #[arg(long)]
    json: bool,
}

/// Runs `inspect`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let mut rows = Vec::new();
    let mut failed = false;
    for file in &args.files {
        match read_path(file) {
            Ok(automata) => rows.extend(automata.into_iter().map(|a| (file.display().to_string(), a))),
            Err(e) => {
                eprintln!("error: {e}");
                failed = true;
            }
        }
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        let json: Vec<_> = rows.iter().map(|(file, a)| to_json(file, a)).collect();
        serde_json::to_writer_pretty(&mut out, &json)?;
        writeln!(out)?;
    } else {
        for (file, a) in &rows {
            writeln!(out, "{}", line(file, a))?;
            if a.controllability_unsaid {
                let names: Vec<&str> = a.events.iter().map(|e| e.name.as_str()).collect();
                let names = if names.is_empty() { "(none)".to_owned() } else { names.join(", ") };
                writeln!(out, "  controllability unsaid (taken from the plants it is used with): {names}")?;
                continue;
            }
            for (word, controllable) in [("controllable", true), ("uncontrollable", false)] {
                let names: Vec<&str> = a
                    .events
                    .iter()
                    .filter(|e| e.controllable == controllable)
                    .map(|e| e.name.as_str())
                    .collect();
                let names = if names.is_empty() { "(none)".to_owned() } else { names.join(", ") };
                writeln!(out, "  {word}: {names}")?;
            }
        }
    }
    out.flush()?;
    Ok(if failed { ExitCode::from(2) } else { ExitCode::SUCCESS })
}

fn initial_name(a: &Automaton) -> Option<&str> {
    a.initial.map(|s| a.states[s.index()].name.as_str())
}

fn line(file: &str, a: &Automaton) -> String {
    let controllable = match a.controllability_unsaid {
        true => "controllability unsaid".to_owned(),
        false => format!("{} controllable", a.controllable_count()),
    };
    format!(
        "{file}: {} ({}): {} states, {} transitions, {} events ({controllable}), {} marked, initial {}",
        a.name,
        a.kind.as_str(),
        a.states.len(),
        a.transitions.len(),
        a.events.len(),
        a.marked_count(),
        initial_name(a).map_or_else(|| "none".to_owned(), |s| format!("'{s}'")),
    )
}

fn to_json(file: &str, a: &Automaton) -> serde_json::Value {
    serde_json::json!({
        "file": file,
        "name": a.name,
        "kind": a.kind.as_str(),
        "states": a.states.len(),
        "transitions": a.transitions.len(),
        "events": a.events.len(),
        "controllable": (!a.controllability_unsaid).then(|| a.controllable_count()),
        "marked": a.marked_count(),
        "initial": initial_name(a),
        "alphabet": a.events.iter().map(|e| serde_json::json!({
            "name": e.name,
            "controllable": (!a.controllability_unsaid).then_some(e.controllable),
        })).collect::<Vec<_>>(),
    })
}
