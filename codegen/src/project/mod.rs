//! The pipeline, owned in one place: a manifest (or model files named one by one) → models →
//! supervisors → tables → emitted source → firmware image. Every command that runs more than one stage
//! goes through here, so two commands cannot build the same project two ways.
//!
//! | stage | type | function |
//! |---|---|---|
//! | manifest | [`Manifest`] | [`Manifest::load`] |
//! | models | [`ModelSet`] | [`Manifest::read_automata`], [`ModelSet::from_files`] |
//! | supervisors | [`ModelSet`] with every supervisor | [`supervisors`] |
//! | supervisor set | [`PackSet`] | [`supervisor_set`] |
//! | tables | [`Packed`] (`ranked`) | [`Project::tables`] |
//! | emitted source | `String` | [`Project::emit`] |
//! | firmware image | an ELF | [`Project::image`] (QEMU), [`Project::pico_image`] |
//! | tables at build time | `$OUT_DIR/tables.rs` | [`build_script::main`] (a project's `build.rs`) |
//! | a project of the user's own | a directory | [`new_project::new_project`] (`codegen new`) |
//! | its ELF and manifest | [`user_project::UserProject`] | [`user_project::UserProject::open`], `build` (`run`/`plant --project`) |
//!
//! A [`Project`] carries a supervisor set with what the later stages need besides it: its name, the
//! run-time configuration, the board's pin map and where it came from (the emitted header's inputs and
//! command). [`comparison`] runs the other two architectures of the same problem for the size report.

pub mod build_script;
pub mod comparison;
pub mod new_project;
mod sources;
pub mod user_project;

pub use sources::{Loaded, Sources};

use std::path::{Path, PathBuf};

use crate::config::{BoardSpec, Mode, PlcSpec, RuntimeConfig, ScanPolicy, Signals, StateSpec};
use crate::emit::{self, EmitError};
use crate::manifest::{is_manifest, read_board, ManifestError, ModelSet};
use crate::model::Automaton;
use crate::pack::ranked::{self, Packed};
use crate::pack::{PackError, PackSet};
use crate::plc::state_based::guards::GuardProgram;
use crate::plc::state_based::{self, StateError};
use crate::plc::{self, Avalanche, Encoding, PlcError, PlcOptions};
use crate::provenance::{Input, Provenance};
use crate::symbolic::{self, Guards};
use crate::synth::{local_modular, Config, Supervisor, SynthError};
use crate::target::image::{build_pico_image, build_qemu_image, ImageError};

/// A supervisor set with everything the tables, the firmware build and the closed loop need.
#[derive(Clone, Debug)]
pub struct Project {
    /// Name of the set (the manifest's `name`).
    pub name: String,
    /// Plants first, then supervisors, over the event numbering the firmware uses.
    pub set: PackSet,
    /// The run-time configuration the tables carry; tests change it before [`Project::emit`].
    pub runtime: RuntimeConfig,
    /// Pin map of a real board, if any.
    pub board: Option<BoardSpec>,
    /// I/O map, policy and cycle of the PLC program (`[plc]`), if any.
    pub plc: Option<PlcSpec>,
    /// The plant's state vectors for a state-based program (`[state]`), if any.
    pub state: Option<StateSpec>,
    /// Components of Supremica modules given in a role of another kind, left out (`module: name (kind)`).
    pub left_out: Vec<String>,
    origin: Origin,
    /// Every input file with its SHA-256, in the order read.
    inputs: Vec<Input>,
}

/// Where a project came from, for the command its emitted header records.
#[derive(Clone, Debug)]
enum Origin {
    /// A manifest, with the run-time configuration it gave.
    Manifest { path: PathBuf, runtime: RuntimeConfig },
    /// Modules and model files (`codegen emit a.wmod b.wmod`, `--plant … --spec … --sup …`).
    Files { sources: Sources, board: Option<PathBuf> },
    /// Automata built in code.
    Code,
}

