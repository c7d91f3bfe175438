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
//! [events.tick]                                 # an event no plant has, on purpose
//! plantless = true
//!
//! [runtime]                                     # all optional: `config::RuntimeConfig`
//! policy = "random-local-queue"                 # `config::ChoicePolicy`
//! seed = 1
//! guard = true                                  # inexact-synchronisation guard
//! on_fault = "continue"                         # continue | safe-state
//! input_buffer = 32
//! reseed_every = 1024                           # random draws between two reseeds
//! answer_ms = { extend = [1000, 3000] }         # the virtual plant's answer delay per command (run)
//!
//! [board]                                       # optional: pins of a real board, `config::BoardSpec`
//! name = "pico"
//!
//! [check]                                       # optional: which findings fail `codegen check`
//! fail_on = ["avalanche"]                       # the default
//!
//! [[timers]]                                    # optional: timeouts, `TimerSpec`
//! name = "T_ext"                                # one more plant automaton, untimed
//! start = ["extend"]
//! stop = ["at_end"]
//! timeout = "ext_timeout"                       # default "<name>_timeout"
//! ms = 2000
//! ```
//!
//! Paths are relative to the manifest file. Unknown keys are refused, so a typo is an error rather than a
//! silently ignored setting. Every error names the manifest file and the key it is about.
//!
//! Wherever files are brought together (a manifest, or model files named one by one) every event of a
//! specification or supervisor must be an event of some plant ([`plantless_events`]), unless the
//! manifest declares it plant-less (`[events.NAME] plantless = true`): a typo is refused with the file,
//! the line and the plant events closest in spelling, every such event of the set at once.
//!
//! This module reads and validates, nothing more: it reads the model files a manifest names into a
//! [`ModelSet`] and checks that they agree; synthesising supervisors from them and everything after is
//! the pipeline's ([`crate::project`]).

mod lines;
mod timers;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::config::{BoardSpec, HybridSpec, NetSpec, PlcSpec, RuntimeConfig, StateSpec};
use crate::formats::{read_path, ParseError};
use crate::model::suggest::did_you_mean;
use crate::model::{
    plantless_events, resolve_controllability, Automaton, EventTable, Kind, ModelError, PlantlessEvent,
};

