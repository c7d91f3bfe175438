//! The emitted tables of the manufacturing cell: the committed `apps/cell/src/generated/cell.rs` is what
//! `codegen emit examples/cell/cell.toml` (local modular synthesis, the manifest's `[runtime]` and
//! `[board]`) writes today, byte for byte, and emitting is deterministic.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The command that writes the committed file (paths relative to the repository root).
fn cell_args() -> Vec<String> {
    vec!["emit".to_string(), "examples/cell/cell.toml".into()]
}

fn emit_to(out: &Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_codegen"))
        .current_dir(root())
        .args(cell_args())
        .arg("-o")
        .arg(out)
        .status()
        .unwrap();
    assert!(status.success());
}

#[test]
fn committed_cell_tables_are_fresh_and_emission_is_deterministic() {
    let dir = std::env::temp_dir().join(format!("emit-cell-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (a, b) = (dir.join("a.rs"), dir.join("b.rs"));
    emit_to(&a);
    emit_to(&b);
    let (a, b) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    assert_eq!(a, b, "two runs differ");
    let committed = std::fs::read(root().join("apps/cell/src/generated/cell.rs")).unwrap();
    assert!(
        a == committed,
        "apps/cell/src/generated/cell.rs is stale: regenerate it with `cargo run -p codegen -- {} -o apps/cell/src/generated/cell.rs`",
        cell_args().join(" ")
    );
    // The command the header records reproduces the file.
    let text = String::from_utf8(a).unwrap();
    let recorded = text.lines().find_map(|l| l.strip_prefix("// Command: codegen ")).unwrap();
    let c = dir.join("c.rs");
    let status = Command::new(env!("CARGO_BIN_EXE_codegen"))
        .current_dir(root())
        .args(recorded.split(' '))
        .arg("-o")
        .arg(&c)
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(std::fs::read_to_string(c).unwrap(), text);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_controllable_event_no_plant_generates_is_refused() {
    let dir = std::env::temp_dir().join(format!("emit-unowned-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The supervisor S1 alone as "plant" G2: S1's controllable events of G1 belong to no plant.
    let out = Command::new(env!("CARGO_BIN_EXE_codegen"))
        .current_dir(root())
        .args(["emit", "--plant", "examples/cell/plants/G2.xmd", "--sup", "examples/cell/published/S1.xmd"])
        .arg("-o")
        .arg(dir.join("x.rs"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    // Refused where the files meet, every such event named with its file and line.
    assert!(stderr.contains("S1.xmd:59: event 'e1_lig' of supervisor 'S1' is in no plant"), "{stderr}");
    assert!(!dir.join("x.rs").exists());
    std::fs::remove_dir_all(dir).ok();
}

/// The committed tables, compiled as the firmware's applications include them.
#[allow(dead_code)]
mod cell {
    include!("../../apps/cell/src/generated/cell.rs");
}

#[test]
fn committed_cell_tables_compile_and_pass_the_check() {
    use firmware::rng::SeedEntropy;
    use firmware::runtime::{Decision, Runtime};
    assert_eq!(cell::SET.check(cell::AUTOMATA), Ok(()));
    assert_eq!(cell::EVENT_NAMES.len(), cell::SET.events());
    assert_eq!(cell::AUTOMATON_NAMES.len(), cell::AUTOMATA);
    assert_eq!(cell::SET.sites.len(), cell::SITES);
    let mut rt =
        Runtime::new(cell::CHECKED, cell::CONFIG, cell::Policy::default(), SeedEntropy::new(cell::SEED));
    // In the initial state only the conveyor can start.
    assert_eq!(rt.decide(|| false), Decision::Fired(cell::event::E1_LIG));
}

/// The cell's model files without a manifest (issue 22: one project loader for every command): plants
/// without a role and `--spec` give the committed tables' supervisors (6 local modular, 1 028 bytes); a manifest with a run-time
/// option exits 2 (its `[runtime]` holds them).
#[test]
fn model_files_with_specifications_emit_the_synthesised_supervisors() {
    let out = std::env::temp_dir().join(format!("emit-files-{}.rs", std::process::id()));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_codegen"));
    cmd.current_dir(root()).args(["emit", "--name", "cell"]);
    cmd.args((1..=4).map(|k| format!("examples/cell/plants/G{k}.xmd")));
    for k in 1..=7 {
        cmd.args(["--spec".to_owned(), format!("examples/cell/specs/E{k}.xmd")]);
    }
    let run = cmd.arg("-o").arg(&out).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    let _ = std::fs::remove_file(&out);
    assert!(
        text.contains("Set 'cell': 4 plants, 6 supervisors, 23 events; layout ranked, 1028 bytes"),
        "{}",
        &text[..text.len().min(2000)]
    );
    assert!(text.contains("--spec examples/cell/specs/E7.xmd"), "the command names the roles");
    let refused = Command::new(env!("CARGO_BIN_EXE_codegen"))
        .current_dir(root())
        .args(["emit", "examples/cell/cell.toml", "--policy", "first", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("[runtime]"));
}
