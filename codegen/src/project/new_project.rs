//! `codegen new`: a firmware project of the user's own for one board — `Cargo.toml`, `memory.x`,
//! `.cargo/config.toml` (the target, a probe-rs runner with the chip), `build.rs` (the tables emitted at
//! build time, [`super::build_script`]), `src/main.rs`, the manifest with its model files, and a
//! README with the flash command.
//!
//! Nothing is written twice: every piece comes from the sources this binary carries ([`crate::target::sources`],
//! unpacked into the cache). The application is the cell's for the board (`apps/cell/src/bin/`), which
//! reads its tables from `SCT_TABLES_FILE` as the build script sets it, with the modules it shares with
//! the other boards' applications beside it (`src/board_app.rs`, and `src/systick_board.rs` for the
//! boards that tick on SysTick); the dependencies are those the
//! board's feature of `apps/cell/Cargo.toml` enables, at the same versions (the carried `Cargo.lock`
//! comes along); the link flags and runner are the carried `.cargo/config.toml`'s for the board's
//! target; the release profile is the workspace's. The runtime (`firmware`) and `codegen` are path
//! dependencies on the unpacked sources, so the project builds wherever it is and whatever the checkout
//! the binary came from — and a newer `codegen` unpacks beside, never over, the sources a project uses.

use std::path::{Component, Path, PathBuf};

use crate::pack::fit::Core;
use crate::target::flash::Flash;
use crate::target::sources::{self, SourcesError};

use super::{Project, ProjectError};

pub use crate::maps::Board;

/// What a board's project is made of, each named by where it lies in the carried sources.
struct Parts {
    /// The feature of `apps/cell/Cargo.toml` that lists the board's dependencies.
    feature: &'static str,
    /// The Rust target.
    target: &'static str,
    /// probe-rs's name of the chip.
    chip: &'static str,
    /// The application (becomes `src/main.rs`).
    main: &'static str,
    /// The memory layout (becomes `memory.x`).
    memory: &'static str,
    /// The modules the application shares with the other boards' (each becomes `src/NAME.rs`).
    shared: &'static [&'static str],
}

impl Board {
    fn parts(self) -> Parts {
        match self {
            Board::Pico => Parts {
                feature: "pico",
                target: "thumbv6m-none-eabi",
                chip: "RP2040",
                main: "apps/cell/src/bin/cell_pico.rs",
                memory: "apps/cell/boards/pico/memory.x",
                shared: &[BOARD_APP],
            },
            Board::NucleoF401re => Parts {
                feature: "nucleo",
                target: "thumbv7em-none-eabihf",
                chip: "STM32F401RETx",
                main: "apps/cell/src/bin/cell_nucleo.rs",
                memory: "apps/cell/boards/nucleo-f401re/memory.x",
                shared: &[BOARD_APP, SYSTICK_BOARD],
            },
            Board::Nrf52840Dk => Parts {
                feature: "nrf52840",
                target: "thumbv7em-none-eabihf",
                chip: "nRF52840_xxAA",
                main: "apps/cell/src/bin/cell_nrf52840.rs",
                memory: "apps/cell/boards/nrf52840-dk/memory.x",
                shared: &[BOARD_APP, SYSTICK_BOARD],
            },
        }
    }

    /// The board's Rust target (where cargo puts the ELF: `target/TARGET/release/NAME`).
    pub fn target(self) -> &'static str {
        self.parts().target
    }

    /// probe-rs's name of the board's chip (the runner's `--chip`).
    pub fn chip(self) -> &'static str {
        self.parts().chip
    }

    /// The core whose tables the board's application runs: the Pico's Cortex-M0+ its own (`m0plus`),
    /// the Cortex-M4 boards the Cortex-M3's.
    pub fn core(self) -> Core {
        match self {
            Board::Pico => Core::CortexM0Plus,
            Board::NucleoF401re | Board::Nrf52840Dk => Core::CortexM3,
        }
    }

    /// The board's flash, as the `memory.x` its project links with says.
    pub fn flash(self) -> Flash {
        let board = match self {
            Board::Pico => "RP2040 (Pico)",
            Board::NucleoF401re => "STM32F401RE (Nucleo-F401RE)",
            Board::Nrf52840Dk => "nRF52840 (nRF52840 DK)",
        };
        Flash::board(board, self.parts().memory)
    }
}

