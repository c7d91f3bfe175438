//! A Supremica module as a whole project: its components say which are plants, specifications and
//! supervisors, and every subcommand that takes a manifest takes the module. The module here is the
//! cell's plants and specifications written by our own `.wmod` writer.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use codegen::formats::{read_path, write_path};
use codegen::model::Kind;

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// `cell.wmod` in a scratch folder: plants G1–G4 as PLANT, specifications E1–E7 as SPEC.
fn cell_module(tag: &str) -> (PathBuf, String) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_module").join(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let mut automata = Vec::new();
    for (sub, names, kind) in [("plants", 1..=4, Kind::Plant), ("specs", 1..=7, Kind::Spec)] {
        for i in names {
            let letter = if kind == Kind::Plant { "G" } else { "E" };
            let mut a = read_path(&repo(&format!("examples/cell/{sub}/{letter}{i}.xmd"))).unwrap().remove(0);
            a.kind = kind;
            automata.push(a);
        }
    }
    let path = dir.join("cell.wmod");
    write_path(&path, &automata).unwrap();
    let s = path.display().to_string();
    (path, s)
}

fn totals(out: &Output) -> (u64, u64) {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    (json["total_states"].as_u64().unwrap(), json["total_transitions"].as_u64().unwrap())
}

#[test]
fn a_module_is_a_project_for_synth_check_pack_and_emit() {
    let (_, module) = cell_module("project");
    // The cell's local modular supervisors, as from its manifest.
    assert_eq!(totals(&codegen(&["synth", "--json", &module])), (233, 697));
    let manifest = repo("examples/cell/cell.toml").display().to_string();
    assert_eq!(totals(&codegen(&["synth", "--json", &manifest])), (233, 697));
    // The checks on the closed loop: the same findings as the manifest's.
    // Choice findings are reported but do not fail the check by default (`[check] fail_on`).
    let check = codegen(&["check", "--json", &module]);
    assert_eq!(check.status.code(), Some(0), "{}", String::from_utf8_lossy(&check.stderr));
    let json: serde_json::Value = serde_json::from_slice(&check.stdout).unwrap();
    let findings = json["scopes"][0]["findings"].as_array().unwrap();
    assert_eq!(findings.iter().filter(|f| f["problem"] == "choice").count(), 217);
    assert!(codegen(&["pack", &module]).status.success());
    let tables = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_module").join("project").join("tables.rs");
    let emit = codegen(&["emit", &module, "-o", &tables.display().to_string()]);
    assert!(emit.status.success(), "{}", String::from_utf8_lossy(&emit.stderr));
    assert!(
        std::fs::read_to_string(&tables).unwrap().contains("cell.wmod"),
        "the module is in the provenance"
    );
}

#[test]
fn a_module_in_a_role_contributes_only_the_components_of_that_kind() {
    let (_, module) = cell_module("roles");
    let out = codegen(&["synth", "--json", "--plant", &module, "--spec", &module]);
    assert_eq!(totals(&out), (233, 697));
    let err = String::from_utf8_lossy(&out.stderr);
    // Under --plant the 7 specifications are left out, under --spec the 4 plants; each is said.
    assert_eq!(err.matches("left out").count(), 11, "{err}");
    assert!(err.contains("E1 (Spec) left out") && err.contains("G1 (Plant) left out"), "{err}");
    // emit takes plants and supervisors one by one the same way.
    let tables = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_module").join("roles").join("tables.rs");
    let emit = codegen(&["emit", "--plant", &module, "-o", &tables.display().to_string()]);
    assert!(emit.status.success(), "{}", String::from_utf8_lossy(&emit.stderr));
    assert_eq!(String::from_utf8_lossy(&emit.stderr).matches("(Spec) left out").count(), 7);
}

/// A model file is part of a project like a module: alone, a plant without specifications gives
/// nothing to synthesise, and says so (exit 2).
#[test]
fn a_lone_plant_file_has_nothing_to_synthesise() {
    let model = repo("examples/cell/plants/G1.xmd").display().to_string();
    let out = codegen(&["synth", &model]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no specification to synthesise a supervisor for"), "{err}");
}
