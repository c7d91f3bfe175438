//! `codegen synth -o DIR --format wmod`: the cell's supervisors go back to Supremica as one module, the
//! plants as PLANT components and the supervisors as SUPERVISOR components; read back by our reader,
//! every automaton has the language it was written with (the plants their files', the supervisors the
//! published ones'), and the module is a project the other commands take.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use codegen::formats::read_path;
use codegen::model::{Automaton, Kind};
use codegen::synth::language::equal;

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

fn one(path: &Path) -> Automaton {
    read_path(path).unwrap_or_else(|e| panic!("{e}")).remove(0)
}

#[test]
fn the_cells_supervisors_go_back_to_supremica_as_one_module() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("synth_wmod");
    let _ = std::fs::remove_dir_all(&dir);
    let out = codegen(&[
        "synth",
        repo("examples/cell/cell.toml").to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
        "--format",
        "wmod",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let listed: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(listed, ["cell.wmod"], "one module, no .xmd");

    let module = dir.join("cell.wmod");
    let automata = read_path(&module).unwrap_or_else(|e| panic!("{e}"));
    let names =
        |kind| automata.iter().filter(|a| a.kind == kind).map(|a| a.name.as_str()).collect::<Vec<_>>();
    assert_eq!(names(Kind::Plant), ["G1", "G2", "G3", "G4"]);
    assert_eq!(names(Kind::Supervisor), ["S1", "S2_6", "S3", "S4", "S5", "S7"]);
    assert!(names(Kind::Spec).is_empty());
    for a in &automata {
        let original = match a.kind {
            Kind::Plant => one(&repo(&format!("examples/cell/plants/{}.xmd", a.name))),
            _ => one(&repo(&format!("examples/cell/published/{}.xmd", a.name))),
        };
        let difference = equal(a, &original).unwrap();
        assert!(difference.is_none(), "{} read back has another language: {difference:?}", a.name);
        for e in &a.events {
            let theirs = original.events.iter().find(|o| o.name == e.name);
            assert_eq!(theirs.map(|o| o.controllable), Some(e.controllable), "{}: event {}", a.name, e.name);
        }
    }
    let (states, transitions) = automata
        .iter()
        .filter(|a| a.kind == Kind::Supervisor)
        .fold((0, 0), |(s, t), a| (s + a.states.len(), t + a.transitions.len()));
    assert_eq!((states, transitions), (233, 697), "the paper's totals");

    // The module is a project: its supervisors are taken as they are.
    let packed = codegen(&["pack", module.to_str().unwrap(), "--json"]);
    assert!(packed.status.success(), "{}", String::from_utf8_lossy(&packed.stderr));
}

#[test]
fn format_goes_with_out() {
    let out = codegen(&["synth", repo("examples/cell/cell.toml").to_str().unwrap(), "--format", "wmod"]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
}