pub use lines::{Key, Lines};
pub use timers::TimerSpec;

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
    /// `[events.NAME]` entries that do not fit the set: a name no automaton has, a plant-less
    /// declaration of an event a plant has. Every one of the manifest is listed.
    #[error("{}: [events] does not fit the automata:\n  {}", file.display(), problems.join("\n  "))]
    Events {
        /// The manifest file.
        file: PathBuf,
        /// One line per entry: `LINE: events.NAME: what is wrong (did you mean …?)`.
        problems: Vec<String>,
    },
    /// Automata that cannot be members of one set: an empty one (no states), two of one name. Every
    /// one of the set is listed, each with the file (and the manifest key) it comes from.
    #[error("{}the automata do not make a set:\n  {}", file.as_ref().map_or_else(String::new, |f| format!("{}: ", f.display())), problems.join("\n  "))]
    Automata {
        /// The manifest, when the set is one.
        file: Option<PathBuf>,
        /// One line per problem, naming the automaton and where it comes from.
        problems: Vec<String>,
    },
    /// Events of specifications or supervisors that no plant has.
    #[error(transparent)]
    Alphabet(#[from] AlphabetError),
    /// A model file named on the command line could not be read.
    #[error(transparent)]
    File(#[from] ParseError),
    /// The model files named on the command line do not agree on, or do not say, an event's
    /// controllability.
    #[error(transparent)]
    Controllability(#[from] ModelError),
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
    /// `[[timers]]` entries that do not fit the set (an event no automaton has, a zero delay, a
    /// controllable timeout, a timeout a plant file generates). Every one of the manifest is listed.
    #[error("{}: [[timers]] does not fit the automata:\n  {}", file.display(), problems.join("\n  "))]
    Timers {
        /// The manifest file.
        file: PathBuf,
        /// One line per problem: `LINE: timers[N].KEY: what is wrong`.
        problems: Vec<String>,
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

/// Every event of a set's specifications and supervisors that no plant has, each with the file and line
/// that declares it: why the set is refused.
#[derive(Debug, thiserror::Error)]
#[error(
    "{} in no plant (a typo? an event no plant has on purpose is declared in a manifest: \
     [events.NAME] plantless = true):\n  {}",
    if problems.len() == 1 {
        "an event of a specification or supervisor is".to_owned()
    } else {
        format!("{} events of specifications or supervisors are", problems.len())
    },
    problems.iter().map(|(at, p)| format!("{at}: {}", p.describe())).collect::<Vec<_>>().join("\n  ")
)]
pub struct AlphabetError {
    /// Each event with where it is declared (`file:line`, or the file alone when the line is unknown).
    pub problems: Vec<(String, PlantlessEvent)>,
}

/// An `[events.NAME]` entry: settings of one event for the whole set.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventOverride {
    /// Controllability to use in every automaton that has the event (unset: as the files say).
    #[serde(default)]
    pub controllable: Option<bool>,
    /// The event is in no plant on purpose (a specification's or supervisor's own event); without this
    /// such an event is refused as a probable typo. Default false.
    #[serde(default)]
    pub plantless: bool,
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
    /// The events of the `[net]`'s transitions when that net is the plant of a hybrid controller
    /// (`[hybrid]`, `plc::hybrid`).
    #[serde(default)]
    pub hybrid: Option<HybridSpec>,
    /// The plant's state vector for state-based programs (`[state]`, `config::StateSpec`).
    #[serde(default)]
    pub state: Option<StateSpec>,
    /// What fails `codegen check` (`[check]`).
    #[serde(default)]
    pub check: CheckSpec,
    /// Timeouts (`[[timers]]`): each an untimed plant automaton for synthesis, its delay for the runtimes.
    #[serde(default)]
    pub timers: Vec<TimerSpec>,
    /// The manifest file itself (set by [`Manifest::load`]).
    #[serde(skip)]
    pub file: PathBuf,
    /// The manifest's text, for the line of a key in messages (set by [`Manifest::parse`]; empty for a
    /// module read as a project).
    #[serde(skip)]
    pub lines: Lines,
    /// Whether this is a Supremica module read as a project ([`Manifest::of_module`]): errors then name
    /// the module, not a manifest key the user never wrote.
    #[serde(skip)]
    module: bool,
}

/// The `[check]` section: which kinds of finding make `codegen check` fail (exit 1); the others are
/// reported and pass.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckSpec {
    /// Names of the failing problems (`avalanche`, `choice`, `inexact-synchronisation`,
    /// `simultaneity`). Default: `["avalanche"]` — the one problem a concurrent model does not always
    /// have, and the one no run-time measure answers (the choice policy answers choice, the guard
    /// inexact synchronisation, and simultaneity is mostly sensors that exclude each other).
    #[serde(default = "CheckSpec::default_fail_on")]
    pub fail_on: Vec<String>,
}

impl CheckSpec {
    fn default_fail_on() -> Vec<String> {
        vec!["avalanche".to_owned()]
    }
}

impl Default for CheckSpec {
    fn default() -> Self {
        CheckSpec { fail_on: CheckSpec::default_fail_on() }
    }
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
    /// The file each automaton was read from, by automaton name, in the order read (errors name it).
    pub sources: Vec<(String, PathBuf)>,
}

/// The automata of `files`, given on the command line in the role `kind`: every automaton of a model
/// file, and of a Supremica module only the components of that kind (a plant role takes PLANT
/// components); adds the components left out to `skipped`, as `module: name (KIND)`, and each automaton
/// kept with its file to `sources`.
fn read_role(
    files: &[PathBuf],
    kind: Kind,
    skipped: &mut Vec<String>,
    sources: &mut Vec<(String, PathBuf)>,
) -> Result<Vec<Automaton>, ParseError> {
    let mut kept = Vec::new();
    for f in files {
        for a in read_path(f)? {
            let wanted = a.kind == kind || (kind == Kind::Plant && a.kind == Kind::Unknown);
            if has_extension(f, "wmod") && !wanted {
                skipped.push(format!("{}: {} ({:?})", f.display(), a.name, a.kind));
            } else {
                sources.push((a.name.clone(), f.clone()));
                kept.push(a);
            }
        }
    }
    Ok(kept)
}

