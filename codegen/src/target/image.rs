//! Builds the firmware images QEMU boots and the RP2040 harness loads, for a given tables file.
//!
//! The applications (package `cell` in `apps/cell`, binaries `cell-qemu`, `cell-pico`, `cell-pico-link` and `cell-pico-usb`) include the tables named by the
//! `SCT_TABLES` environment variable. Building it is one `cargo build` in the root of the sources this
//! binary carries ([`super::sources`]: unpacked into a cache directory, with the `.cargo/config.toml`
//! that holds the Cortex-M link flags), whatever the current directory. Cargo writes the ELF to one
//! fixed path, so two builds with different tables would overwrite each other: builds are serialised
//! with a lock file and each ELF is copied to a path of its own before the lock is released.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use super::lock::FileLock;
use super::sources::{self, SourcesError};

/// The Cortex-M target of the QEMU board.
pub const TARGET: &str = "thumbv7m-none-eabi";
/// The firmware binary that runs on QEMU.
pub const BINARY: &str = "cell-qemu";
/// The Cortex-M target of the Raspberry Pi Pico.
pub const PICO_TARGET: &str = "thumbv6m-none-eabi";
/// The Pico's firmware binary (what `cargo pico-build` makes).
pub const PICO_BINARY: &str = "cell-pico";
/// The Pico's link build: the same supervisors driven over UART0 (what `cargo pico-link-build` makes).
pub const PICO_LINK_BINARY: &str = "cell-pico-link";
/// The Pico's USB link build: the same supervisors driven over its USB port, a CDC-ACM serial device
/// (what `cargo pico-usb-build` makes).
pub const PICO_USB_BINARY: &str = "cell-pico-usb";

/// Building the firmware failed.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// Cargo or a file operation failed to run.
    #[error("{what}: {source}")]
    Io {
        /// What was being done.
        what: String,
        /// Why it failed.
        source: std::io::Error,
    },
    /// Cargo ran and reported failure.
    #[error("building the firmware failed ({status}):\n{stderr}")]
    Build {
        /// Cargo's exit status.
        status: std::process::ExitStatus,
        /// What it printed.
        stderr: String,
    },
    /// Cargo succeeded but named no executable.
    #[error("cargo built no {0} executable")]
    NoExecutable(String),
    /// `cargo build --release` in a project of the user's own failed (cargo's messages were shown).
    #[error("{}: `cargo build --release` failed ({status}): its errors are above", dir.display())]
    ProjectBuild {
        /// The project's directory.
        dir: PathBuf,
        /// Cargo's exit status.
        status: std::process::ExitStatus,
    },
    /// The firmware's sources could not be unpacked.
    #[error(transparent)]
    Sources(#[from] SourcesError),
}

/// Builds the QEMU firmware with the tables in `tables` (a Rust source file as `codegen emit` writes it)
/// and copies the ELF to `out`.
pub fn build_qemu_image(tables: &Path, out: &Path) -> Result<PathBuf, ImageError> {
    build_image(tables, out, "qemu", TARGET, BINARY)
}

/// Builds the Pico firmware with the tables in `tables` (they must carry a `[board]` pin map) and copies
/// the ELF to `out`.
pub fn build_pico_image(tables: &Path, out: &Path) -> Result<PathBuf, ImageError> {
    build_image(tables, out, "pico", PICO_TARGET, PICO_BINARY)
}

/// Builds the Pico's link build with the tables in `tables` (no pin map needed: it takes UART0's pins
/// only) and copies the ELF to `out`.
pub fn build_pico_link_image(tables: &Path, out: &Path) -> Result<PathBuf, ImageError> {
    build_image(tables, out, "pico", PICO_TARGET, PICO_LINK_BINARY)
}

/// Builds the Pico's USB link build with the tables in `tables` (no pin map needed: it takes the USB
/// port only) and copies the ELF to `out`.
pub fn build_pico_usb_image(tables: &Path, out: &Path) -> Result<PathBuf, ImageError> {
    build_image(tables, out, "pico", PICO_TARGET, PICO_USB_BINARY)
}

/// `cargo build -p cell --release --features FEATURE --target TARGET --bin BINARY` on `tables`.
fn build_image(
    tables: &Path,
    out: &Path,
    feature: &str,
    target: &str,
    binary: &str,
) -> Result<PathBuf, ImageError> {
    let io = |what: String| move |source| ImageError::Io { what, source };
    let tables = std::fs::canonicalize(tables).map_err(io(format!("tables {}", tables.display())))?;
    let root = sources::unpacked()?;
    let target_dir = sources::target_dir()?;
    std::fs::create_dir_all(&target_dir).map_err(io(format!("creating {}", target_dir.display())))?;
    let lock_path = target_dir.join("codegen-firmware-build.lock");
    let _lock = FileLock::exclusive(&lock_path).map_err(io(format!("locking {}", lock_path.display())))?;
    sources::make_current(&root, &target_dir)?;

    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(&root)
        .args([
            "build",
            "-p",
            "cell",
            "--release",
            "--features",
            feature,
            "--target",
            target,
            "--bin",
            binary,
        ])
        .arg("--message-format=json-render-diagnostics")
        .env("SCT_TABLES", &tables)
        .env("CARGO_TARGET_DIR", &target_dir)
        .stdin(Stdio::null())
        .output()
        .map_err(io("running cargo".to_owned()))?;
    if !output.status.success() {
        return Err(ImageError::Build {
            status: output.status,
            stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
        });
    }
    let elf = executable(&output.stdout, binary)?;
    std::fs::copy(&elf, out).map_err(io(format!("copying {} to {}", elf.display(), out.display())))?;
    Ok(out.to_path_buf())
}

/// `cargo build --release` in `dir`, a firmware project of the user's own (`codegen new`), as the user
/// runs it there: its own `.cargo/config.toml` (target, link flags) and target directory. Cargo's
/// progress and messages go to stderr as they come (a first build takes minutes). Returns the ELF of
/// the binary `binary`, where cargo wrote it.
pub fn build_project(dir: &Path, binary: &str) -> Result<PathBuf, ImageError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(dir)
        .args(["build", "--release", "--bin", binary, "--message-format=json-render-diagnostics"])
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()
        .map_err(|source| ImageError::Io { what: "running cargo".to_owned(), source })?;
    if !output.status.success() {
        return Err(ImageError::ProjectBuild { dir: dir.to_path_buf(), status: output.status });
    }
    executable(&output.stdout, binary)
}

/// The executable of `binary` among cargo's JSON messages `stdout`.
fn executable(stdout: &[u8], binary: &str) -> Result<PathBuf, ImageError> {
    String::from_utf8_lossy(stdout)
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|m| m["reason"] == "compiler-artifact" && m["target"]["name"] == binary)
        .find_map(|m| m["executable"].as_str().map(PathBuf::from))
        .ok_or_else(|| ImageError::NoExecutable(binary.to_owned()))
}
