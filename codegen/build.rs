//! Embeds the sources `codegen run` builds its firmware from into the binary, so that an installed
//! `codegen` runs a user's project from any directory (`codegen::target::sources` unpacks them).
//!
//! What travels: the runtime crate (`firmware/Cargo.toml`, `src/`), the cell applications (`apps/cell/`:
//! `Cargo.toml`, `build.rs`, `src/`, `boards/` with each board's `memory.x`), codegen itself
//! (`codegen/Cargo.toml`, `build.rs`, `src/`, `benches/`: the library a firmware project's `build.rs`
//! calls, and whose own build embeds these same files again), the cell's manifest and models (`examples/cell/`:
//! the starter project of `codegen new`), the workspace's `Cargo.lock` (the dependencies' versions), `rust-toolchain.toml`,
//! `.cargo/config.toml` (the Cortex-M link flags) and the RP2040 harness (`harness/rp2040/`: its
//! `package.json`, `package-lock.json` and `src/`). The workspace manifest travels rewritten to hold the
//! runtime, the applications and codegen alone, with the same profiles. The generated file `$OUT_DIR/embedded_sources.rs` lists
//! every file with its bytes, in path order, so that the same checkout gives the same binary.
//!
//! It also checks the cell's committed tables (`apps/cell/src/generated/cell.rs`), which codegen's tests
//! compile as the firmware does, as the firmware's build script does (`apps/cell/build.rs`): with the
//! runtime's own check, their digests handed to the compiler as `SCT_TABLES_CHECKED`.

use std::env;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Single files, relative to the workspace root.
const FILES: &[&str] = &[
    "Cargo.lock",
    "rust-toolchain.toml",
    ".cargo/config.toml",
    "firmware/Cargo.toml",
    "apps/cell/Cargo.toml",
    "apps/cell/build.rs",
    "codegen/Cargo.toml",
    "codegen/build.rs",
    "examples/cell/cell.toml",
    "examples/cell/cell-nucleo-f401re.toml",
    "examples/cell/cell-nrf52840-dk.toml",
    "harness/rp2040/package.json",
    "harness/rp2040/package-lock.json",
];

/// Directories embedded whole, relative to the workspace root.
const DIRS: &[&str] = &[
    "firmware/src",
    "apps/cell/src",
    "apps/cell/boards",
    "codegen/src",
    "codegen/benches",
    "examples/cell/plants",
    "examples/cell/specs",
    "harness/rp2040/src",
];

/// The workspace members that travel: the runtime, the applications built on it, and codegen's library
/// (a firmware project's build-dependency: it emits the tables at build time).
const MEMBERS: &[&str] = &["firmware", "apps/cell", "codegen"];

fn main() {
    let crate_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let root = crate_dir.parent().expect("codegen sits in the workspace").to_path_buf();
    let mut files: Vec<String> = FILES.iter().map(|f| (*f).to_owned()).collect();
    for dir in DIRS {
        println!("cargo:rerun-if-changed={}", root.join(dir).display());
        walk(&root, Path::new(dir), &mut files);
    }
    files.sort();

    let mut out = String::from(
        "/// Every embedded file: its path relative to the sources' root and its bytes, in path order.\n\
         pub const FILES: &[(&str, &[u8])] = &[\n",
    );
    let _ = writeln!(out, "    (\"Cargo.toml\", {:?}.as_bytes()),", workspace_manifest(&root));
    for rel in &files {
        let path = root.join(rel);
        println!("cargo:rerun-if-changed={}", path.display());
        assert!(
            path.is_file(),
            "codegen/build.rs: {} is missing: build codegen in its checkout",
            path.display()
        );
        let _ = writeln!(out, "    ({rel:?}, include_bytes!({:?})),", path.display().to_string());
    }
    out.push_str("];\n");
    println!("cargo:rerun-if-changed={}", root.join("Cargo.toml").display());
    let dest = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("embedded_sources.rs");
    std::fs::write(&dest, out).expect("write embedded_sources.rs");

    let cell = root.join("apps/cell/src/generated/cell.rs");
    let text = std::fs::read_to_string(&cell).expect("read the committed cell tables");
    match firmware::build::image::check_source(&text) {
        Ok(proof) => println!("cargo:rustc-env=SCT_TABLES_CHECKED={proof}"),
        Err(e) => panic!("{}: {e}: emit them again (codegen/tests/emit_cell.rs says how)", cell.display()),
    }
}

/// Adds every file under `root/dir` to `files`, as a path relative to `root` with `/` separators.
fn walk(root: &Path, dir: &Path, files: &mut Vec<String>) {
    let entries = std::fs::read_dir(root.join(dir)).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let entry = entry.expect("read a directory entry");
        let rel = dir.join(entry.file_name());
        if entry.file_type().expect("file type").is_dir() {
            walk(root, &rel, files);
        } else {
            files.push(rel.to_string_lossy().replace('\\', "/"));
        }
    }
}

/// The workspace's `Cargo.toml` with [`MEMBERS`] as its only members: the same
/// `[workspace.package]` and profiles, so the firmware builds exactly as `cargo qemu-build` builds it in the
/// checkout.
fn workspace_manifest(root: &Path) -> String {
    let text = std::fs::read_to_string(root.join("Cargo.toml")).expect("read the workspace Cargo.toml");
    let mut manifest: toml::Table = text.parse().expect("the workspace Cargo.toml is TOML");
    let workspace = manifest.get_mut("workspace").and_then(toml::Value::as_table_mut).expect("[workspace]");
    let members = toml::Value::Array(MEMBERS.iter().map(|m| toml::Value::String((*m).into())).collect());
    workspace.insert("members".into(), members.clone());
    workspace.insert("default-members".into(), members);
    if let Some(profiles) = manifest.get_mut("profile").and_then(toml::Value::as_table_mut) {
        if let Some(release) = profiles.get_mut("release").and_then(toml::Value::as_table_mut) {
            // Per-package overrides of the host crates name packages this workspace does not have.
            release.remove("package");
        }
    }
    format!(
        "# Written by codegen (codegen/build.rs): the runtime, the cell applications and codegen, with the workspace's profiles.\n{}",
        toml::to_string(&manifest).expect("serialise the workspace manifest")
    )
}
