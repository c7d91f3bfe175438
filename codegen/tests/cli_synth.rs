//! `codegen synth` end to end: the cell's table, JSON and written supervisors, and the exit statuses.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel).display().to_string()
}

#[test]
fn the_cell_manifest_gives_the_published_table() {
    let out = codegen(&["synth", &repo("examples/cell/cell.toml")]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("S2_6        E2,E6  G3,G4           121          360"), "{text}");
    assert!(text.contains("total                              233          697"), "{text}");
    assert!(text.ends_with("merged: E2 + E6 (their supervisors conflicted)\nnonconflicting\n"), "{text}");
}

#[test]
fn json_lists_supervisors_merges_and_totals_and_out_writes_them() {
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_synth");
    let _ = std::fs::remove_dir_all(&dir);
    let plants: Vec<String> = (1..=4).map(|i| repo(&format!("examples/cell/plants/G{i}.xmd"))).collect();
    let specs: Vec<String> = (1..=7).map(|i| repo(&format!("examples/cell/specs/E{i}.xmd"))).collect();
    let mut args = vec!["synth", "--json", "-o", dir.to_str().unwrap(), "--plant"];
    args.extend(plants.iter().map(String::as_str));
    args.push("--spec");
    args.extend(specs.iter().map(String::as_str));
    let out = codegen(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["nonconflicting"], true);
    assert_eq!(json["merged"], serde_json::json!([["E2", "E6"]]));
    assert_eq!((json["total_states"].as_u64(), json["total_transitions"].as_u64()), (Some(233), Some(697)));
    let s5 = &json["supervisors"][4];
    assert_eq!(s5["name"], "S5");
    assert_eq!(s5["plants"], serde_json::json!(["G2", "G3"]));
    assert_eq!((s5["states"].as_u64(), s5["transitions"].as_u64()), (Some(30), Some(74)));
    let written = codegen::formats::read_path(&dir.join("S2_6.xmd")).unwrap();
    assert_eq!((written[0].states.len(), written[0].transitions.len()), (121, 360));
}

