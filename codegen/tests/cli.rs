//! The `codegen` binary: exit statuses, `inspect` output, `convert` and `dot`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel).display().to_string()
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn inspect_json_reports_the_published_supervisor_sizes() {
    let files: Vec<String> = ["S1", "S2_6", "S3", "S4", "S5", "S7"]
        .iter()
        .map(|s| repo(&format!("examples/cell/published/{s}.xmd")))
        .collect();
    let args: Vec<&str> = ["inspect", "--json"].into_iter().chain(files.iter().map(String::as_str)).collect();
    let out = codegen(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let sizes: Vec<(String, u64, u64)> = json
        .as_array()
        .unwrap()
        .iter()
        .map(|o| {
            (
                o["name"].as_str().unwrap().to_owned(),
                o["states"].as_u64().unwrap(),
                o["transitions"].as_u64().unwrap(),
            )
        })
        .collect();
    let expected =
        [("S1", 4, 10), ("S2_6", 121, 360), ("S3", 33, 112), ("S4", 33, 112), ("S5", 30, 74), ("S7", 12, 29)];
    assert_eq!(sizes, expected.map(|(n, s, t)| (n.to_owned(), s, t)));
    let first = &json[0];
    for key in ["file", "kind", "events", "controllable", "marked", "initial"] {
        assert!(first.get(key).is_some(), "missing {key}");
    }
}

#[test]
fn inspect_line_names_file_and_sizes() {
    let g1 = repo("examples/cell/plants/G1.xmd");
    let out = codegen(&["inspect", &g1]);
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        format!(
            "{g1}: G1 (unknown): 2 states, 2 transitions, 2 events (2 controllable), 1 marked, initial '1'\n  \
             controllable: e1_lig, e1_des\n  uncontrollable: (none)\n"
        )
    );
}

#[test]
fn bad_input_exits_2_with_the_file_named_and_good_files_still_shown() {
    let bad = scratch("broken.xmd");
    std::fs::write(&bad, "<model type=\"FSA\"><data>").unwrap();
    let g1 = repo("examples/cell/plants/G1.xmd");
    let out = codegen(&["inspect", &g1, bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stdout).contains("G1 (unknown)"));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.starts_with(&format!("error: {}: line 1: malformed XML", bad.display())), "{err}");
}

#[test]
fn missing_file_and_unknown_output_format_exit_2() {
    assert_eq!(codegen(&["inspect", "no/such/file.xmd"]).status.code(), Some(2));
    let g1 = repo("examples/cell/plants/G1.xmd");
    let out = codegen(&["convert", &g1, scratch("G1.png").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown output format"));
}

#[test]
fn convert_then_inspect_gives_the_same_sizes() {
    let s1 = repo("examples/cell/published/S1.xmd");
    let copy = scratch("S1.xmd");
    assert!(codegen(&["convert", &s1, copy.to_str().unwrap()]).status.success());
    let line = |f: &str| {
        let out = String::from_utf8(codegen(&["inspect", f]).stdout).unwrap();
        out.split_once(": ").unwrap().1.to_owned()
    };
    assert_eq!(line(&s1), line(copy.to_str().unwrap()));
}

#[test]
fn dot_writes_to_a_file_or_stdout() {
    let g1 = repo("examples/cell/plants/G1.xmd");
    let out = codegen(&["dot", &g1]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("digraph automata {") && text.contains("shape=doublecircle"), "{text}");
    let file = scratch("G1.dot");
    assert!(codegen(&["dot", &g1, "-o", file.to_str().unwrap()]).status.success());
    assert_eq!(std::fs::read_to_string(file).unwrap(), text);
}

#[test]
fn inspect_reads_the_tct_seed_with_its_published_figures() {
    let out = codegen(&["inspect", "--json", &repo("codegen/tests/data/TEST.ADS")]);
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let o = &json[0];
    let figures = ["states", "transitions", "events", "controllable"].map(|k| o[k].as_u64().unwrap());
    assert_eq!(figures, [5, 13, 6, 3]);
    assert_eq!((o["kind"].as_str(), o["initial"].as_str()), (Some("unknown"), Some("0")));
    // The alphabet, each event with its controllability: TCT's odd labels are controllable.
    let alphabet: Vec<(&str, bool)> = o["alphabet"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| (e["name"].as_str().unwrap(), e["controllable"].as_bool().unwrap()))
        .collect();
    assert_eq!(alphabet.len(), 6);
    assert!(
        alphabet.iter().all(|(name, c)| name.parse::<u32>().unwrap() % 2 == u32::from(*c)),
        "{alphabet:?}"
    );
}

#[test]
fn inspect_names_the_component_kinds_of_a_module() {
    let out =
        codegen(&["inspect", "--json", &repo("codegen/tests/data/kyllercg_digit_sequence_detector.wmod")]);
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((json[0]["name"].as_str(), json[0]["kind"].as_str()), (Some("Automato"), Some("plant")));
}
