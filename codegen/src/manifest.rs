//! The project manifest: a supervisor set as users describe it, in TOML.
//!
//! ```toml
//! name = "cell"
//! plants = ["plants/G1.xmd", "plants/G2.xmd"]   # any supported format
//! specs = ["specs/E1.xmd"]
//! supervisors = []                              # ready supervisors (optional)
//!
//! [events.e1_lig]                               # optional per-event override
//! controllable = true
//!
//! [runtime]                                     # all optional: `config::RuntimeConfig`
//! policy = "random-local-queue"                 # `config::ChoicePolicy`
//! seed = 1
//! guard = true                                  # inexact-synchronisation guard
//! on_fault = "continue"                         # continue | safe-state
//! input_buffer = 32
//! reseed_every = 1024                           # random draws between two reseeds
//!
//! [board]                                       # optional: pins of a real board, `config::BoardSpec`
//! name = "pico"
//! ```
//!
//! Paths are relative to the manifest file. Unknown keys are refused, so a typo is an error rather than a
//! silently ignored setting. Every error names the manifest file and the key it is about.
//!
//! This module reads and validates, nothing more: it reads the model files a manifest names into a
//! [`ModelSet`] and checks that they agree; synthesising supervisors from them and everything after is
//! the pipeline's ([`crate::project`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::config::{BoardSpec, NetSpec, PlcSpec, RuntimeConfig, StateSpec};
use crate::formats::{read_path, ParseError};
use crate::model::{resolve_controllability, Automaton, EventTable, Kind, ModelError};

/// Why a manifest could not be loaded or its automata read.
#[derive(Debug, thiserror::Error)]
pub enum ManifestError {
    /// The manifest file could not be read.
    #[error("{}: {source}", file.display())]
    Read {
        /// The manifest file.
        file: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The manifest is not valid TOML or does not follow the schema.
    #[error("{}:{line}: {message}", file.display())]
    Syntax {
        /// The manifest file.
        file: PathBuf,
        /// Line of the offending key or value (1-based; 0 when unknown).
        line: usize,
        /// What is wrong, naming the key.
        message: String,
    },
    /// A model file named by the manifest could not be read.
    #[error("{}: {key}: {source}", file.display())]
    Model {
        /// The manifest file.
        file: PathBuf,
        /// The key naming the model file, such as `plants[2]`.
        key: String,
        /// The reader's error (it names the model file and line).
        source: ParseError,
    },
    /// An `[events.NAME]` override names an event no automaton of the manifest has.
    #[error("{}: events.{event}: no automaton of the manifest has this event", file.display())]
    UnknownEvent {
        /// The manifest file.
        file: PathBuf,
        /// The event named by the override.
        event: String,
    },
    /// A project was expected and the file is neither a manifest nor a module.
    #[error(
        "{}: not a project: expected a manifest (.toml) or a Supremica module (.wmod); give model files \
         with --plant, --spec or --sup",
        file.display()
    )]
    NotAProject {
        /// The file given.
        file: PathBuf,
    },
    /// The automata disagree on an event's controllability (and no override settles it).
    #[error("{}: {source}", file.display())]
    Inconsistent {
        /// The manifest file.
        file: PathBuf,
        /// Which event, where.
        source: ModelError,
    },
}

/// An `[events.NAME]` override.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventOverride {
    /// Controllability to use in every automaton that has the event.
    pub controllable: bool,
}