/// What every board application shares (`apps/cell/src/bin/board_app.rs`): written beside `main.rs`,
/// which declares it as `mod board_app;`.
const BOARD_APP: &str = "apps/cell/src/bin/board_app.rs";

/// What the boards that tick on SysTick share (the Nucleo's and the nRF52840's applications).
const SYSTICK_BOARD: &str = "apps/cell/src/bin/systick_board.rs";

impl Board {
    /// The manifest of a project made without `--manifest`: the manufacturing cell with a pin map of
    /// this board's (`examples/cell/cell.toml` is the Pico's, `cell-nucleo-f401re.toml`,
    /// `cell-nrf52840-dk.toml` the others').
    pub fn starter(self) -> &'static str {
        match self {
            Board::Pico => "examples/cell/cell.toml",
            Board::NucleoF401re => "examples/cell/cell-nucleo-f401re.toml",
            Board::Nrf52840Dk => "examples/cell/cell-nrf52840-dk.toml",
        }
    }
}

/// Where the project's manifest and model files go, relative to its root.
pub const MODEL_DIR: &str = "model";

/// A project could not be written.
#[derive(Debug, thiserror::Error)]
pub enum NewError {
    /// The directory exists and is not empty.
    #[error("{}: exists and is not empty: name a new directory", .0.display())]
    NotEmpty(PathBuf),
    /// The manifest or a model file could not be read.
    #[error(transparent)]
    Project(Box<ProjectError>),
    /// A model file is not inside the manifest's directory, so it cannot be copied beside it.
    #[error("{manifest}: names {file}, outside the manifest's directory: put the model files beside or below the manifest")]
    Outside {
        /// The manifest.
        manifest: String,
        /// The file.
        file: String,
    },
    /// The carried sources could not be unpacked.
    #[error(transparent)]
    Sources(#[from] SourcesError),
    /// A carried file is not what `codegen new` expects (a bug of this binary, not of the input).
    #[error("carried {file}: {why}")]
    Carried {
        /// The file.
        file: &'static str,
        /// What is wrong.
        why: String,
    },
    /// A file operation failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl From<ProjectError> for NewError {
    fn from(e: ProjectError) -> Self {
        NewError::Project(Box::new(e))
    }
}

/// What `codegen new` wrote.
#[derive(Debug)]
pub struct NewProject {
    /// The package's (and the binary's) name.
    pub name: String,
    /// The manifest, relative to the project's root.
    pub manifest: String,
}

/// Writes a project for `board` into `dir` (which must not exist or be empty), from the manifest
/// `manifest` with its model files, or from the starter one. A manifest the board's firmware cannot run
/// — state-based, or tables its layout cannot hold or its flash cannot fit — is refused at once, with
/// nothing written.
pub fn new_project(dir: &Path, board: Board, manifest: Option<&Path>) -> Result<NewProject, NewError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| NewError::Io { path, source }
    };
    if std::fs::read_dir(dir).map(|mut d| d.next().is_some()).unwrap_or(false) {
        return Err(NewError::NotEmpty(dir.to_path_buf()));
    }
    let root = sources::unpacked()?;
    let manifest = manifest.map_or_else(|| root.join(board.starter()), Path::to_path_buf);
    let project = Project::load_for(&manifest, board)?;
    project.for_board()?;
    project.fit(board.core(), &board.flash())?;
    let parts = board.parts();
    let name = package_name(dir);

    let write = |rel: &str, text: &str| {
        let path = dir.join(rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(io(parent))?;
        }
        std::fs::write(&path, text).map_err(io(&path))
    };
    let carried = |rel: &'static str| {
        std::fs::read_to_string(root.join(rel))
            .map_err(|e| NewError::Carried { file: rel, why: e.to_string() })
    };

    // The manifest and its model files, at the same places relative to each other.
    let base = manifest.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut manifest_rel = String::new();
    for input in project.input_paths() {
        let rel = Path::new(&input).strip_prefix(&base).ok().filter(|r| is_plain(r)).ok_or_else(|| {
            NewError::Outside { manifest: manifest.display().to_string(), file: input.clone() }
        })?;
        let to = Path::new(MODEL_DIR).join(rel);
        let text = std::fs::read(&input).map_err(io(Path::new(&input)))?;
        if let Some(parent) = dir.join(&to).parent() {
            std::fs::create_dir_all(parent).map_err(io(parent))?;
        }
        std::fs::write(dir.join(&to), text).map_err(io(&dir.join(&to)))?;
        if manifest_rel.is_empty() {
            manifest_rel = to.to_string_lossy().replace('\\', "/");
        }
    }

    write("Cargo.toml", &cargo_toml(&root, &name, parts.feature, &carried)?)?;
    write("Cargo.lock", &carried("Cargo.lock")?)?;
    write("rust-toolchain.toml", &carried("rust-toolchain.toml")?)?;
    write(".cargo/config.toml", &cargo_config(&parts, &carried)?)?;
    write("memory.x", &carried(parts.memory)?)?;
    write("src/main.rs", &carried(parts.main)?)?;
    for &module in parts.shared {
        let name =
            Path::new(module).file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        write(&format!("src/{name}"), &carried(module)?)?;
    }
    write("build.rs", &build_rs(&manifest_rel))?;
    write("README.md", &readme(&name, &manifest_rel, board))?;
    write(".gitignore", "/target\n")?;
    Ok(NewProject { name, manifest: manifest_rel })
}