/// The first line (1-based) of the file at `path` where `name` stands as a whole word (not inside a
/// longer name): where a reader declares or first uses it. `None` when the file cannot be read or does
/// not hold it as a word.
fn line_of(path: &Path, name: &str) -> Option<usize> {
    let text = std::fs::read_to_string(path).ok()?;
    let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    text.lines()
        .position(|line| {
            line.match_indices(name).any(|(at, _)| {
                !word(line[..at].chars().next_back()) && !word(line[at + name.len()..].chars().next())
            })
        })
        .map(|i| i + 1)
}

/// Refuses automata that cannot be members of one set, every one of them: an automaton without states
/// (the empty language: a plant that can do nothing, a specification that allows nothing — synthesis
/// would blame whatever it meets first) and a second automaton of a name already taken (two
/// specifications of one name would give two supervisors of one name). Each member comes with where
/// it was read from (`specs[1] (Z1.gen)`, or the file).
fn check_members(members: &[(&Automaton, &str)]) -> Result<(), Vec<String>> {
    let mut problems = Vec::new();
    let mut first: BTreeMap<&str, &str> = BTreeMap::new();
    for &(a, origin) in members {
        if a.states.is_empty() {
            let role = match a.kind {
                Kind::Plant | Kind::Unknown => "plant",
                Kind::Spec => "specification",
                Kind::Supervisor => "supervisor",
            };
            problems.push(format!(
                "{origin}: {role} '{}' is empty (no states): it is the empty language, in which nothing \
                 ever happens; give it its states and an initial one",
                a.name
            ));
        }
        match first.get(a.name.as_str()) {
            Some(&earlier) if earlier == origin => problems.push(format!(
                "{origin}: automaton '{}' a second time (the file is given twice?): one name, one \
                 automaton (two specifications of one name would give two supervisors called S_{})",
                a.name, a.name
            )),
            Some(&earlier) => problems.push(format!(
                "{origin}: a second automaton called '{}' (the first: {earlier}): one name, one \
                 automaton (a file listed twice? two specifications of one name would give two \
                 supervisors called S_{})",
                a.name, a.name
            )),
            None => {
                first.insert(&a.name, origin);
            }
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems)
    }
}

/// Model files as a command line names them instead of a manifest: some read as their files say, the
/// others in the role they are given in.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FileRoles {
    /// Files whose automata take the role their file gives them (a Supremica module's component kinds,
    /// a model file's kind; plants when the file does not say), as a manifest's `modules`.
    pub as_said: Vec<PathBuf>,
    /// Plant files (`--plant`).
    pub plants: Vec<PathBuf>,
    /// Specification files (`--spec`).
    pub specs: Vec<PathBuf>,
    /// Supervisor files (`--sup`).
    pub supervisors: Vec<PathBuf>,
}

impl ModelSet {
    /// Puts `a` where its kind says: specifications, supervisors, else plants.
    fn place(&mut self, a: Automaton) {
        match a.kind {
            Kind::Spec => self.specs.push(a),
            Kind::Supervisor => self.supervisors.push(a),
            Kind::Plant | Kind::Unknown => self.plants.push(a),
        }
    }