/// A parsed manifest. Paths are kept as written; [`Manifest::resolve`] makes them usable.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Name of the supervisor set.
    pub name: String,
    /// Plant subsystem files.
    #[serde(default)]
    pub plants: Vec<PathBuf>,
    /// Specification files.
    #[serde(default)]
    pub specs: Vec<PathBuf>,
    /// Ready supervisor files.
    #[serde(default)]
    pub supervisors: Vec<PathBuf>,
    /// Supremica modules (`.wmod`), each component in the role its kind gives: PLANT a plant, SPEC a
    /// specification, SUPERVISOR a supervisor.
    #[serde(default)]
    pub modules: Vec<PathBuf>,
    /// Per-event overrides, by event name.
    #[serde(default)]
    pub events: BTreeMap<String, EventOverride>,
    /// The run-time configuration (`[runtime]`).
    #[serde(default)]
    pub runtime: RuntimeConfig,
    /// Pin map for a real board (`[board]`).
    #[serde(default)]
    pub board: Option<BoardSpec>,
    /// I/O map and choices of the PLC program (`[plc]`).
    #[serde(default)]
    pub plc: Option<PlcSpec>,
    /// A sequence as a Petri net and its interpretation (`[net]`).
    #[serde(default)]
    pub net: Option<NetSpec>,
    /// The plant's state vector for state-based programs (`[state]`, `config::StateSpec`).
    #[serde(default)]
    pub state: Option<StateSpec>,
    /// The manifest file itself (set by [`Manifest::load`]).
    #[serde(skip)]
    pub file: PathBuf,
}

/// The automata of a manifest, read, with their kinds set and the event overrides applied: the models
/// stage of the pipeline.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelSet {
    /// Plant subsystems, in manifest order.
    pub plants: Vec<Automaton>,
    /// Specifications, in manifest order.
    pub specs: Vec<Automaton>,
    /// Ready supervisors, in manifest order.
    pub supervisors: Vec<Automaton>,
}

/// The automata of `files`, given on the command line in the role `kind`: every automaton of a model
/// file, and of a Supremica module only the components of that kind (a plant role takes PLANT
/// components); returns them with the components left out, as `module: name (KIND)`.
pub fn read_role(files: &[PathBuf], kind: Kind) -> Result<(Vec<Automaton>, Vec<String>), ParseError> {
    let (mut kept, mut skipped) = (Vec::new(), Vec::new());
    for f in files {
        for a in read_path(f)? {
            let wanted = a.kind == kind || (kind == Kind::Plant && a.kind == Kind::Unknown);
            if has_extension(f, "wmod") && !wanted {
                skipped.push(format!("{}: {} ({:?})", f.display(), a.name, a.kind));
            } else {
                kept.push(a);
            }
        }
    }
    Ok((kept, skipped))
}

impl ModelSet {
    /// Reads model files named one by one, as the command line names them instead of a manifest:
    /// automata from `supervisors`, or from `plants` but marked as supervisors by their file, are
    /// supervisors; those from `specs` specifications; all others plants. Kinds stay as the files say;
    /// a Supremica module contributes only the components of the role it is given in ([`read_role`]).
    /// Returns the set and the components left out.
    pub fn from_files(
        plants: &[PathBuf],
        specs: &[PathBuf],
        supervisors: &[PathBuf],
    ) -> Result<(ModelSet, Vec<String>), ParseError> {
        let (specs, mut skipped) = read_role(specs, Kind::Spec)?;
        let mut set = ModelSet { plants: Vec::new(), specs, supervisors: Vec::new() };
        let (plants, more) = read_role(plants, Kind::Plant)?;
        skipped.extend(more);
        for a in plants {
            if a.kind == Kind::Supervisor {
                set.supervisors.push(a);
            } else {
                set.plants.push(a);
            }
        }
        let (supervisors, more) = read_role(supervisors, Kind::Supervisor)?;
        skipped.extend(more);
        set.supervisors.extend(supervisors);
        Ok((set, skipped))
    }

    /// Gives the automata whose files left controllability unsaid what the rest of the set says
    /// ([`resolve_controllability`]).
    pub fn resolve_controllability(&mut self) -> Result<(), ModelError> {
        resolve_controllability(self.plants.iter_mut().chain(&mut self.specs).chain(&mut self.supervisors))
    }
}

