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
    &["problems", "pack", "monitor", "net", "symbolic", "interpreter"],
    &["feedback", "closed_loop", "maps"],
    &["plc", "emit", "sim"],
    &["project"],
];

/// firmware's library modules, lowest layer first (the applications in `src/bin/` sit on top).
const FIRMWARE: &[&[&str]] = &[
    &["board", "event_set", "fault", "input_queue", "rng", "status", "timer"],
    &["table"],
    &["build", "choice"],
    &["shell"],
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

/// The module path of the file `file` under `src` (`plc/state_based/memory.rs` → `plc state_based
/// memory`; a `mod.rs` is its directory's module).
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap_or(file).with_extension("");
    let mut out: Vec<String> =
        rel.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
    if out.last().is_some_and(|l| l == "mod") {
        out.pop();
    }
    out
}

/// The paths named by `crate::`, `super::` and `self::` in the code of `text` (comments and the test
/// module left out) as absolute module paths, for a file of module `here`. A group `a::{b, c::D}` names
/// `a::b` and `a::c::D`.
fn paths(text: &str, here: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("#[cfg(test)]") {
            break;
        }
        let code = line.split("//").next().unwrap_or("");
        for (at, _) in code.match_indices(['c', 's']) {
            let rest = &code[at..];
            let before = code[..at].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            // `self` is the file's module, `super` its parent.
            let mut base: Vec<String> = if rest.starts_with("crate::") {
                Vec::new()
            } else if rest.starts_with("self::") {
                here.to_vec()
            } else if rest.starts_with("super::") {
                here[..here.len().saturating_sub(1)].to_vec()
            } else {
                continue;
            };
            let mut tail = rest.split_once("::").map_or("", |(_, t)| t);
            while let Some(t) = tail.strip_prefix("super::") {
                base.pop();
                tail = t;
            }
            let head: String =
                tail.chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':').collect();
            let head = head.trim_end_matches(':');
            let mut prefix = base.clone();
            prefix.extend(head.split("::").filter(|s| !s.is_empty()).map(String::from));
            let after = &tail[head.len()..];
            match after.strip_prefix("::{").or_else(|| after.strip_prefix('{')) {
                Some(group) => {
                    for item in group.split('}').next().unwrap_or("").split(',') {
                        let mut p = prefix.clone();
                        p.extend(
                            item.trim().split("::").map(|s| s.trim().to_string()).filter(|s| {
                                !s.is_empty() && s.chars().all(|c| c.is_alphanumeric() || c == '_')
                            }),
                        );
                        out.push(p);
                    }
                }
                None => out.push(prefix),
            }
        }
    }
    out
}

/// Circles among the files of one module of the crate at `src`: per directory, its files and
/// subdirectories (a `mod.rs` aside, which declares them) as nodes, an edge where one names an item
/// of another; every circle found, as `dir: a → b → a`.
fn file_circles(src: &Path) -> Vec<String> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    // (directory module, from node, to node)
    let mut edges: BTreeSet<(Vec<String>, String, String)> = BTreeSet::new();
    let exists = |dir: &[String], node: &str| {
        let d = dir.iter().fold(src.to_path_buf(), |p, s| p.join(s));
        d.join(format!("{node}.rs")).exists() || d.join(node).is_dir()
    };
    for file in &files {
        let here = module_path(src, file);
        if here.first().is_some_and(|m| NOT_MODULES.contains(&m.as_str())) {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap();
        for target in paths(&text, &here) {
            let common = here.iter().zip(&target).take_while(|(a, b)| a == b).count();
            let (Some(from), Some(to)) = (here.get(common), target.get(common)) else { continue };
            let dir = &here[..common];
            if exists(dir, from) && exists(dir, to) {
                edges.insert((dir.to_vec(), from.clone(), to.clone()));
            }
        }
    }
    let mut out = Vec::new();
    let dirs: BTreeSet<&Vec<String>> = edges.iter().map(|(d, ..)| d).collect();
    for dir in dirs {
        let next = |n: &str| -> Vec<&String> {
            edges.iter().filter(|(d, f, _)| d == dir && f == n).map(|(.., t)| t).collect()
        };
        let nodes: BTreeSet<&String> = edges.iter().filter(|(d, ..)| d == dir).map(|(_, f, _)| f).collect();
        for start in nodes {
            // A path back to `start`, depth first.
            let mut stack = vec![(start, vec![start.clone()])];
            let mut seen = BTreeSet::new();
            while let Some((n, path)) = stack.pop() {
                for t in next(n) {
                    if t == start {
                        out.push(format!("{}: {} → {start}", dir.join("::"), path.join(" → ")));
                    } else if seen.insert(t.clone()) {
                        let mut p = path.clone();
                        p.push(t.clone());
                        stack.push((t, p));
                    }
                }
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

#[test]
fn codegen_has_no_circle_of_files() {
    let circles = file_circles(&root().join("codegen/src"));
    assert!(circles.is_empty(), "{}", circles.join("\n"));
}

#[test]
fn the_firmware_has_no_circle_of_files() {
    let circles = file_circles(&root().join("firmware/src"));
    assert!(circles.is_empty(), "{}", circles.join("\n"));
}

#[test]
fn a_circle_of_files_is_found() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("layers-circle");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("m")).unwrap();
    std::fs::write(dir.join("m/mod.rs"), "pub mod a;\npub mod b;\npub struct T;\n").unwrap();
    std::fs::write(dir.join("m/a.rs"), "use super::b::X;\nuse super::T;\n").unwrap();
    std::fs::write(dir.join("m/b.rs"), "use crate::m::{a::Y, T};\n").unwrap();
    assert_eq!(file_circles(&dir), ["m: a → b → a", "m: b → a → b"]);
    std::fs::write(dir.join("m/b.rs"), "use crate::m::T;\n// crate::m::a\n").unwrap();
    assert!(file_circles(&dir).is_empty());
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