    /// Reads model files named one by one, as the command line names them instead of a manifest:
    /// automata of `as_said` where their files put them ([`FileRoles::as_said`]); automata from
    /// `supervisors`, or from `plants` but marked as supervisors by their file, are supervisors; those
    /// from `specs` specifications; all others plants. Kinds stay as the files say; a Supremica module
    /// in a role contributes only the components of that role (`read_role`). Returns the set and the
    /// components left out.
    /// The set is checked as a manifest's is: every event of a specification or supervisor in some plant
    /// ([`ModelSet::check_alphabets`], none declared plant-less), controllability resolved
    /// ([`ModelSet::resolve_controllability`]).
    pub fn from_files(files: &FileRoles) -> Result<(ModelSet, Vec<String>), ManifestError> {
        let (mut skipped, mut sources) = (Vec::new(), Vec::new());
        let specs = read_role(&files.specs, Kind::Spec, &mut skipped, &mut sources)?;
        let mut set = ModelSet { plants: Vec::new(), specs, supervisors: Vec::new(), sources: Vec::new() };
        for f in &files.as_said {
            for a in read_path(f)? {
                sources.push((a.name.clone(), f.clone()));
                set.place(a);
            }
        }
        for a in read_role(&files.plants, Kind::Plant, &mut skipped, &mut sources)? {
            if a.kind == Kind::Supervisor {
                set.supervisors.push(a);
            } else {
                set.plants.push(a);
            }
        }
        set.supervisors.extend(read_role(&files.supervisors, Kind::Supervisor, &mut skipped, &mut sources)?);
        // Every automaton read, in the order read, with its file (a name taken twice finds its first
        // automaton twice: the second is reported for its name anyway).
        let all: Vec<&Automaton> = set.plants.iter().chain(&set.specs).chain(&set.supervisors).collect();
        let origins: Vec<(&Automaton, String)> = sources
            .iter()
            .filter_map(|(name, f)| {
                all.iter().find(|a| a.name == *name).map(|a| (*a, f.display().to_string()))
            })
            .collect();
        let members: Vec<(&Automaton, &str)> = origins.iter().map(|(a, f)| (*a, f.as_str())).collect();
        check_members(&members).map_err(|problems| ManifestError::Automata { file: None, problems })?;
        set.sources = sources;
        set.check_alphabets(&BTreeSet::new())?;
        set.resolve_controllability()?;
        Ok((set, skipped))
    }

    /// Refuses the set when an event of a specification or supervisor is in no plant and not in
    /// `declared` ([`plantless_events`]), naming each such event with its file and line.
    pub fn check_alphabets(&self, declared: &BTreeSet<String>) -> Result<(), AlphabetError> {
        let problems = plantless_events(&self.plants, &self.specs, &self.supervisors, declared);
        if problems.is_empty() {
            return Ok(());
        }
        let problems = problems
            .into_iter()
            .map(|p| {
                let file = self.sources.iter().find(|(name, _)| *name == p.automaton).map(|(_, f)| f);
                let at = match file {
                    Some(f) => match line_of(f, &p.event) {
                        Some(line) => format!("{}:{line}", f.display()),
                        None => f.display().to_string(),
                    },
                    None => format!("'{}'", p.automaton),
                };
                (at, p)
            })
            .collect();
        Err(AlphabetError { problems })
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

/// Whether `path` ends in `.ext` (any case).
pub fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// The `[board]` table of the TOML file at `path` (a pin map given apart from a manifest), with the
/// file's text for the lines of its keys.
pub fn read_board(path: &Path) -> Result<(BoardSpec, Lines), ManifestError> {
    #[derive(Deserialize)]
    struct File {
        board: BoardSpec,
    }
    let text = std::fs::read_to_string(path)
        .map_err(|source| ManifestError::Read { file: path.to_owned(), source })?;
    let file: File = parse_toml(path, &text)?;
    Ok((file.board, Lines::new(text)))
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
        m.lines = Lines::new(text);
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
            hybrid: None,
            state: None,
            check: CheckSpec::default(),
            timers: Vec::new(),
            file: path.to_owned(),
            lines: Lines::default(),
            module: true,
        }
    }

    /// The line of `key` in the manifest, as a message prefix (`12: `), or nothing when unknown.
    pub fn at(&self, key: &Key) -> String {
        self.lines.line(key).map_or_else(String::new, |l| format!("{l}: "))
    }

    /// `p` relative to the manifest's folder (absolute paths stay as they are).
    pub fn resolve(&self, p: &Path) -> PathBuf {
        self.file.parent().unwrap_or(Path::new("")).join(p)
    }

    /// Reads every plant, specification and supervisor file, sets each automaton's kind, applies the
    /// event overrides and checks that every event has one controllability across the set.
    pub fn read_automata(&self) -> Result<ModelSet, ManifestError> {
        self.read_automata_over(Vec::new())
    }

