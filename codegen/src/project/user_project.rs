//! A firmware project that `codegen new` wrote, as `codegen run --project` and `codegen plant
//! --project` find it: its binary's name (`Cargo.toml`), its board (the target and the probe-rs chip
//! of `.cargo/config.toml`), its manifest (the one `.toml` in `model/`), and its release build.
//!
//! Why read the project's own files rather than ask for each on the command line: they are what
//! `cargo build` in the project uses, so the ELF that runs and the manifest the plant and the monitor
//! judge it by are the project's, the same pair its `build.rs` made the tables from.

use std::path::{Path, PathBuf};

use clap::ValueEnum;

use crate::target::image::{build_project, ImageError};

use super::new_project::{Board, MODEL_DIR};

/// A project of the user's own, found in its directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UserProject {
    /// The project's directory.
    pub dir: PathBuf,
    /// The package's (and its binary's) name.
    pub name: String,
    /// The board it is built for.
    pub board: Board,
    /// Its manifest, `DIR/model/NAME.toml`.
    pub manifest: PathBuf,
}

/// A directory is not a project `codegen new` wrote, or its build failed.
#[derive(Debug, thiserror::Error)]
pub enum UserProjectError {
    /// A file of the project could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A file of the project is not what `codegen new` writes.
    #[error("{}: {why} (a project written by `codegen new DIR --board B`?)", file.display())]
    NotAProject {
        /// The file.
        file: PathBuf,
        /// What is wrong or missing.
        why: String,
    },
    /// The project did not build.
    #[error(transparent)]
    Build(#[from] ImageError),
}

impl UserProject {
    /// Reads the project in `dir`: `Cargo.toml`'s package name, `.cargo/config.toml`'s target and
    /// runner chip (one of [`Board`]'s), the one manifest in `model/`.
    pub fn open(dir: &Path) -> Result<UserProject, UserProjectError> {
        let cargo = read_toml(&dir.join("Cargo.toml"))?;
        let name = cargo
            .get("package")
            .and_then(|p| p.get("name"))
            .and_then(toml::Value::as_str)
            .ok_or_else(|| not_a_project(&dir.join("Cargo.toml"), "no [package] name"))?
            .to_owned();
        let config_path = dir.join(".cargo/config.toml");
        let config = read_toml(&config_path)?;
        let target = config
            .get("build")
            .and_then(|b| b.get("target"))
            .and_then(toml::Value::as_str)
            .ok_or_else(|| not_a_project(&config_path, "no [build] target"))?;
        let runner = config
            .get("target")
            .and_then(|t| t.get(target))
            .and_then(|t| t.get("runner"))
            .and_then(toml::Value::as_str)
            .unwrap_or_default();
        let board = Board::value_variants()
            .iter()
            .copied()
            .find(|b| b.target() == target && runner.ends_with(&format!("--chip {}", b.chip())))
            .ok_or_else(|| {
                not_a_project(
                    &config_path,
                    &format!("target {target} with runner '{runner}' is no board of `codegen new`"),
                )
            })?;
        let model = dir.join(MODEL_DIR);
        let entries = std::fs::read_dir(&model)
            .map_err(|source| UserProjectError::Io { path: model.clone(), source })?;
        let mut manifests: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "toml"))
            .collect();
        manifests.sort();
        let manifest = match manifests.as_slice() {
            [one] => one.clone(),
            [] => return Err(not_a_project(&model, "no manifest (*.toml) here")),
            many => {
                let names: Vec<String> = many.iter().map(|p| p.display().to_string()).collect();
                return Err(not_a_project(&model, &format!("more than one manifest: {}", names.join(", "))));
            }
        };
        Ok(UserProject { dir: dir.to_path_buf(), name, board, manifest })
    }

    /// `cargo build --release` in the project; the ELF.
    pub fn build(&self) -> Result<PathBuf, UserProjectError> {
        Ok(build_project(&self.dir, &self.name)?)
    }
}

/// `file` parsed as TOML.
fn read_toml(file: &Path) -> Result<toml::Table, UserProjectError> {
    let text = std::fs::read_to_string(file)
        .map_err(|source| UserProjectError::Io { path: file.to_path_buf(), source })?;
    text.parse().map_err(|e: toml::de::Error| not_a_project(file, &e.to_string()))
}

fn not_a_project(file: &Path, why: &str) -> UserProjectError {
    UserProjectError::NotAProject { file: file.to_path_buf(), why: why.to_owned() }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scratch directory holding `files` (path, text), removed when dropped.
    struct Dir(PathBuf);

    impl Dir {
        fn with(tag: &str, files: &[(&str, &str)]) -> Dir {
            let dir = std::env::temp_dir().join(format!("user-project-{tag}-{}", std::process::id()));
            for (rel, text) in files {
                let path = dir.join(rel);
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                std::fs::write(path, text).unwrap();
            }
            Dir(dir)
        }
    }

    impl Drop for Dir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    const CARGO: &str = "[package]\nname = \"my-cell\"\n";

    fn config(target: &str, chip: &str) -> String {
        format!(
            "[build]\ntarget = \"{target}\"\n[target.{target}]\nrunner = \"probe-rs run --chip {chip}\"\n"
        )
    }

    #[test]
    fn the_board_is_read_off_the_target_and_the_chip() {
        for board in Board::value_variants() {
            let config = config(board.target(), board.chip());
            let files = [("Cargo.toml", CARGO), (".cargo/config.toml", &config), ("model/cell.toml", "")];
            let dir = Dir::with(&format!("{board:?}"), &files);
            let project = UserProject::open(&dir.0).unwrap();
            assert_eq!((project.name.as_str(), project.board), ("my-cell", *board));
            assert_eq!(project.manifest, dir.0.join("model/cell.toml"));
        }
    }

    #[test]
    fn what_codegen_new_would_not_write_is_refused_naming_the_file() {
        let nucleo = config("thumbv7em-none-eabihf", "STM32F401RETx");
        let unknown = config("thumbv7em-none-eabihf", "nRF52832_xxAA");
        /// A directory's tag, its files (path, text), a word its error must hold.
        type Case<'a> = (&'a str, Vec<(&'a str, &'a str)>, &'a str);
        let cases: [Case; 4] = [
            ("no-cargo", vec![], "Cargo.toml"),
            ("chip", vec![("Cargo.toml", CARGO), (".cargo/config.toml", &unknown)], ".cargo/config.toml"),
            (
                "none",
                vec![("Cargo.toml", CARGO), (".cargo/config.toml", &nucleo), ("model/a.xmd", "")],
                "model",
            ),
            (
                "two",
                vec![
                    ("Cargo.toml", CARGO),
                    (".cargo/config.toml", &nucleo),
                    ("model/a.toml", ""),
                    ("model/b.toml", ""),
                ],
                "more than one manifest",
            ),
        ];
        for (tag, files, named) in cases {
            let dir = Dir::with(tag, &files);
            let err = UserProject::open(&dir.0).unwrap_err().to_string();
            assert!(err.contains(named), "{tag}: {err}");
        }
    }
}