/// Whether `path` names a project rather than a model: a manifest (`.toml`), or a Supremica module
/// (`.wmod`), which holds a whole project — its components say what each is.
pub fn is_manifest(path: &Path) -> bool {
    has_extension(path, "toml") || has_extension(path, "wmod")
}

fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// The `[board]` table of the TOML file at `path` (a pin map given apart from a manifest).
pub fn read_board(path: &Path) -> Result<BoardSpec, ManifestError> {
    #[derive(Deserialize)]
    struct File {
        board: BoardSpec,
    }
    let text = std::fs::read_to_string(path)
        .map_err(|source| ManifestError::Read { file: path.to_owned(), source })?;
    let file: File = parse_toml(path, &text)?;
    Ok(file.board)
}

/// `text` (from `path`) as TOML of type `T`; an error names the file and the line.
fn parse_toml<T: serde::de::DeserializeOwned>(path: &Path, text: &str) -> Result<T, ManifestError> {
    toml::from_str(text).map_err(|e| ManifestError::Syntax {
        file: path.to_owned(),
        line: e.span().map_or(0, |s| {
            text.as_bytes()[..s.start.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
        }),
        message: e.message().to_owned(),
    })
}

impl Manifest {
    /// Reads and parses the manifest at `path`.
    pub fn load(path: &Path) -> Result<Manifest, ManifestError> {
        if has_extension(path, "wmod") {
            return Ok(Manifest::of_module(path));
        }
        if !has_extension(path, "toml") {
            return Err(ManifestError::NotAProject { file: path.to_owned() });
        }
        let text = std::fs::read_to_string(path)
            .map_err(|source| ManifestError::Read { file: path.to_owned(), source })?;
        Manifest::parse(path, &text)
    }

    /// Parses manifest `text`; `path` is where it came from (errors name it, paths resolve against it).
    pub fn parse(path: &Path, text: &str) -> Result<Manifest, ManifestError> {
        let mut m: Manifest = parse_toml(path, text)?;
        m.file = path.to_owned();
        if let Some(net) = &mut m.net {
            net.locate(text);
        }
        Ok(m)
    }

    /// The project a Supremica module is by itself: named after the file, its components in their
    /// roles, default `[runtime]`.
    pub fn of_module(path: &Path) -> Manifest {
        let name = path.file_stem().map_or_else(|| "module".into(), |s| s.to_string_lossy().into_owned());
        let file_name = path.file_name().map_or_else(|| path.to_owned(), PathBuf::from);
        Manifest {
            name,
            plants: Vec::new(),
            specs: Vec::new(),
            supervisors: Vec::new(),
            modules: vec![file_name],
            events: BTreeMap::new(),
            runtime: RuntimeConfig::default(),
            board: None,
            plc: None,
            net: None,
            state: None,
            file: path.to_owned(),
        }
    }

    /// `p` relative to the manifest's folder (absolute paths stay as they are).
    pub fn resolve(&self, p: &Path) -> PathBuf {
        self.file.parent().unwrap_or(Path::new("")).join(p)
    }

    /// Reads every plant, specification and supervisor file, sets each automaton's kind, applies the
    /// event overrides and checks that every event has one controllability across the set.
    pub fn read_automata(&self) -> Result<ModelSet, ManifestError> {
        // The automata of the files under `key`, each with the manifest key naming it in errors.
        let read = |key: &str, files: &[PathBuf]| -> Result<Vec<Automaton>, ManifestError> {
            let mut out = Vec::new();
            for (i, f) in files.iter().enumerate() {
                out.extend(read_path(&self.resolve(f)).map_err(|source| ManifestError::Model {
                    file: self.file.clone(),
                    key: format!("{key}[{i}]"),
                    source,
                })?);
            }
            Ok(out)
        };
        let as_kind = |kind: Kind, automata: Vec<Automaton>| -> Vec<Automaton> {
            automata.into_iter().map(|a| Automaton { kind, ..a }).collect()
        };
        let mut set = ModelSet {
            plants: as_kind(Kind::Plant, read("plants", &self.plants)?),
            specs: as_kind(Kind::Spec, read("specs", &self.specs)?),
            supervisors: as_kind(Kind::Supervisor, read("supervisors", &self.supervisors)?),
        };
        for a in read("modules", &self.modules)? {
            match a.kind {
                Kind::Spec => set.specs.push(a),
                Kind::Supervisor => set.supervisors.push(a),
                Kind::Plant | Kind::Unknown => set.plants.push(a),
            }
        }
        set.resolve_controllability()
            .map_err(|source| ManifestError::Inconsistent { file: self.file.clone(), source })?;
        for (event, o) in &self.events {
            let mut found = false;
            for a in set.plants.iter_mut().chain(&mut set.specs).chain(&mut set.supervisors) {
                if let Some(id) = a.event_id(event) {
                    a.events[id.index()].controllable = o.controllable;
                    found = true;
                }
            }
            if !found {
                return Err(ManifestError::UnknownEvent { file: self.file.clone(), event: event.clone() });
            }
        }
        EventTable::build(set.plants.iter().chain(&set.specs).chain(&set.supervisors))
            .map_err(|source| ManifestError::Inconsistent { file: self.file.clone(), source })?;
        Ok(set)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell() -> PathBuf {
        [env!("CARGO_MANIFEST_DIR"), "..", "examples", "cell", "cell.toml"].iter().collect()
    }

    #[test]
    fn the_cell_manifest_loads_with_paths_relative_to_it() {
        let m = Manifest::load(&cell()).unwrap();
        assert_eq!(m.name, "cell");
        assert_eq!(m.runtime.policy, crate::config::ChoicePolicy::RandomLocalQueue);
        assert_eq!(m.runtime.seed, 1);
        let set = m.read_automata().unwrap();
        assert_eq!((set.plants.len(), set.specs.len(), set.supervisors.len()), (4, 7, 0));
        assert!(set.plants.iter().all(|a| a.kind == Kind::Plant));
        assert_eq!(set.specs[1].name, "E2");
    }

    #[test]
    fn unknown_keys_are_named_with_their_line() {
        let err =
            Manifest::parse(Path::new("m.toml"), "name = \"x\"\n[runtime]\npolicy = \"first\"\nsed = 3\n")
                .unwrap_err()
                .to_string();
        assert!(err.starts_with("m.toml:4: unknown field `sed`"), "{err}");
        let err = Manifest::parse(Path::new("m.toml"), "name = \"x\"\n[runtime]\npolicy = \"fastest\"\n")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("m.toml:3: unknown variant `fastest`"), "{err}");
    }

    #[test]
    fn model_errors_name_the_key_and_overrides_must_exist() {
        let dir = cell();
        let m = Manifest::parse(&dir, "name = \"x\"\nplants = [\"plants/G1.xmd\", \"plants/nope.xmd\"]\n")
            .unwrap();
        let err = m.read_automata().unwrap_err().to_string();
        assert!(err.contains("cell.toml: plants[1]: ") && err.contains("nope.xmd"), "{err}");
        let m = Manifest::parse(
            &dir,
            "name = \"x\"\nplants = [\"plants/G1.xmd\"]\n[events.zz]\ncontrollable = true\n",
        )
        .unwrap();
        let err = m.read_automata().unwrap_err().to_string();
        assert!(err.ends_with("cell.toml: events.zz: no automaton of the manifest has this event"), "{err}");
    }

    #[test]
    fn an_override_changes_controllability_everywhere() {
        let m = Manifest::parse(
            &cell(),
            "name = \"x\"\nplants = [\"plants/G1.xmd\"]\n[events.e1_lig]\ncontrollable = false\n",
        )
        .unwrap();
        let set = m.read_automata().unwrap();
        let g1 = &set.plants[0];
        assert!(!g1.events[g1.event_id("e1_lig").unwrap().index()].controllable);
    }
}