    /// [`Manifest::read_automata`] with `plants` that no file of the manifest holds first among the
    /// plants (the reachability graph of a hybrid controller's net), checked with the rest.
    pub fn read_automata_over(&self, plants: Vec<Automaton>) -> Result<ModelSet, ManifestError> {
        let mut sources = Vec::new();
        let mut origins = Vec::new();
        // The automata of the files under `key`, each with the manifest key naming it in errors (a
        // module read as a project is named by itself).
        let mut read = |key: &str, files: &[PathBuf]| -> Result<Vec<Automaton>, ManifestError> {
            let mut out = Vec::new();
            for (i, f) in files.iter().enumerate() {
                let path = self.resolve(f);
                let automata = read_path(&path).map_err(|source| match self.module {
                    true => ManifestError::File(source),
                    false => {
                        ManifestError::Model { file: self.file.clone(), key: format!("{key}[{i}]"), source }
                    }
                })?;
                sources.extend(automata.iter().map(|a| (a.name.clone(), path.clone())));
                let origin = match self.module {
                    true => path.display().to_string(),
                    false => format!("{key}[{i}] ({})", f.display()),
                };
                origins.extend(automata.iter().map(|_| origin.clone()));
                out.extend(automata);
            }
            Ok(out)
        };
        let as_kind = |kind: Kind, automata: Vec<Automaton>| -> Vec<Automaton> {
            automata.into_iter().map(|a| Automaton { kind, ..a }).collect()
        };
        let read_plants = as_kind(Kind::Plant, read("plants", &self.plants)?);
        let specs = as_kind(Kind::Spec, read("specs", &self.specs)?);
        let supervisors = as_kind(Kind::Supervisor, read("supervisors", &self.supervisors)?);
        let modules = read("modules", &self.modules)?;
        let timers =
            self.timer_automata(read_plants.iter().chain(&specs).chain(&supervisors).chain(&modules))?;
        origins.extend((0..timers.len()).map(|i| format!("timers[{i}]")));
        let members: Vec<(&Automaton, &str)> = read_plants
            .iter()
            .chain(&specs)
            .chain(&supervisors)
            .chain(&modules)
            .chain(&timers)
            .zip(origins.iter().map(String::as_str))
            .collect();
        let file = (!self.module).then(|| self.file.clone());
        check_members(&members).map_err(|problems| ManifestError::Automata { file, problems })?;
        let plants = plants.into_iter().chain(read_plants).chain(timers).collect();
        let mut set = ModelSet { plants, specs, supervisors, sources: Vec::new() };
        for a in modules {
            set.place(a);
        }
        set.sources = sources;
        self.check_events(&set)?;
        let declared: BTreeSet<String> =
            self.events.iter().filter(|(_, o)| o.plantless).map(|(name, _)| name.clone()).collect();
        set.check_alphabets(&declared)?;
        set.resolve_controllability()
            .map_err(|source| ManifestError::Inconsistent { file: self.file.clone(), source })?;
        for (event, o) in &self.events {
            let Some(controllable) = o.controllable else { continue };
            for a in set.plants.iter_mut().chain(&mut set.specs).chain(&mut set.supervisors) {
                if let Some(id) = a.event_id(event) {
                    a.events[id.index()].controllable = controllable;
                }
            }
        }
        EventTable::build(set.plants.iter().chain(&set.specs).chain(&set.supervisors))
            .map_err(|source| ManifestError::Inconsistent { file: self.file.clone(), source })?;
        Ok(set)
    }

