//! `codegen synth --engine`: the symbolic engine's supervisors and counts through the command line, the
//! contract of issue 27 as written, and which engine `auto` runs.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use codegen::formats::write_path;
use codegen::model::{Automaton, Kind};

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel).display().to_string()
}

fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// `--plant` and `--spec` arguments for the cell's files.
fn cell_args(extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = ["synth"].iter().chain(extra).map(|s| s.to_string()).collect();
    args.push("--plant".into());
    args.extend((1..=4).map(|i| repo(&format!("examples/cell/plants/G{i}.xmd"))));
    args.push("--spec".into());
    args.extend((1..=7).map(|i| repo(&format!("examples/cell/specs/E{i}.xmd"))));
    args
}

fn run(args: &[String]) -> Output {
    codegen(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

#[test]
fn the_contract_monolithic_symbolic_json_gives_the_explicit_counts() {
    let symbolic = run(&cell_args(&["--monolithic", "--engine", "symbolic", "--json"]));
    assert!(String::from_utf8_lossy(&symbolic.stderr).contains("monolithic synthesis ran symbolic"));
    let (s, e) = (json(&symbolic), json(&run(&cell_args(&["--monolithic", "--json"]))));
    assert_eq!(s["engine"], "symbolic");
    assert_eq!(e["engine"], "explicit");
    let sup = &s["supervisors"][0];
    assert!(sup["states"].as_u64().is_some_and(|n| n > 0), "{s}");
    assert_eq!(sup["states"], e["supervisors"][0]["states"]);
    assert_eq!(sup["transitions"], e["supervisors"][0]["transitions"]);
}

#[test]
fn auto_runs_the_explicit_engine_on_the_small_cell() {
    let out = run(&cell_args(&["--monolithic", "--engine", "auto", "--json"]));
    assert!(String::from_utf8_lossy(&out.stderr).contains("monolithic synthesis ran explicit"));
    assert_eq!(json(&out)["engine"], "explicit");
}

#[test]
fn the_symbolic_conflict_check_merges_as_the_explicit_one() {
    let out = run(&cell_args(&["--engine", "symbolic", "--json"]));
    assert!(String::from_utf8_lossy(&out.stderr).contains("the conflict check ran symbolic"));
    let (s, e) = (json(&out), json(&run(&cell_args(&["--json"]))));
    assert_eq!(s["merged"], serde_json::json!([["E2", "E6"]]));
    assert_eq!(
        (&s["merged"], &s["total_states"], &s["nonconflicting"]),
        (&e["merged"], &e["total_states"], &e["nonconflicting"])
    );
}

/// Writes `n` independent machines (every state marked) and a specification allowing every start.
fn machines(dir: &Path, n: usize) -> (Vec<String>, String) {
    std::fs::create_dir_all(dir).unwrap();
    let plants = (0..n)
        .map(|i| {
            let mut m = Automaton::new(format!("M{i}"), Kind::Plant);
            let (idle, busy) = (m.add_state("idle", true).unwrap(), m.add_state("busy", true).unwrap());
            let (s, f) =
                (m.add_event(format!("s{i}"), true).unwrap(), m.add_event(format!("f{i}"), false).unwrap());
            m.initial = Some(idle);
            m.add_transition(idle, s, busy);
            m.add_transition(busy, f, idle);
            let path = dir.join(format!("M{i}.xmd"));
            write_path(&path, &[m]).unwrap();
            path.display().to_string()
        })
        .collect();
    let mut spec = Automaton::new("Free", Kind::Spec);
    let x = spec.add_state("x", true).unwrap();
    spec.initial = Some(x);
    for i in 0..n {
        let s = spec.add_event(format!("s{i}"), true).unwrap();
        spec.add_transition(x, s, x);
    }
    let path = dir.join("Free.xmd");
    write_path(&path, &[spec]).unwrap();
    (plants, path.display().to_string())
}

#[test]
fn counts_beyond_two_to_the_64_are_decimal_strings_and_out_needs_a_listed_supervisor() {
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_symbolic");
    let (plants, spec) = machines(&dir, 70);
    let mut args: Vec<String> = ["synth", "--monolithic", "--engine", "symbolic", "--json", "--plant"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.extend(plants);
    args.extend(["--spec".to_string(), spec]);
    let j = json(&run(&args));
    let sup = &j["supervisors"][0];
    assert_eq!(sup["states"], "1180591620717411303424"); // 2^70
    assert_eq!(sup["transitions"], "82641413450218791239680"); // 70 · 2^70
    assert_eq!(sup["explicit"], false);
    args.extend(["-o".to_string(), dir.join("out").display().to_string()]);
    let out = run(&args);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("listed as an automaton"), "{out:?}");
}
