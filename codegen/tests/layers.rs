//! The import graph of the two crates, as `ARCHITECTURE.md` draws it: every `crate::` path from one
//! top-level module into another points to a lower layer — never up, never sideways — so the graph has
//! no circle. A new top-level module must be given its layer here and in `ARCHITECTURE.md` (whose layer
//! tables are checked against these).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// codegen's library modules, lowest layer first (the `cli` of the binary sits on top of all of them).
const CODEGEN: &[&[&str]] = &[
    &["model", "provenance"],
    &["formats", "config", "link"],
    &["manifest", "synth", "plant", "target", "scan"],
    &["problems", "pack", "monitor", "net", "symbolic"],
    &["feedback", "closed_loop"],
    &["plc", "emit"],
    &["project"],
];

/// firmware's library modules, lowest layer first (the applications in `src/bin/` sit on top).
const FIRMWARE: &[&[&str]] = &[
    &["board", "event_set", "fault", "input_queue", "rng", "status"],
    &["table"],
    &["build", "choice"],
    &["runtime"],
    &["link", "state"],
    &["event_loop"],
];

/// Directories and files of `src` that are not library modules.
const NOT_MODULES: &[&str] = &["lib", "main", "cli", "bin", "generated"];

/// The top-level module `file` (under `src`) belongs to.
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap_or(file);
    let first =
        rel.components().next().map(|c| c.as_os_str().to_string_lossy().into_owned()).unwrap_or_default();
    first.trim_end_matches(".rs").to_owned()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules named by `crate::` paths in the code of `text` (comments left out); a group
/// `crate::{a::X, b}` names each of its items.
fn crate_paths(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let before = rest[..at].chars().next_back();
            rest = &rest[at + "crate::".len()..];
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue; // `firmware::...::crate` never occurs; an identifier ending in `crate` is no path.
            }
            let items: Vec<&str> = match rest.strip_prefix('{') {
                Some(group) => group.split('}').next().unwrap_or("").split(',').collect(),
                None => vec![rest],
            };
            for item in items {
                let name: String =
                    item.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        }
    }
    out
}

/// Every arrow between top-level modules of the crate at `src`: importer → imported, with a file.
fn arrows(src: &Path) -> BTreeMap<(String, String), PathBuf> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let mut out = BTreeMap::new();
    for file in files {
        let from = module_of(src, &file);
        if NOT_MODULES.contains(&from.as_str()) {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        for to in crate_paths(&text) {
            if to != from {
                out.entry((from.clone(), to)).or_insert_with(|| file.clone());
            }
        }
    }
    out
}

/// The layer of every module; panics on a module listed twice.
fn layers(table: &[&[&str]]) -> BTreeMap<String, usize> {
    let mut out = BTreeMap::new();
    for (layer, modules) in table.iter().enumerate() {
        for m in *modules {
            assert!(out.insert(m.to_string(), layer).is_none(), "{m} listed twice");
        }
    }
    out
}

/// The violations of `table` by the crate at `src`: modules without a layer, and arrows that do not
/// point down.
fn violations(src: &Path, table: &[&[&str]]) -> Vec<String> {
    let layer = layers(table);
    let mut out = Vec::new();
    for entry in std::fs::read_dir(src).unwrap() {
        let path = entry.unwrap().path();
        let m = module_of(src, &path);
        if !NOT_MODULES.contains(&m.as_str()) && !layer.contains_key(&m) {
            out.push(format!("module {m} has no layer"));
        }
    }
    for ((from, to), file) in arrows(src) {
        let (Some(&a), Some(&b)) = (layer.get(&from), layer.get(&to)) else { continue };
        if b >= a {
            let how = if a == b { "sideways" } else { "up" };
            out.push(format!("{from} (layer {a}) → {to} (layer {b}) runs {how}: {}", file.display()));
        }
    }
    out
}

fn root() -> PathBuf {
    let codegen = Path::new(env!("CARGO_MANIFEST_DIR"));
    codegen.parent().unwrap_or(codegen).to_path_buf()
}

#[test]
fn codegen_imports_only_point_down() {
    let v = violations(&root().join("codegen/src"), CODEGEN);
    assert!(v.is_empty(), "{}", v.join("\n"));
}

#[test]
fn firmware_imports_only_point_down() {
    let v = violations(&root().join("firmware/src"), FIRMWARE);
    assert!(v.is_empty(), "{}", v.join("\n"));
}

#[test]
fn the_manifest_only_reads() {
    let arrows = arrows(&root().join("codegen/src"));
    let from_manifest: Vec<&str> =
        arrows.keys().filter(|(from, _)| from == "manifest").map(|(_, to)| to.as_str()).collect();
    assert_eq!(from_manifest, ["config", "formats", "model"]);
}

#[test]
fn paths_are_found_in_code_not_comments() {
    let text = "use crate::model::X;\n// crate::pack\nuse crate::{synth::Y, emit};\nlet a = crate::link::z(); // crate::plant\n";
    assert_eq!(crate_paths(text), BTreeSet::from(["emit", "link", "model", "synth"].map(String::from)));
}

/// The layer table under heading `## {section}` of `ARCHITECTURE.md`, lowest layer first: rows
/// `| N | `a`, `b` (note) |`.
fn documented(section: &str) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let start = text.find(&format!("\n## {section}\n")).unwrap_or_else(|| panic!("no section {section}"));
    let mut rows: Vec<(usize, Vec<String>)> = Vec::new();
    for line in text[start + 1..].lines().skip(1).take_while(|l| !l.starts_with("## ")) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let Some(layer) = cells.get(1).and_then(|c| c.parse().ok()) else { continue };
        let mut modules: Vec<String> = cells[2].split('`').skip(1).step_by(2).map(String::from).collect();
        modules.sort();
        rows.push((layer, modules));
    }
    rows.sort();
    assert!(rows.iter().enumerate().all(|(i, (layer, _))| *layer == i), "{section}: layers 0, 1, 2, …");
    rows.into_iter().map(|(_, m)| m).collect()
}

fn listed(table: &[&[&str]]) -> Vec<Vec<String>> {
    table
        .iter()
        .map(|m| {
            let mut modules: Vec<String> = m.iter().map(|s| s.to_string()).collect();
            modules.sort();
            modules
        })
        .collect()
}

#[test]
fn architecture_md_draws_the_same_layers() {
    assert_eq!(documented("codegen"), listed(CODEGEN));
    assert_eq!(documented("firmware"), listed(FIRMWARE));
}