#[test]
fn unmerged_conflict_exits_1_and_bad_input_exits_2() {
    let out = codegen(&["synth", "--no-merge", &repo("examples/cell/cell.toml")]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8(out.stdout).unwrap().contains("\nconflicting\n  S2 and S6 block together"));
    let out = codegen(&["synth", &repo("examples/cell/nope.toml")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8(out.stderr).unwrap().contains("nope.toml"));
    let out = codegen(&["synth", "--monolithic", &repo("examples/cell/cell.toml"), "--state-limit", "1000"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8(out.stderr).unwrap().contains("exceeded the state limit of 1000"));
}

/// libFAUDES keeps controllability with the plant: its specifications are plain generators without
/// `+C+`, and their events take the plant's. libFAUDES `SupCon` on these pairs (copies of its tutorial
/// files in `tests/data/libfaudes/`) gives 7 states and 10 transitions, and 6 and 10.
#[test]
fn libfaudes_specifications_take_controllability_from_the_plant() {
    for (n, want) in [(1, (7, 10)), (3, (6, 10))] {
        let plant = repo(&format!("codegen/tests/data/libfaudes/wplant{n}.gen"));
        let spec = repo(&format!("codegen/tests/data/libfaudes/wspec{n}.gen"));
        let out = codegen(&["synth", "--monolithic", "--json", "--plant", &plant, "--spec", &spec]);
        assert!(out.status.success(), "wplant{n}: {}", String::from_utf8_lossy(&out.stderr));
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let got = (json["total_states"].as_u64().unwrap(), json["total_transitions"].as_u64().unwrap());
        assert_eq!(got, want, "wplant{n} + wspec{n}");
    }
}

/// A set in which no file says whether an event is controllable is refused, naming the event and the
/// automata that leave it unsaid.
#[test]
fn an_event_no_file_says_is_refused_with_exit_2() {
    let spec1 = repo("codegen/tests/data/libfaudes/wspec1.gen");
    let spec3 = repo("codegen/tests/data/libfaudes/wspec3.gen");
    // Both as plants: no file says controllability (the set is refused as it is loaded).
    let out = codegen(&["synth", "--plant", &spec1, &spec3]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no file of the set says whether event"), "{err}");
    assert!(err.contains("wspec1, wspec3"), "{err}");
}

/// A product that outgrows `--memory-limit` stops the run with exit 2 and a message naming the product,
/// its states so far and the limit — never the kernel's out-of-memory killer.
#[test]
fn a_small_memory_limit_stops_a_growing_product_cleanly() {
    use codegen::formats::write_path;
    use codegen::synth::families::generate;

    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_synth_memory");
    std::fs::create_dir_all(&dir).unwrap();
    // Six machines and five buffers: a monolithic closed loop of 50 421 states.
    let inst = generate("factory", 6).unwrap();
    let mut args =
        vec!["synth".to_owned(), "--monolithic".to_owned(), "--memory-limit".to_owned(), "1M".to_owned()];
    for (flag, automata) in [("--plant", &inst.plants), ("--spec", &inst.specs)] {
        args.push(flag.to_owned());
        for a in automata {
            let path = dir.join(format!("{}.xmd", a.name));
            write_path(&path, std::slice::from_ref(a)).unwrap();
            args.push(path.display().to_string());
        }
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = codegen(&args);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    // Stopped before the product's index first doubles (at 512 states), not after.
    assert!(err.contains("S_monolithic: 512 states so far"), "names the product and its size: {err}");
    assert!(err.contains("more would pass the memory limit of 1.0 MiB"), "{err}");
    // Without the limit the same run completes.
    let args: Vec<&str> = args.iter().copied().filter(|a| *a != "--memory-limit" && *a != "1M").collect();
    assert!(codegen(&args).status.success());
}

#[test]
fn synth_says_which_specifications_are_controllable_as_written_the_rtpn_papers_all_but_the_last_two() {
    let net1 = repo("examples/station-rtpn/net1.toml");
    let out = codegen(&["synth", &net1, "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let specs = json["specifications"].as_array().unwrap();
    let verdicts: Vec<(&str, bool)> =
        specs.iter().map(|s| (s["name"].as_str().unwrap(), s["controllable"].as_bool().unwrap())).collect();
    assert_eq!(verdicts.len(), 7);
    assert!(verdicts[..5].iter().all(|&(_, c)| c), "{verdicts:?}");
    assert_eq!(&verdicts[5..], [("piston_out_arm_away", false), ("arm_left_piston_in", false)]);
    // Each refusal names a word, the state it reaches and the uncontrollable event refused there.
    let refusal = &specs[5]["refusal"];
    assert_eq!(refusal["event"], "sf1");
    assert_eq!(refusal["trace"], serde_json::json!(["af1", "sb0"]));
    let text = String::from_utf8(codegen(&["synth", &net1]).stdout).unwrap();
    assert!(
        text.contains("controllable as written (each specification against its local plant): 5 of 7"),
        "{text}"
    );
    assert!(text.contains("  not arm_left_piston_in: after af1 sb0 sf1 ar1 sl0 al1 ar0,"), "{text}");
}

/// The contract: each supervisor of `synth --json` says `spec_controllable`, true or false. On
/// the cell, E2, E3 and E4 are not controllable as written; `S2_6` (E2 merged with E6) answers for both.
#[test]
fn each_supervisor_says_whether_its_specifications_are_controllable_as_written() {
    let out = codegen(&["synth", &repo("examples/cell/cell.toml"), "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let verdicts: Vec<(&str, bool)> = json["supervisors"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| (s["name"].as_str().unwrap(), s["spec_controllable"].as_bool().unwrap()))
        .collect();
    assert_eq!(
        verdicts,
        [("S1", true), ("S2_6", false), ("S3", false), ("S4", false), ("S5", true), ("S7", true)],
        "{json}"
    );
}
