//! `--supervisors` (and `[runtime] supervisors`) end to end on the cell: `emit`, `plc` and `pack` deploy the
//! chosen set, say which in their report and in the emitted provenance, spell a choice that differs from
//! the manifest's out in the recorded command, and that command reproduces the file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).current_dir(root()).args(args).output().expect("run codegen")
}

fn scratch(tag: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli_deploy_{tag}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn emit_deploys_the_chosen_set_with_its_proof_in_the_header() {
    let dir = scratch("emit");
    for (choice, says) in [
        ("reduced", "reduced: 6 supervisors, 24 states"),
        ("monolithic", "monolithic: 1 supervisor, 3420 states / 11808 transitions"),
    ] {
        let out_file = dir.join(format!("{choice}.rs"));
        let out = codegen(&[
            "emit",
            "examples/cell/cell.toml",
            "--supervisors",
            choice,
            "-o",
            out_file.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(stdout.starts_with(&format!("supervisors: {says}")), "{stdout}");
        assert!(stdout.contains("closed loop proven equal to the full set's"), "{stdout}");
        let text = std::fs::read_to_string(&out_file).unwrap();
        assert!(text.contains(&format!("// Supervisors: {says}")), "{text}");
        let command = text.lines().find_map(|l| l.strip_prefix("// Command: codegen ")).unwrap();
        assert!(command.ends_with(&format!("--supervisors {choice}")), "{command}");
        // The recorded command writes the same file again.
        let again = dir.join(format!("{choice}-again.rs"));
        let mut words: Vec<&str> = command.split(' ').collect();
        words.extend(["-o", again.to_str().unwrap()]);
        assert!(codegen(&words).status.success());
        assert_eq!(std::fs::read(&again).unwrap(), text.as_bytes(), "{command}");
    }
}

#[test]
fn plc_programs_carry_the_chosen_set() {
    let dir = scratch("plc");
    let out =
        codegen(&["plc", "examples/cell/cell.toml", "--supervisors", "reduced", "-o", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("supervisors: reduced: 6 supervisors, 24 states"));
    let st = std::fs::read_to_string(dir.join("cell.st")).unwrap();
    assert!(st.contains("Supervisors: reduced: 6 supervisors, 24 states"), "provenance");
    assert!(st.contains("--supervisors reduced"), "command");
}

#[test]
fn a_choice_that_changes_the_closed_loop_is_refused() {
    // The cell's supervisors left unmerged conflict (S2 and S6 block together); given as ready
    // supervisors, their closed loop blocks, and the monolithic supervisor (nonblocking) cannot have it.
    let dir = scratch("refused");
    let out = codegen(&["synth", "examples/cell/cell.toml", "--no-merge", "-o", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "the unmerged cell conflicts");
    let mut args =
        vec!["emit".to_string(), "--name".into(), "cell".into(), "--supervisors".into(), "monolithic".into()];
    for p in ["G1", "G2", "G3", "G4"] {
        args.extend(["--plant".into(), format!("examples/cell/plants/{p}.xmd")]);
    }
    let mut sups: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path().to_string_lossy().into_owned()).collect();
    sups.sort();
    for s in sups {
        args.extend(["--sup".into(), s]);
    }
    args.extend(["-o".into(), dir.join("t.rs").to_string_lossy().into_owned()]);
    let words: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = codegen(&words);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("supervisors = \"monolithic\": the closed loop of S_monolithic against every plant differs from the full set's"), "{err}");
    assert!(!dir.join("t.rs").exists(), "nothing written");
}

#[test]
fn pack_measures_the_chosen_set() {
    let bytes = |choice: &str| {
        let out = codegen(&["pack", "examples/cell/cell.toml", "--supervisors", choice, "--json"]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(json["supervisors"].as_str().unwrap().starts_with(choice), "{json}");
        json["layouts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l["supervisor_bytes"].as_u64().unwrap())
            .collect::<Vec<_>>()
    };
    let (full, reduced) = (bytes("full"), bytes("reduced"));
    // Every layout holds the reduced supervisors in fewer bytes than the full ones.
    assert_eq!(full.len(), reduced.len());
    assert!(full.iter().zip(&reduced).all(|(f, r)| r < f), "full {full:?}, reduced {reduced:?}");
    let text =
        String::from_utf8(codegen(&["pack", "examples/cell/cell.toml", "--supervisors", "reduced"]).stdout)
            .unwrap();
    assert!(text.starts_with("supervisors: reduced: 6 supervisors, 24 states"), "{text}");
}
