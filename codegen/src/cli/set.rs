//! The supervisor set `pack` and `check` work on, from a manifest or from model files.

use std::path::{Path, PathBuf};

use codegen::formats::read_path;
use codegen::manifest::Manifest;
use codegen::model::{Automaton, Kind};

use super::Error;

/// Plants, specifications and supervisors, each in the order given.
pub struct ClosedLoop {
    /// Plant subsystems.
    pub plants: Vec<Automaton>,
    /// Specifications (empty when the set came as plant and supervisor files).
    pub specs: Vec<Automaton>,
    /// Supervisors: the manifest's ready ones, else synthesised local modular from its specifications.
    pub supervisors: Vec<Automaton>,
}

impl ClosedLoop {
    /// Reads the manifest at `path`: its ready supervisors, then those synthesised from its specifications.
    pub fn from_manifest(path: &Path) -> Result<ClosedLoop, Error> {
        let set = Manifest::load(path)?.read_automata()?;
        let supervisors = set.all_supervisors()?;
        Ok(ClosedLoop { plants: set.plants, specs: set.specs, supervisors })
    }

    /// Reads model files; automata from `supervisors`, or marked as supervisors by their file, are
    /// supervisors, those from `specs` specifications, all others plants.
    pub fn from_files(
        plants: &[PathBuf],
        specs: &[PathBuf],
        supervisors: &[PathBuf],
    ) -> Result<ClosedLoop, Error> {
        let mut set = ClosedLoop { plants: Vec::new(), specs: read_all(specs)?, supervisors: Vec::new() };
        for a in read_all(plants)? {
            if a.kind == Kind::Supervisor {
                set.supervisors.push(a);
            } else {
                set.plants.push(a);
            }
        }
        set.supervisors.extend(read_all(supervisors)?);
        Ok(set)
    }
}

/// Every automaton of every file, in order.
fn read_all(files: &[PathBuf]) -> Result<Vec<Automaton>, Error> {
    let mut out = Vec::new();
    for f in files {
        out.extend(read_path(f)?);
    }
    Ok(out)
}

/// Whether `path` names a manifest (a `.toml` file) rather than a model.
pub fn is_manifest(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}
