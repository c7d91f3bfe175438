//! What a command was given to work on, and the one loader of every command that takes files: a
//! manifest, one or several Supremica modules (one project), model files read as their files say, or
//! model files in roles (`--plant`, `--spec`, `--sup`).

use std::path::{Path, PathBuf};

use crate::manifest::{has_extension, FileRoles, Manifest, ModelSet};
use crate::maps::{self, Board};

use super::ProjectError;

/// The files a command names. A lone `.toml` is a manifest; every other file given without a role is
/// read as its file says (a module's components by their kinds, a model file by its kind, plants when
/// it does not say), and files given in a role as [`ModelSet::from_files`] reads them; all of them are
/// one project.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Sources {
    /// Files given without a role (the command's positional arguments).
    pub files: Vec<PathBuf>,
    /// `--plant` files.
    pub plants: Vec<PathBuf>,
    /// `--spec` files.
    pub specs: Vec<PathBuf>,
    /// `--sup` files.
    pub supervisors: Vec<PathBuf>,
    /// The board the command builds for (`codegen new --board`, `run --target rp2040`, a project's
    /// build), if it builds for one: a manifest's `[board]` and `[state]` pins are checked against it
    /// (else against the board `[board] name` names).
    pub board: Option<Board>,
}

/// A project's models as loaded, before any synthesis.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The project's name: the manifest's `name`, else the first file's stem.
    pub name: String,
    /// The automata, checked ([`ModelSet::check_alphabets`]) and with controllability resolved.
    pub models: ModelSet,
    /// The manifest, when the project is one (a `.toml`, or a lone module read as one).
    pub manifest: Option<Manifest>,
    /// Components of modules given in a role of another kind, left out (`module: name (KIND)`).
    pub left_out: Vec<String>,
    /// Every input file, in the order read (a manifest first, then the files it names).
    pub inputs: Vec<PathBuf>,
}

/// The stem of `path`, or `fallback`.
fn stem(path: Option<&PathBuf>, fallback: &str) -> String {
    path.and_then(|p| p.file_stem()).map_or_else(|| fallback.to_owned(), |s| s.to_string_lossy().into_owned())
}

impl Loaded {
    /// The project of the manifest `m`: its automata, each set checked where its files meet, and its
    /// maps checked against them ([`maps::check`]; a board's pins against `board`'s when one is built for).
    pub fn of_manifest(m: Manifest, board: Option<Board>) -> Result<Loaded, ProjectError> {
        let models = m.read_automata()?;
        maps::check(&m, &models, board)?;
        let named = m.plants.iter().chain(&m.specs).chain(&m.supervisors).chain(&m.modules);
        // A module loaded as a project is its own manifest: one input.
        let inputs = std::iter::once(m.file.clone())
            .chain(named.map(|p| m.resolve(p)).filter(|p| *p != m.file))
            .collect();
        Ok(Loaded { name: m.name.clone(), models, manifest: Some(m), left_out: Vec::new(), inputs })
    }
}

impl Sources {
    /// The files given without a role, as a project: `files` (a manifest, modules or model files).
    pub fn project(files: &[PathBuf]) -> Sources {
        Sources { files: files.to_vec(), ..Sources::default() }
    }

    /// Whether nothing was given.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
            && self.plants.is_empty()
            && self.specs.is_empty()
            && self.supervisors.is_empty()
    }

    /// The sources as a command line's words: the files without a role, then `--plant`, `--spec` and
    /// `--sup` with theirs.
    pub fn words(&self) -> Vec<String> {
        let role = |flag: &'static str, files: &'_ [PathBuf]| {
            files.iter().map(move |p| format!("{flag} {}", p.display())).collect::<Vec<_>>()
        };
        let mut out: Vec<String> = self.files.iter().map(|p| p.display().to_string()).collect();
        out.extend(role("--plant", &self.plants));
        out.extend(role("--spec", &self.specs));
        out.extend(role("--sup", &self.supervisors));
        out
    }

    /// The manifest among the files, if the sources are a lone manifest (or a lone module with no
    /// files in roles, which is its own manifest).
    pub fn manifest(&self) -> Option<&Path> {
        let roles = self.plants.len() + self.specs.len() + self.supervisors.len();
        match self.files.as_slice() {
            [one] if roles == 0 && (has_extension(one, "toml") || has_extension(one, "wmod")) => Some(one),
            _ => None,
        }
    }

    /// Reads the project: its automata, each set checked where its files meet — events of
    /// specifications and supervisors that no plant has refused, controllability resolved — and a
    /// manifest's maps checked against them ([`maps::check`]). A manifest among several files, or given
    /// with files in roles, is refused.
    pub fn load(&self) -> Result<Loaded, ProjectError> {
        if let Some(path) = self.manifest() {
            return Loaded::of_manifest(Manifest::load(path)?, self.board);
        }
        if let Some(toml) = self.files.iter().find(|f| has_extension(f, "toml")) {
            return Err(ProjectError::ManifestAmongFiles { file: toml.clone() });
        }
        let roles = FileRoles {
            as_said: self.files.clone(),
            plants: self.plants.clone(),
            specs: self.specs.clone(),
            supervisors: self.supervisors.clone(),
        };
        let (models, left_out) = ModelSet::from_files(&roles)?;
        let first = self.files.first().or(self.plants.first()).or(self.supervisors.first());
        let inputs =
            self.files.iter().chain(&self.plants).chain(&self.specs).chain(&self.supervisors).cloned();
        Ok(Loaded { name: stem(first, "set"), models, manifest: None, left_out, inputs: inputs.collect() })
    }
}