    /// The plant automata of `[[timers]]` over the events of `read` (the automata of the manifest's
    /// files), their start and stop events as controllable as those files say; refuses, every one at
    /// once, an entry that does not fit ([`TimerSpec::problems`]) and a timeout a plant file generates
    /// (the timer is its only source).
    fn timer_automata<'a>(
        &self,
        read: impl Iterator<Item = &'a Automaton> + Clone,
    ) -> Result<Vec<Automaton>, ManifestError> {
        if self.timers.is_empty() {
            return Ok(Vec::new());
        }
        // A file that says controllability beats one that left it unsaid (placeholders).
        let controllable = |name: &str| {
            let mut said = read.clone().filter_map(|a| a.event_id(name).map(|id| (a, id)));
            let first = said.clone().next();
            said.find(|(a, _)| !a.controllability_unsaid)
                .or(first)
                .map(|(a, id)| a.events[id.index()].controllable)
        };
        let mut problems = Vec::new();
        for (i, t) in self.timers.iter().enumerate() {
            let at = self.at(&Key::new("timers").item(i));
            problems.extend(t.problems(i, controllable).into_iter().map(|p| format!("{at}{p}")));
            let timeout = t.timeout_event();
            let generates = |a: &&Automaton| {
                matches!(a.kind, Kind::Plant | Kind::Unknown) && a.event_id(&timeout).is_some()
            };
            if let Some(plant) = read.clone().find(generates) {
                problems.push(format!(
                    "{at}timers[{i}].timeout: plant '{}' has '{timeout}' too; the timer is the only source of its timeout",
                    plant.name
                ));
            }
        }
        if !problems.is_empty() {
            return Err(ManifestError::Timers { file: self.file.clone(), problems });
        }
        let mut automata = Vec::new();
        for t in &self.timers {
            let a = t
                .automaton(controllable)
                .map_err(|source| ManifestError::Inconsistent { file: self.file.clone(), source })?;
            automata.push(a);
        }
        Ok(automata)
    }

    /// Refuses `[events.NAME]` entries that do not fit `set`: a name no automaton has (with the names
    /// closest in spelling), a plant-less declaration of an event a plant has. Lists every one.
    fn check_events(&self, set: &ModelSet) -> Result<(), ManifestError> {
        let all: BTreeSet<&str> = set
            .plants
            .iter()
            .chain(&set.specs)
            .chain(&set.supervisors)
            .flat_map(|a| &a.events)
            .map(|e| e.name.as_str())
            .collect();
        let mut problems = Vec::new();
        for (event, o) in &self.events {
            let at =
                line_of(&self.file, &format!("events.{event}")).map_or(String::new(), |l| format!("{l}: "));
            if !all.contains(event.as_str()) {
                let hint = did_you_mean(event, all.iter().copied());
                problems.push(format!("{at}events.{event}: no automaton of the set has this event{hint}"));
            } else if let Some(plant) = set.plants.iter().find(|p| o.plantless && p.event_id(event).is_some())
            {
                problems.push(format!(
                    "{at}events.{event}: declared plant-less, but plant '{}' has it",
                    plant.name
                ));
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(ManifestError::Events { file: self.file.clone(), problems })
        }
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
        assert!(err.ends_with("events.zz: no automaton of the set has this event"), "{err}");
    }

    #[test]
    fn a_timer_is_a_plant_of_the_set_and_one_that_does_not_fit_is_refused_with_its_line() {
        let cylinder: PathBuf =
            [env!("CARGO_MANIFEST_DIR"), "..", "examples", "cylinder", "cylinder.toml"].iter().collect();
        let m = Manifest::load(&cylinder).unwrap();
        assert_eq!(m.timers.len(), 1);
        assert_eq!((m.timers[0].ms, m.timers[0].timeout_event()), (2000, "ext_timeout".to_owned()));
        let set = m.read_automata().unwrap();
        let t = set.plants.iter().find(|a| a.name == "T_ext").expect("the timer is a plant");
        let controllable = |n: &str| t.events[t.event_id(n).unwrap().index()].controllable;
        assert!(controllable("extend") && controllable("retract"));
        assert!(!controllable("at_end") && !controllable("ext_timeout"));
        let text = "name = \"x\"\nplants = [\"plants/cylinder.gen\"]\n\n[[timers]]\nname = \"T\"\n\
                    start = [\"extnd\"]\ntimeout = \"at_home\"\nms = 0\n";
        let err = Manifest::parse(&cylinder, text).unwrap().read_automata().unwrap_err().to_string();
        assert!(err.contains("4: timers[0].ms: a timeout of 0 ms"), "{err}");
        assert!(err.contains("timers[0].start: no automaton of the set has the event 'extnd'"), "{err}");
        assert!(err.contains("plant 'cylinder' has 'at_home' too"), "{err}");
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