/// A project could not be put together or carried through a stage.
#[derive(Debug, thiserror::Error)]
pub enum ProjectError {
    /// The manifest, a model file it names or one named on the command line is bad, or the files do
    /// not fit together.
    #[error(transparent)]
    Manifest(#[from] ManifestError),
    /// A manifest given together with other files: a manifest is a whole project.
    #[error("{}: a manifest is a whole project: give it alone, or name its model files instead", file.display())]
    ManifestAmongFiles {
        /// The manifest.
        file: PathBuf,
    },
    /// An input file could not be read to hash it, or the emitted tables could not be written.
    #[error("{}: {source}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The manifest names neither supervisors nor specifications to synthesise them from.
    #[error("{}: no supervisors and no specifications to synthesise them from", file.display())]
    Nothing {
        /// The manifest file.
        file: PathBuf,
    },
    /// Synthesis failed.
    #[error("synthesis: {0}")]
    Synth(#[from] SynthError),
    /// The set cannot be packed.
    #[error(transparent)]
    Pack(#[from] PackError),
    /// The tables cannot be emitted.
    #[error(transparent)]
    Emit(#[from] EmitError),
    /// The firmware did not build.
    #[error(transparent)]
    Image(#[from] ImageError),
    /// The state-based program cannot be written.
    #[error("{}: {source}", file.display())]
    State {
        /// The manifest (or the set's name without one).
        file: PathBuf,
        /// Why (boxed: the other stages' errors are small).
        source: Box<StateError>,
    },
}

/// The supervisors stage: `models` with every supervisor its set runs — the ready supervisors first,
/// then the local modular supervisors synthesised from its specifications (none without
/// specifications).
pub fn supervisors(models: ModelSet) -> Result<ModelSet, ProjectError> {
    Ok(synthesise(models, &Config::default())?.0)
}

/// The supervisors stage under `cfg`, with the synthesised supervisors as synthesis gave them (each
/// with the plants and specifications it was built from, which name its states' positions).
pub fn synthesise(mut models: ModelSet, cfg: &Config) -> Result<(ModelSet, Vec<Supervisor>), ProjectError> {
    if models.specs.is_empty() {
        return Ok((models, Vec::new()));
    }
    let result = local_modular(&models.plants, &models.specs, cfg)?;
    models.supervisors.extend(result.supervisors.iter().map(|s| s.automaton.clone()));
    Ok((models, result.supervisors))
}

/// Loaded models → supervisor set: the models with their supervisors ([`supervisors`]), plants first,
/// over one event numbering.
pub fn supervisor_set(loaded: &Loaded) -> Result<PackSet, ProjectError> {
    supervisor_set_with(loaded, &Config::default())
}

/// [`supervisor_set`] with the supervisors synthesised under `cfg` (its limits, its conflict check).
pub fn supervisor_set_with(loaded: &Loaded, cfg: &Config) -> Result<PackSet, ProjectError> {
    let models = synthesise(loaded.models.clone(), cfg)?.0;
    if models.supervisors.is_empty() && models.plants.is_empty() {
        let file = loaded.inputs.first().cloned().unwrap_or_default();
        return Err(ProjectError::Nothing { file });
    }
    Ok(PackSet::new(models.plants, models.supervisors)?)
}

/// The command-line words of a state-based program's choice policy (` --choice POLICY`, or none).
fn choice_flag(choice: Option<ScanPolicy>) -> String {
    choice.map(|p| format!(" --choice {}", p.name())).unwrap_or_default()
}

/// Reads and hashes `path`.
fn hash(path: &Path) -> Result<Input, ProjectError> {
    Input::read(path).map_err(|source| ProjectError::File { path: path.to_owned(), source })
}

impl Project {
    /// The project of the manifest at `path`: its supervisor set ([`supervisor_set`]), `[runtime]` and
    /// `[board]`, and the hashes of the manifest and every model file it names.
    pub fn load(path: &Path) -> Result<Project, ProjectError> {
        Project::load_with(path, &Config::default())
    }

    /// [`Project::load`] with the supervisors synthesised under `cfg` (for example with the symbolic
    /// conflict check, when the supervisors' product is too large to build state by state).
    pub fn load_with(path: &Path, cfg: &Config) -> Result<Project, ProjectError> {
        if !is_manifest(path) {
            return Err(ManifestError::NotAProject { file: path.to_owned() }.into());
        }
        let loaded = Sources::project(&[path.to_owned()]).load()?;
        let set = supervisor_set_with(&loaded, cfg)?;
        let inputs = loaded.inputs.iter().map(|f| hash(f)).collect::<Result<_, _>>()?;
        let Some(m) = loaded.manifest else {
            return Err(ManifestError::NotAProject { file: path.to_owned() }.into());
        };
        Ok(Project {
            set,
            origin: Origin::Manifest { path: path.to_owned(), runtime: m.runtime.clone() },
            name: m.name,
            runtime: m.runtime,
            board: m.board,
            plc: m.plc,
            state: m.state,
            left_out: Vec::new(),
            inputs,
        })
    }

    /// The project of model files: `plants` and ready `supervisors` in these roles (see
    /// [`Project::from_sources`]).
    pub fn from_files(
        name: &str,
        plants: &[PathBuf],
        supervisors: &[PathBuf],
        board: Option<&Path>,
        runtime: RuntimeConfig,
    ) -> Result<Project, ProjectError> {
        let sources =
            Sources { plants: plants.to_vec(), supervisors: supervisors.to_vec(), ..Sources::default() };
        Project::from_sources(name, &sources, board, runtime)
    }

    /// The project of `sources` as every command that takes files reads them ([`Sources::load`]): a
    /// lone manifest (or module) is [`Project::load`]; otherwise modules and model files, one project,
    /// the local modular supervisors synthesised where it has specifications ([`supervisor_set`]), named
    /// `name`, with the pin map `board` and `runtime`.
    pub fn from_sources(
        name: &str,
        sources: &Sources,
        board: Option<&Path>,
        runtime: RuntimeConfig,
    ) -> Result<Project, ProjectError> {
        if let (Some(path), None) = (sources.manifest(), board) {
            return Project::load(path);
        }
        let loaded = sources.load()?;
        let set = supervisor_set(&loaded)?;
        let mut inputs: Vec<Input> = loaded.inputs.iter().map(|f| hash(f)).collect::<Result<_, _>>()?;
        let board_spec = match board {
            Some(path) => {
                inputs.push(hash(path)?);
                Some(read_board(path)?)
            }
            None => None,
        };
        Ok(Project {
            name: name.to_owned(),
            set,
            runtime,
            board: board_spec,
            plc: None,
            state: None,
            left_out: loaded.left_out,
            origin: Origin::Files { sources: sources.clone(), board: board.map(Path::to_path_buf) },
            inputs,
        })
    }

    /// A project from automata built in code, with `runtime`.
    pub fn new(
        name: &str,
        plants: Vec<Automaton>,
        supervisors: Vec<Automaton>,
        runtime: RuntimeConfig,
    ) -> Result<Project, PackError> {
        Ok(Project {
            name: name.to_owned(),
            set: PackSet::new(plants, supervisors)?,
            runtime,
            board: None,
            plc: None,
            state: None,
            left_out: Vec::new(),
            origin: Origin::Code,
            inputs: Vec::new(),
        })
    }

    /// The command that reproduces the emitted tables, paths as given, every option spelt out.
    pub fn command(&self) -> String {
        let r = &self.runtime;
        let words = match &self.origin {
            Origin::Manifest { path, runtime } => {
                let mut line = format!("codegen emit {} --reseed-every {}", path.display(), r.reseed_every);
                if let Some(layout) = r.layout.filter(|_| r.layout != runtime.layout) {
                    line.push_str(&format!(" --layout {layout}"));
                }
                let same =
                    RuntimeConfig { reseed_every: runtime.reseed_every, layout: runtime.layout, ..r.clone() };
                if *runtime != same {
                    line.push_str(" (then its [runtime] changed in code)");
                }
                line
            }
            Origin::Files { sources, board } => {
                let mut words = vec![String::from("codegen emit"), format!("--name {}", self.name)];
                words.extend(sources.words());
                words.push(format!("--policy {}", r.policy));
                words.push(format!("--seed {}", r.seed));
                words.push(format!("--guard {}", r.guard));
                words.push(format!("--on-fault {}", r.on_fault));
                words.push(format!("--input-buffer {}", r.input_buffer));
                words.push(format!("--reseed-every {}", r.reseed_every));
                if let Some(layout) = r.layout {
                    words.push(format!("--layout {layout}"));
                }
                if let Some(board) = board {
                    words.push(format!("--board {}", board.display()));
                }
                words.join(" ")
            }
            Origin::Code => format!("closed loop of '{}' (automata built in code)", self.name),
        };
        words.replace('\\', "/")
    }

    /// Every input file as given (the manifest first, then the model files it names), in the order read.
    pub fn input_paths(&self) -> Vec<String> {
        self.inputs.iter().map(|i| i.path.clone()).collect()
    }

    /// The tables stage: the set in the firmware's `ranked` layout.
    pub fn tables(&self) -> Result<Packed, PackError> {
        ranked::encode(&self.set)
    }

    /// The set in the `indexed` layout the Cortex-M0+ runs, or why it does not fit.
    pub fn m0plus_tables(&self) -> Result<Packed, PackError> {
        ranked::encode_indexed(&self.set)
    }

    /// The emitted-source stage: the Rust tables the firmware includes (`SCT_TABLES`), under a header
    /// naming every input with its hash and the command that reproduces them. Event-based
    /// (`[runtime] mode = "event"`): the set in the layouts of [`RuntimeConfig::layouts`] (the
    /// Cortex-M0+'s falls back to the Cortex-M3's when it does not fit). State-based (`mode = "state"`):
    /// the state feedback of the `[state]` section as cubes over the signal word, no supervisor tables
    /// ([`emit::state::firmware_tables`]).
    pub fn emit(&self) -> Result<String, ProjectError> {
        let provenance = Provenance { inputs: self.inputs.clone(), command: self.command() };
        if self.runtime.mode == Mode::State {
            let signals = self.state.as_ref().ok_or(StateError::Missing).and_then(|s| Ok(s.check()?));
            return signals
                .and_then(|signals| {
                    emit::state::firmware_tables(&self.set, signals, &self.name, &self.runtime, &provenance)
                })
                .map_err(|e| self.in_file(e));
        }
        let (m3, m0) = self.runtime.layouts();
        let tables = ranked::encode_as(&self.set, m3.firmware()).map_err(EmitError::from)?;
        let m0plus = ranked::encode_as(&self.set, m0.firmware());
        let m0plus = m0plus.as_ref().map_err(|e| format!("the {m0} layout does not fit: {e}"));
        Ok(emit::emit(&tables, m0plus, &self.name, &self.runtime, self.board.as_ref(), &provenance)?)
    }

    /// The PLC stage: the Structured Text and PLCopen XML program of the set with its report, under the
    /// same provenance header as the tables. The policy is `policy` when given, else the manifest's
    /// (`[plc]`, else `[runtime]` when it has a scan-cycle form), else local-queue for model files.
    pub fn plc(
        &self,
        encoding: Encoding,
        avalanche: Avalanche,
        policy: Option<ScanPolicy>,
    ) -> Result<plc::Output, PlcError> {
        self.plc_beside(encoding, avalanche, policy, None)
    }

    /// [`Project::plc`], with the sequence `net` (bound to the set's events) beside the interlocks in
    /// one program when given ([`plc::generate_with_sequence`]).
    pub fn plc_beside(
        &self,
        encoding: Encoding,
        avalanche: Avalanche,
        policy: Option<ScanPolicy>,
        net: Option<&crate::net::Interpretation>,
    ) -> Result<plc::Output, PlcError> {
        let fallback = match self.origin {
            Origin::Manifest { .. } => None,
            Origin::Files { .. } | Origin::Code => Some(ScanPolicy::LocalQueue),
        };
        let opts = PlcOptions {
            encoding,
            avalanche,
            ..PlcOptions::new(&self.name, &self.runtime, self.plc.as_ref(), policy.or(fallback))?
        };
        let provenance = Provenance { inputs: self.inputs.clone(), command: self.plc_command(&opts) };
        match net {
            Some(net) => plc::generate_with_sequence(&self.set, &opts, &provenance, net),
            None => plc::generate(&self.set, &opts, &provenance),
        }
    }

    /// The state-based PLC program of the set (`--encoding state`): its `[state]` section's state
    /// vectors, memory allowed, F_σ exact and one command per scan as `choices` (or the `[state]`
    /// keys) say, the event-based program's figures beside. Errors name the manifest.
    pub fn state_plc(&self, choices: state_based::StateOptions) -> Result<state_based::Output, ProjectError> {
        let choice = choice_flag(choices.choice);
        let flags = [(choices.memory, " --memory"), (choices.exact, " --exact"), (true, choice.as_str())];
        let (signals, opts, provenance) = self.state_setup(&flags).map_err(|e| self.in_file(e))?;
        let event_based = self.plc(Encoding::Int, Avalanche::Auto, None).ok();
        let report = event_based.as_ref().map(|o| &o.report);
        state_based::generate(&self.set, signals, &opts, choices, &provenance, report)
            .map_err(|e| self.in_file(e))
    }

    /// The state-based program from guards read off the symbolic engine's BDDs (`--engine symbolic`):
    /// the monolithic supervisor of the manifest's plants and specifications synthesised on BDDs
    /// ([`Guards`]), F_σ per controllable event rewritten over the `[state]` signals, F_σ exact and one
    /// command per scan as `choices` (or the `[state]` keys) say; `choices.memory` is not read (a program
    /// from guards keeps no memory). Needs a manifest with specifications; the supervisor's memory
    /// deciding somewhere is [`StateError::Memory`].
    pub fn state_plc_guards(
        &self,
        choices: state_based::StateOptions,
        cfg: &Config,
        options: &symbolic::Options,
    ) -> Result<(GuardProgram, Guards), ProjectError> {
        let Origin::Manifest { path, .. } = &self.origin else {
            return Err(ManifestError::NotAProject { file: PathBuf::from(&self.name) }.into());
        };
        let models = Sources::project(std::slice::from_ref(path)).load()?.models;
        if models.specs.is_empty() {
            return Err(ProjectError::Nothing { file: path.clone() });
        }
        let choice = choice_flag(choices.choice);
        let flags = [(choices.exact, " --exact"), (true, " --engine symbolic"), (true, choice.as_str())];
        let (signals, opts, provenance) = self.state_setup(&flags).map_err(|e| self.in_file(e))?;
        let guards = Guards::compute(&models.plants, &models.specs, cfg, options)?;
        let both = (choices.exact, choices.choice);
        let program = state_based::guards::generate(&self.set, signals, &guards, &opts, both, &provenance)
            .map_err(|e| self.in_file(e))?;
        Ok((program, guards))
    }

    /// A state-based program's error, in the manifest (or the set's name without one).
    fn in_file(&self, source: StateError) -> ProjectError {
        let file = match &self.origin {
            Origin::Manifest { path, .. } => path.clone(),
            Origin::Files { .. } | Origin::Code => PathBuf::from(&self.name),
        };
        ProjectError::State { file, source: Box::new(source) }
    }

    /// The checked `[state]` signals, the PLC options and the provenance of a state-based program whose
    /// command adds the words of the `flags` that are set.
    fn state_setup(&self, flags: &[(bool, &str)]) -> Result<(Signals, PlcOptions, Provenance), StateError> {
        let signals = self.state.as_ref().ok_or(StateError::Missing).and_then(|s| Ok(s.check()?))?;
        let opts = PlcOptions::new(&self.name, &self.runtime, self.plc.as_ref(), Some(ScanPolicy::First))
            .map_err(|e| StateError::Vector { key: "plc".into(), message: e.to_string() })?;
        let mut words = self.plc_command(&opts);
        words.truncate(words.find(" --encoding").unwrap_or(words.len()));
        words.push_str(" --encoding state");
        for (_, word) in flags.iter().filter(|(on, _)| *on) {
            words.push_str(word);
        }
        Ok((signals, opts, Provenance { inputs: self.inputs.clone(), command: words }))
    }

    /// The command that reproduces a PLC program, paths as given, every option spelt out.
    fn plc_command(&self, opts: &PlcOptions) -> String {
        let mut words = vec![String::from("codegen plc")];
        match &self.origin {
            Origin::Manifest { path, .. } => words.push(path.display().to_string()),
            Origin::Files { sources, .. } => {
                words.push(format!("--name {}", self.name));
                words.extend(sources.words());
            }
            Origin::Code => words.push(format!("(automata of '{}' built in code)", self.name)),
        }
        words.push(format!("--encoding {}", opts.encoding.name()));
        words.push(format!("--avalanche {}", opts.avalanche.name()));
        words.push(format!("--policy {}", opts.policy.name()));
        words.join(" ").replace('\\', "/")
    }

    /// The firmware-image stage: emits the tables into `dir/tables.rs` and builds the QEMU firmware on
    /// them (`cell-qemu`, which runs supervisor tables and, with `mode = "state"`, state tables alike);
    /// returns the ELF, `dir/firmware.elf`.
    pub fn image(&self, dir: &Path) -> Result<PathBuf, ProjectError> {
        Ok(build_qemu_image(&self.tables_file(dir)?, &dir.join("firmware.elf"))?)
    }

    /// The same stage for the Raspberry Pi Pico: the tables, with the board's pin map, built into the
    /// Pico firmware (`cell-pico`); returns the ELF, `dir/firmware.elf`. State-based tables are refused
    /// ([`Project::for_board`]).
    pub fn pico_image(&self, dir: &Path) -> Result<PathBuf, ProjectError> {
        self.for_board()?;
        Ok(build_pico_image(&self.tables_file(dir)?, &dir.join("firmware.elf"))?)
    }

    /// Refuses `mode = "state"` for a board's application (the Pico image, a `codegen new` project's
    /// build script), naming the key: the board applications feed their pins' edges to the supervisor
    /// runtime, and none samples its pins into the state runtime's signal word yet, so the state tables
    /// would fail to compile there with no word of why.
    pub fn for_board(&self) -> Result<(), ProjectError> {
        if self.runtime.mode == Mode::State {
            return Err(self.in_file(StateError::Vector {
                key: "runtime.mode".into(),
                message: "the state-based firmware runs under QEMU (cell-qemu) only; the board \
                          applications feed their pins' edges to the supervisor runtime: use mode = \"event\" \
                          on a board"
                    .into(),
            }));
        }
        Ok(())
    }

    /// Emits the tables into `dir/tables.rs`.
    fn tables_file(&self, dir: &Path) -> Result<PathBuf, ProjectError> {
        let tables = dir.join("tables.rs");
        std::fs::write(&tables, self.emit()?)
            .map_err(|source| ProjectError::File { path: tables.clone(), source })?;
        Ok(tables)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn livelock_plant() -> PathBuf {
        [env!("CARGO_MANIFEST_DIR"), "..", "examples", "livelock", "livelock.xmd"].iter().collect()
    }

    /// A manifest in a scratch directory over the livelock plant, with `runtime` as its `[runtime]`.
    fn manifest(tag: &str, runtime: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("project-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.toml");
        let text = format!("name = \"m\"\nplants = [{:?}]\n[runtime]\n{runtime}\n", livelock_plant());
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn the_manifests_runtime_reaches_the_tables_and_the_command_reproduces_them() {
        let path = manifest("reseed", "reseed_every = 7\npolicy = \"first\"");
        let mut project = Project::load(&path).unwrap();
        assert_eq!((project.runtime.reseed_every, project.runtime.policy.to_string()), (7, "first".into()));
        let text = project.emit().unwrap();
        assert!(text.contains("    reseed_every: 7,\n"), "{text}");
        assert!(text.contains("pub type Policy = firmware::choice::First;"), "{text}");
        assert_eq!(project.command(), format!("codegen emit {} --reseed-every 7", path.display()));
        // `codegen emit MANIFEST --reseed-every N` overrides the manifest's period, and says so.
        project.runtime.reseed_every = 9;
        assert!(project.emit().unwrap().contains("    reseed_every: 9,\n"));
        assert!(project.command().ends_with("--reseed-every 9"));
        // Any other change made in code is flagged: the command alone no longer reproduces the tables.
        project.runtime.guard = false;
        assert!(project.command().ends_with("(then its [runtime] changed in code)"));
        std::fs::remove_dir_all(path.parent().unwrap()).ok();
    }

    #[test]
    fn an_input_that_cannot_be_read_is_an_error_not_an_empty_hash() {
        let missing = livelock_plant().with_file_name("missing.xmd");
        let err = hash(&missing).unwrap_err().to_string();
        assert!(err.starts_with(&missing.display().to_string()), "{err}");
        let err = Project::from_files("x", &[missing], &[], None, RuntimeConfig::default()).unwrap_err();
        assert!(matches!(err, ProjectError::Manifest(ManifestError::File(_))), "{err}");
    }
}