/// A relative path with no `..`, root or prefix in it.
fn is_plain(p: &Path) -> bool {
    p.components().all(|c| matches!(c, Component::Normal(_)))
}

/// The package name: the directory's name in lower case, every character cargo does not take as `-`;
/// `app` when nothing is left, and never the name of a dependency.
fn package_name(dir: &Path) -> String {
    let raw = dir.file_name().map(|n| n.to_string_lossy().to_lowercase()).unwrap_or_default();
    let mut name: String =
        raw.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '-' }).collect();
    name = name.trim_matches('-').to_owned();
    if name.is_empty() {
        return "app".to_owned();
    }
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        name.insert_str(0, "app-");
    }
    if matches!(name.as_str(), "firmware" | "codegen") {
        name.push_str("-app");
    }
    name
}

/// The project's `Cargo.toml`: the board feature's dependencies of the cell applications, the runtime
/// and codegen by path on the unpacked sources, the workspace's release profile, a `[workspace]` of its
/// own.
fn cargo_toml(
    root: &Path,
    name: &str,
    feature: &str,
    carried: &dyn Fn(&'static str) -> Result<String, NewError>,
) -> Result<String, NewError> {
    let bad = |file: &'static str| move |why: String| NewError::Carried { file, why };
    let app: toml::Table = carried("apps/cell/Cargo.toml")?
        .parse()
        .map_err(|e: toml::de::Error| bad("apps/cell/Cargo.toml")(e.to_string()))?;
    let workspace: toml::Table =
        carried("Cargo.toml")?.parse().map_err(|e: toml::de::Error| bad("Cargo.toml")(e.to_string()))?;
    let deps = app.get("dependencies").and_then(toml::Value::as_table).cloned().unwrap_or_default();
    let wanted = app
        .get("features")
        .and_then(|f| f.get(feature))
        .and_then(toml::Value::as_array)
        .ok_or_else(|| bad("apps/cell/Cargo.toml")(format!("no feature {feature}")))?;

    let mut out = toml::Table::new();
    // Non-optional dependencies always; optional ones as the feature enables them.
    for (dep, spec) in &deps {
        if spec.get("optional").and_then(toml::Value::as_bool) != Some(true) {
            out.insert(dep.clone(), spec.clone());
        }
    }
    for item in wanted.iter().filter_map(toml::Value::as_str) {
        let (dep, dep_feature) = match item.strip_prefix("dep:") {
            Some(dep) => (dep, None),
            None => match item.split_once('/') {
                Some((dep, f)) => (dep, Some(f)),
                None => continue,
            },
        };
        let Some(spec) = deps.get(dep) else { continue };
        let entry = out.entry(dep.to_owned()).or_insert_with(|| spec.clone());
        let table = match entry {
            toml::Value::Table(t) => t,
            other => {
                let version = other.clone();
                *other = toml::Value::Table(toml::Table::from_iter([("version".to_owned(), version)]));
                other.as_table_mut().expect("just made a table")
            }
        };
        table.remove("optional");
        if let Some(f) = dep_feature {
            let features = table.entry("features").or_insert_with(|| toml::Value::Array(Vec::new()));
            if let Some(list) = features.as_array_mut() {
                if !list.iter().any(|v| v.as_str() == Some(f)) {
                    list.push(toml::Value::String(f.to_owned()));
                }
            }
        }
    }
    let path_dep = |rel: &str| {
        toml::Value::Table(toml::Table::from_iter([(
            "path".to_owned(),
            toml::Value::String(root.join(rel).to_string_lossy().into_owned()),
        )]))
    };
    let mut firmware = path_dep("firmware");
    if let Some(old) = out.get("firmware").and_then(|f| f.get("features")) {
        firmware.as_table_mut().expect("a table").insert("features".into(), old.clone());
    }
    out.insert("firmware".into(), firmware);

    let package = toml::Table::from_iter([
        ("name".to_owned(), toml::Value::String(name.to_owned())),
        ("version".to_owned(), toml::Value::String("0.1.0".into())),
        ("edition".to_owned(), toml::Value::String("2021".into())),
        ("publish".to_owned(), toml::Value::Boolean(false)),
    ]);
    let bin = toml::Table::from_iter([
        ("name".to_owned(), toml::Value::String(name.to_owned())),
        ("path".to_owned(), toml::Value::String("src/main.rs".into())),
        ("test".to_owned(), toml::Value::Boolean(false)),
        ("bench".to_owned(), toml::Value::Boolean(false)),
    ]);
    // One table per section, in the order a reader expects (a TOML table alone sorts its keys).
    let mut sections: Vec<(&str, toml::Value)> = vec![
        ("package", toml::Value::Table(package)),
        ("bin", toml::Value::Array(vec![toml::Value::Table(bin)])),
        ("dependencies", toml::Value::Table(out)),
        (
            "build-dependencies",
            toml::Value::Table(toml::Table::from_iter([("codegen".to_owned(), path_dep("codegen"))])),
        ),
    ];
    if let Some(profile) = workspace.get("profile") {
        sections.push(("profile", profile.clone()));
    }
    sections.push(("workspace", toml::Value::Table(toml::Table::new())));
    let mut text = String::from(
        "# Written by `codegen new`: the runtime and codegen are the sources `codegen` carries, unpacked in its cache.\n",
    );
    for (key, value) in sections {
        let one = toml::Table::from_iter([(key.to_owned(), value)]);
        text.push_str(&toml::to_string(&one).map_err(|e| bad("Cargo.toml")(e.to_string()))?);
        text.push('\n');
    }
    Ok(text)
}

/// The project's `.cargo/config.toml`: the board's target by default, its link flags as the checkout
/// builds the cell's application with, a probe-rs runner for the chip, defmt's log level.
fn cargo_config(
    parts: &Parts,
    carried: &dyn Fn(&'static str) -> Result<String, NewError>,
) -> Result<String, NewError> {
    let bad = |why: String| NewError::Carried { file: ".cargo/config.toml", why };
    let config: toml::Table =
        carried(".cargo/config.toml")?.parse().map_err(|e: toml::de::Error| bad(e.to_string()))?;
    let flags = config
        .get("target")
        .and_then(|t| t.get(parts.target))
        .and_then(|t| t.get("rustflags"))
        .cloned()
        .ok_or_else(|| bad(format!("no rustflags for {}", parts.target)))?;
    let target = toml::Table::from_iter([
        ("runner".to_owned(), toml::Value::String(format!("probe-rs run --chip {}", parts.chip))),
        ("rustflags".to_owned(), flags),
    ]);
    let mut out = toml::Table::new();
    out.insert(
        "build".into(),
        toml::Value::Table(toml::Table::from_iter([(
            "target".to_owned(),
            toml::Value::String(parts.target.into()),
        )])),
    );
    out.insert(
        "target".into(),
        toml::Value::Table(toml::Table::from_iter([(parts.target.to_owned(), toml::Value::Table(target))])),
    );
    if let Some(env) = config.get("env") {
        out.insert("env".into(), env.clone());
    }
    toml::to_string(&out).map_err(|e| bad(e.to_string()))
}

/// The project's `build.rs`.
fn build_rs(manifest: &str) -> String {
    format!(
        r#"//! Emits the supervisors' tables from `{manifest}` into `OUT_DIR` at every build where the manifest or
//! a model file changed (codegen is a build-dependency), and puts `memory.x` on the linker's path.

fn main() {{
    let dir = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default();
    println!("cargo:rustc-link-search={{dir}}");
    println!("cargo:rerun-if-changed=memory.x");
    codegen::project::build_script::main("{manifest}");
}}
"#
    )
}

/// The project's README: the flash command and how the tables are made.
fn readme(name: &str, manifest: &str, board: Board) -> String {
    let closed_loop = if board == Board::Pico {
        "Closed loop on the emulated RP2040: `codegen run --project .` (builds, then runs the ELF against the manifest's plant)."
    } else {
        "There is no emulator for this board here (`codegen run --project .` refuses it): flash it to run it."
    };
    let (target, board) = (board.target(), board.name());
    format!(
        "# {name}\n\n\
         The local modular supervisors of `{manifest}` on a `{board}` board, written by `codegen new`.\n\n\
         - Build: `cargo build --release` (the ELF is `target/{target}/release/{name}`). `build.rs` emits the\n  \
           tables from the manifest at build time: edit the manifest or a model file and build again.\n\
         - Flash and run, defmt logs on the terminal: `cargo run --release` (probe-rs, a debug probe on SWD).\n\
         - {closed_loop}\n\
         - The virtual plant of the manifest against a firmware that speaks codegen's link on a serial port: `codegen plant --project . --connect serial:DEVICE`.\n\
         - The pin map is the manifest's `[board]` section.\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Package names are what cargo takes, and never a dependency's.
    #[test]
    fn package_names_are_cargo_names() {
        assert_eq!(package_name(Path::new("/tmp/My Board")), "my-board");
        assert_eq!(package_name(Path::new("/tmp/2nd")), "app-2nd");
        assert_eq!(package_name(Path::new("/tmp/firmware")), "firmware-app");
        assert_eq!(package_name(Path::new("/")), "app");
    }

    /// Only plain relative paths are copied under `model/`.
    #[test]
    fn only_plain_relative_paths_stay_inside() {
        assert!(is_plain(Path::new("plants/a.xmd")));
        assert!(!is_plain(Path::new("../a.xmd")));
        assert!(!is_plain(Path::new("/a.xmd")));
    }
}
