//! Chooses the tables the cell applications include, checks them, and picks the memory layout they link
//! with.
//!
//! Tables: the file named by the `SCT_TABLES` environment variable (absolute, or relative to the
//! workspace root), else the committed `src/generated/cell.rs` (which a codegen test keeps
//! byte-identical to `codegen emit examples/cell/cell.toml`). The applications read the chosen path from
//! `SCT_TABLES_FILE`. Every table image in it is checked here, on the host, with the runtime's own check
//! (`firmware::build::image::check_source`), and their digests handed to the compiler as
//! `SCT_TABLES_CHECKED`: the emitted `CHECKED` does not compile without them, so the runtime's unchecked
//! reads stand on a check that ran on these bytes, and the firmware carries no check code. Memory layout: `boards/lm3s6965/memory.x` for thumbv7m, `boards/pico/memory.x` for
//! the RP2040 (thumbv6m), `boards/nucleo-f401re/memory.x` with the `nucleo` feature,
//! `boards/nrf52840-dk/memory.x` with the `nrf52840` feature. None may sit at
//! the workspace root: the linker looks for `memory.x` in its working directory (where cargo runs rustc)
//! before the search paths, so a root file would be linked into every target's image.

use std::env;
use std::path::{Path, PathBuf};

fn main() {
    let crate_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    // apps/cell → the workspace root.
    let root = crate_dir.ancestors().nth(2).map(Path::to_path_buf).unwrap_or_default();
    println!("cargo:rerun-if-env-changed=SCT_TABLES");
    let tables = match env::var_os("SCT_TABLES") {
        Some(p) => root.join(PathBuf::from(p)),
        None => crate_dir.join("src/generated/cell.rs"),
    };
    println!("cargo:rerun-if-changed={}", tables.display());
    println!("cargo:rustc-env=SCT_TABLES_FILE={}", tables.display());
    let text = match std::fs::read_to_string(&tables) {
        Ok(text) => text,
        Err(e) => fail(&format!("{}: {e}", tables.display())),
    };
    match firmware::build::image::check_source(&text) {
        Ok(proof) => println!("cargo:rustc-env=SCT_TABLES_CHECKED={proof}"),
        Err(e) => fail(&format!("{}: {e}: emit them again with `codegen emit`", tables.display())),
    }

    let target = env::var("TARGET").unwrap_or_default();
    let board = if target.starts_with("thumbv6m") {
        "boards/pico"
    } else if env::var_os("CARGO_FEATURE_NUCLEO").is_some() {
        "boards/nucleo-f401re"
    } else if env::var_os("CARGO_FEATURE_NRF52840").is_some() {
        "boards/nrf52840-dk"
    } else {
        "boards/lm3s6965"
    };
    let memory_dir = crate_dir.join(board);
    if target.starts_with("thumb") {
        println!("cargo:rerun-if-changed={}", memory_dir.join("memory.x").display());
        println!("cargo:rustc-link-search={}", memory_dir.display());
    }
}

/// Stops the build with `message` (exit status 2, as codegen's own errors).
fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2)
}
