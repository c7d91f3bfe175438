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
//! | tables | `pack::tables::Packed`, the layout each core runs | [`pack::fit::choose`](crate::pack::fit::choose) |
//! | emitted source | `String` | [`Project::emit`] |
//! | firmware image | an ELF | [`Project::image`] (QEMU), [`Project::pico_image`] |
//! | tables at build time | `$OUT_DIR/tables.rs` | [`build_script::main`] (a project's `build.rs`) |
//! | a project of the user's own | a directory | [`new_project::new_project`] (`codegen new`) |
//! | its ELF and manifest | [`user_project::UserProject`] | [`user_project::UserProject::open`], `build` (`run`/`plant --project`) |
//!
//! A [`Project`] carries a supervisor set with what the later stages need besides it: its name, the
//! run-time configuration, the board's pin map and where it came from (the emitted header's inputs and
//! command). [`comparison`] runs the other two architectures of the same problem for the size report.
//!
//! [`Manifest`]: crate::manifest::Manifest
//! [`Manifest::load`]: crate::manifest::Manifest::load
//! [`Manifest::read_automata`]: crate::manifest::Manifest::read_automata

pub mod build_script;
pub mod comparison;
pub mod hybrid;
pub mod new_project;
mod sources;
pub mod user_project;

pub use sources::{Loaded, Sources};

use std::path::{Path, PathBuf};

use crate::closed_loop::Options;
use crate::config::{
    BoardSpec, Mode, NetSpec, PlcSpec, RuntimeConfig, ScanPolicy, StateSpec, SupervisorChoice,
};
use crate::emit::{self, EmitError};
use crate::feedback::FeedbackError;
use crate::manifest::{is_manifest, read_board, Manifest, ManifestError, ModelSet};
use crate::maps::{self, Board, MapsError};
use crate::model::Automaton;
use crate::monitor::Report;
use crate::net::Interpretation;
use crate::pack::fit::{self, Core, Refusal};
use crate::pack::{PackError, PackSet, Role};
use crate::plc::closed_loop::RunError;
use crate::plc::state_based::{self, Engine};
use crate::plc::{self, Avalanche, Encoding, Form, PlcError, PlcOptions, Written};
use crate::provenance::{Input, Provenance};
use crate::symbolic::Guards;
use crate::synth::deploy::{self, Summary};
use crate::synth::{local_modular, Config, Supervisor, SynthError};
use crate::target::image::{
    build_pico_image, build_pico_link_image, build_pico_usb_image, build_qemu_image, ImageError,
};

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
    /// Timeouts (`[[timers]]`): their automata are among the plants; the runtimes take their delays.
    pub timers: Vec<crate::manifest::TimerSpec>,
    /// The variables, guards and actions of the manifest's Supremica modules that have any (as written,
    /// before unfolding): the PLC program keeps the variables and writes guards over them.
    pub efa: Vec<crate::formats::efa::Efa>,
    /// The plant's state vectors for a state-based program (`[state]`), if any.
    pub state: Option<StateSpec>,
    /// The sequence net that runs beside the interlocks in a PLC program (`[net]`), if any.
    pub net: Option<NetSpec>,
    /// The models as loaded, before synthesis (what the symbolic engine synthesises from).
    pub models: ModelSet,
    /// A hybrid controller's plant net and supervisor (a manifest with `[hybrid]`), if it is one.
    pub hybrid: Option<Hybrid>,
    /// Components of Supremica modules given in a role of another kind, left out (`module: name (kind)`).
    pub left_out: Vec<String>,
    /// Which supervisors the set holds ([`RuntimeConfig::supervisors`]), their sizes and the proof that
    /// they give the full set's closed loop; every report and the emitted provenance print it.
    pub deployed: Summary,
    origin: Origin,
    /// Every input file with its SHA-256, in the order read.
    inputs: Vec<Input>,
}

/// A hybrid controller's project: the plant net, and the supervisor synthesised against its
/// reachability graph (or the ready one, checked) — the set's one plant and one supervisor.
#[derive(Clone, Debug)]
pub struct Hybrid {
    /// The plant net, its labels and its reachability graph.
    pub plant: plc::hybrid::Plant,
    /// The supervisor, `SUPER`.
    pub supervisor: Automaton,
}

impl Hybrid {
    /// The net's reachability graph and `SUPER` as a set: what the hybrid controller's own run judges
    /// its firings by (it reads its sensors itself: the arrivals of the project's set are no events
    /// of it).
    pub fn net_set(&self) -> Result<PackSet, ProjectError> {
        Ok(PackSet::new(vec![self.plant.graph.clone()], vec![self.supervisor.clone()])?)
    }
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
    /// A map of the manifest (`[board]`, `[plc]`, `[state]`, `[net]`) does not fit the automata or the
    /// board: every problem, each with its line.
    #[error(transparent)]
    Maps(#[from] MapsError),
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
    /// The layout cannot hold the set, or its tables exceed what the board's flash leaves them.
    #[error(transparent)]
    Refused(#[from] Refusal),
    /// The firmware did not build.
    #[error(transparent)]
    Image(#[from] ImageError),
    /// The state-based firmware's tables cannot be written, or a board cannot run them.
    #[error("{}: {source}", file.display())]
    Feedback {
        /// The manifest (or the set's name without one).
        file: PathBuf,
        /// Why (boxed: the other stages' errors are small).
        source: Box<FeedbackError>,
    },
    /// A PLC program cannot be written.
    #[error(transparent)]
    Plc(Box<PlcError>),
    /// A PLC program's closed-loop run failed.
    #[error(transparent)]
    PlcRun(Box<RunError>),
}

impl From<RunError> for ProjectError {
    fn from(e: RunError) -> ProjectError {
        ProjectError::PlcRun(Box::new(e))
    }
}

impl From<PlcError> for ProjectError {
    fn from(e: PlcError) -> ProjectError {
        ProjectError::Plc(Box::new(e))
    }
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
    let choice = loaded.manifest.as_ref().map_or_else(SupervisorChoice::default, |m| m.runtime.supervisors);
    Ok(deployed_set(loaded, cfg, choice)?.0)
}

/// The set `choice` deploys ([`deploy::deploy`]): the full set of [`supervisor_set_with`] (ready
/// supervisors, then the synthesised ones), each supervisor reduced, or the monolithic supervisor, full
/// or reduced — proven to give the plants the full set's closed loop — with its summary.
pub fn deployed_set(
    loaded: &Loaded,
    cfg: &Config,
    choice: SupervisorChoice,
) -> Result<(PackSet, Summary), ProjectError> {
    let ready = loaded.models.supervisors.len();
    let (mut models, synthesised) = synthesise(loaded.models.clone(), cfg)?;
    if models.supervisors.is_empty() && models.plants.is_empty() {
        let file = loaded.inputs.first().cloned().unwrap_or_default();
        return Err(ProjectError::Nothing { file });
    }
    let full: Vec<Supervisor> = models.supervisors[..ready]
        .iter()
        .map(|a| deploy::ready(&models.plants, a))
        .chain(synthesised)
        .collect();
    let (chosen, summary) = deploy::deploy(&models.plants, &models.specs, full, choice, cfg)?;
    models.supervisors = chosen.into_iter().map(|s| s.automaton).collect();
    Ok((PackSet::new(models.plants, models.supervisors)?, summary))
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
        Project::load_from(path, cfg, None)
    }

    /// [`Project::load`] for a command that builds for `board`: the manifest's pins are checked
    /// against that board's ([`maps::check`]), whatever `[board] name` says.
    pub fn load_for(path: &Path, board: Board) -> Result<Project, ProjectError> {
        Project::load_from(path, &Config::default(), Some(board))
    }

    fn load_from(path: &Path, cfg: &Config, board: Option<Board>) -> Result<Project, ProjectError> {
        if !is_manifest(path) {
            return Err(ManifestError::NotAProject { file: path.to_owned() }.into());
        }
        let m = Manifest::load(path)?;
        if m.hybrid.is_some() {
            return Project::hybrid(m, cfg);
        }
        let choice = m.runtime.supervisors;
        let efa = m.read_efa()?;
        let loaded = Loaded::of_manifest(m, board)?;
        let (set, deployed) = deployed_set(&loaded, cfg, choice)?;
        let inputs = loaded.inputs.iter().map(|f| hash(f)).collect::<Result<_, _>>()?;
        let Some(m) = loaded.manifest else {
            return Err(ManifestError::NotAProject { file: path.to_owned() }.into());
        };
        Ok(Project {
            set,
            deployed,
            origin: Origin::Manifest { path: path.to_owned(), runtime: m.runtime.clone() },
            name: m.name,
            runtime: m.runtime,
            board: m.board,
            plc: m.plc,
            timers: m.timers,
            efa,
            state: m.state,
            net: m.net,
            models: loaded.models,
            hybrid: None,
            left_out: Vec::new(),
            inputs,
        })
    }

    /// The project of the hybrid manifest `m` ([`hybrid`]): the net's reachability graph the plant
    /// `SUPER` is synthesised against and the one supervisor; the set the event-based runtimes run has
    /// beside the graph the arrivals its controllable transitions wait for ([`hybrid::arrivals()`]: M1
    /// starts on a part, not whenever it is idle); its inputs the manifest, the net and the model files
    /// it names.
    fn hybrid(m: Manifest, cfg: &Config) -> Result<Project, ProjectError> {
        let plant = hybrid::plant(&m, cfg)?;
        let models = m.read_automata_over(vec![plant.graph.clone()])?;
        let supervisor = hybrid::supervisor(&m, &models, &plant, cfg)?;
        let plants = std::iter::once(plant.graph.clone()).chain(hybrid::arrivals(&m, &plant)?).collect();
        let set = PackSet::new(plants, vec![supervisor.clone()])?;
        let pnml = m.net.as_ref().map(|n| m.resolve(n.pnml.get_ref()));
        let named = m.plants.iter().chain(&m.specs).chain(&m.supervisors).map(|p| m.resolve(p));
        let inputs = std::iter::once(m.file.clone())
            .chain(pnml)
            .chain(named)
            .map(|f| hash(&f))
            .collect::<Result<_, _>>()?;
        Ok(Project {
            set,
            deployed: Summary::full(std::slice::from_ref(&supervisor)),
            origin: Origin::Manifest { path: m.file.clone(), runtime: m.runtime.clone() },
            name: m.name,
            runtime: m.runtime,
            board: m.board,
            plc: m.plc,
            timers: m.timers,
            efa: Vec::new(),
            state: m.state,
            net: None,
            models,
            hybrid: Some(Hybrid { plant, supervisor }),
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
            return Project::load_from(path, &Config::default(), sources.board);
        }
        let loaded = sources.load()?;
        let (set, deployed) = deployed_set(&loaded, &Config::default(), runtime.supervisors)?;
        let mut inputs: Vec<Input> = loaded.inputs.iter().map(|f| hash(f)).collect::<Result<_, _>>()?;
        let board_spec = match board {
            Some(path) => {
                inputs.push(hash(path)?);
                let (spec, lines) = read_board(path)?;
                maps::check_board(&spec, path, &lines, &loaded.models, sources.board)?;
                Some(spec)
            }
            None => None,
        };
        Ok(Project {
            name: name.to_owned(),
            set,
            deployed,
            runtime,
            board: board_spec,
            plc: None,
            timers: Vec::new(),
            efa: Vec::new(),
            state: None,
            net: None,
            models: loaded.models,
            hybrid: None,
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
        let models = ModelSet {
            plants: plants.clone(),
            specs: Vec::new(),
            supervisors: supervisors.clone(),
            sources: Vec::new(),
        };
        let deployed = Summary::full(&supervisors);
        Ok(Project {
            name: name.to_owned(),
            set: PackSet::new(plants, supervisors)?,
            deployed,
            runtime,
            board: None,
            plc: None,
            timers: Vec::new(),
            efa: Vec::new(),
            state: None,
            net: None,
            models,
            hybrid: None,
            left_out: Vec::new(),
            origin: Origin::Code,
            inputs: Vec::new(),
        })
    }

    /// Deploys the supervisors `choice` names instead of the ones the project was loaded with
    /// (`--supervisors`): the set is built again from the project's sources ([`deployed_set`]) and the
    /// run-time configuration records the choice.
    pub fn choose_supervisors(&mut self, choice: SupervisorChoice, cfg: &Config) -> Result<(), ProjectError> {
        if choice == self.deployed.choice {
            self.runtime.supervisors = choice;
            return Ok(());
        }
        let loaded = match &self.origin {
            Origin::Manifest { path, .. } => Sources::project(std::slice::from_ref(path)).load()?,
            Origin::Files { sources, .. } => sources.load()?,
            Origin::Code => {
                let of = |role| {
                    self.set.members().iter().filter(move |m| m.role == role).map(|m| m.automaton.clone())
                };
                Loaded {
                    name: self.name.clone(),
                    models: ModelSet {
                        plants: of(Role::Plant).collect(),
                        specs: Vec::new(),
                        supervisors: of(Role::Supervisor).collect(),
                        sources: Vec::new(),
                    },
                    manifest: None,
                    left_out: Vec::new(),
                    inputs: Vec::new(),
                }
            }
        };
        (self.set, self.deployed) = deployed_set(&loaded, cfg, choice)?;
        self.runtime.supervisors = choice;
        Ok(())
    }

    /// The provenance of a file this project writes with `command`.
    fn provenance(&self, command: String) -> Provenance {
        Provenance { inputs: self.inputs.clone(), command, supervisors: Some(self.deployed.to_string()) }
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
                if r.supervisors != runtime.supervisors {
                    line.push_str(&format!(" --supervisors {}", r.supervisors));
                }
                let same = RuntimeConfig {
                    reseed_every: runtime.reseed_every,
                    layout: runtime.layout,
                    supervisors: runtime.supervisors,
                    ..r.clone()
                };
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
                if r.supervisors != SupervisorChoice::Full {
                    words.push(format!("--supervisors {}", r.supervisors));
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

    /// The emitted-source stage: the Rust tables the firmware includes (`SCT_TABLES`), under a header
    /// naming every input with its hash and the command that reproduces them. Event-based
    /// (`[runtime] mode = "event"`): the set in the layouts of [`RuntimeConfig::layouts`] (refused when
    /// the Cortex-M3's layout cannot hold the set; the Cortex-M0+'s falls back to the Cortex-M3's tables
    /// when it does not fit the Pico, [`fit::choose`]). State-based (`mode = "state"`):
    /// the state feedback of the `[state]` section as cubes over the signal word, no supervisor tables
    /// ([`emit::state::firmware_tables`]). Both end with the manifest's timers ([`emit::timers`]; an
    /// empty table without `[[timers]]`), and with timers their `DIGEST`s cover them
    /// ([`emit::timers::seal`]).
    pub fn emit(&self) -> Result<String, ProjectError> {
        let events = self.set.events();
        let names: Vec<String> = events.ids().map(|e| events.name(e).to_owned()).collect();
        let timers = emit::timers::rust(&self.timers, &names)?;
        Ok(emit::timers::seal(self.emit_tables()? + &timers))
    }

    /// The tables of [`Project::emit`] before its timers.
    fn emit_tables(&self) -> Result<String, ProjectError> {
        let provenance = self.provenance(self.command());
        if self.runtime.mode == Mode::State {
            let signals = self.state.as_ref().ok_or(FeedbackError::Missing).and_then(|s| Ok(s.check()?));
            return signals
                .and_then(|signals| {
                    emit::state::firmware_tables(&self.set, signals, &self.name, &self.runtime, &provenance)
                })
                .map_err(|e| self.feedback(e));
        }
        let (m3, m0) = self.runtime.layouts();
        let tables = fit::fit(&self.set, m3, None)?.packed;
        let m0plus = fit::fit(&self.set, m0, Some(&Core::CortexM0Plus.flash()));
        let m0plus = match &m0plus {
            Ok(fitted) if fitted.layout != m3 => Ok(&fitted.packed),
            Ok(_) => Err(String::from("the Cortex-M3's tables: the manifest names one layout for both")),
            Err(refusal) => Err(refusal.to_string()),
        };
        Ok(emit::emit(&tables, m0plus, &self.name, &self.runtime, self.board.as_ref(), &provenance)?)
    }

    /// The digests of the tables [`Project::emit`] writes (`DIGEST`: the Cortex-M3's image and the
    /// Cortex-M0+'s, or the state tables'): what a firmware built from this project answers the link's
    /// TABLES with, and what `codegen plant` and `codegen run` hold it to ([`crate::closed_loop::Options`]).
    pub fn table_digests(&self) -> Result<Vec<String>, ProjectError> {
        Ok(emit::digests(&self.emit()?))
    }

    /// The event-based program of [`Project::plc`] (`Form::Event`), with the manifest's sequence net
    /// beside it when it has one.
    fn event_program(
        &self,
        encoding: Encoding,
        avalanche: Avalanche,
        policy: Option<ScanPolicy>,
    ) -> Result<plc::Output, ProjectError> {
        let file = self.file();
        let opts = PlcOptions { encoding, avalanche, ..self.plc_options(policy)? };
        let provenance = self.plc_provenance(&opts.words());
        let out = match self.sequence()? {
            Some(net) => {
                let mut provenance = provenance;
                if let Some(spec) = &self.net {
                    let pnml = file.parent().unwrap_or(Path::new("")).join(spec.pnml.get_ref());
                    provenance.inputs.push(hash(&pnml)?);
                }
                plc::generate_with_sequence(&self.set, &opts, &provenance, &net)?
            }
            None => plc::generate(&self.set, &opts, &provenance)?,
        };
        Ok(out)
    }

    /// The PLC program run closed loop (`codegen run --target plc`): the event-based program in
    /// `encoding` (the manifest's policy, its sequence beside it), its `.st` text under the interpreter
    /// against the virtual plant, judged by plants ‖ supervisors as a firmware's run is
    /// ([`plc::closed_loop::run`]).
    pub fn run_plc(
        &self,
        encoding: Encoding,
        options: &Options,
        progress: &mut dyn FnMut(&Report),
    ) -> Result<Report, ProjectError> {
        let out = self.event_program(encoding, Avalanche::Auto, None)?;
        let text = out.files.first().map_or("", |(_, text)| text.as_str());
        let net = self.sequence()?.map(|net| plc::net_drive::NetDrive::new(&net));
        Ok(plc::closed_loop::run_net(
            text,
            &out.report,
            &self.set,
            &self.name,
            net.as_ref(),
            options,
            progress,
        )?)
    }

    /// The state-based program run closed loop (`codegen run --target plc --encoding state`): the
    /// program `codegen plc --encoding state` writes from the manifest's `[state]` section (its
    /// memory and choice policy), under the interpreter against the virtual plant, its signals driven
    /// through the same state vectors ([`state_based::closed_loop::run`]).
    pub fn run_plc_state(
        &self,
        options: &Options,
        progress: &mut dyn FnMut(&Report),
    ) -> Result<Report, ProjectError> {
        let form = Form::State { options: state_based::StateOptions::default(), engine: Engine::Explicit };
        let out = self.plc(&form)?.into_state().ok_or(RunError::Program("no state-based program".into()))?;
        Ok(state_based::closed_loop::run(&out, &self.set, &self.name, options, progress)?)
    }

    /// A hybrid controller run closed loop (`codegen run --target plc` on a `[hybrid]` manifest): the
    /// program `codegen plc` writes with the reduced supervisor (or the full one, `full`), under the
    /// interpreter against the plant net's own token game, judged by the net's reachability graph ‖
    /// `SUPER` ([`plc::hybrid::closed_loop::run`]).
    pub fn run_plc_hybrid(
        &self,
        full: bool,
        options: &Options,
        progress: &mut dyn FnMut(&Report),
    ) -> Result<Report, ProjectError> {
        let h = self.hybrid.as_ref().ok_or_else(|| PlcError::Sections { file: self.file() })?;
        let out =
            self.plc(&Form::Hybrid)?.into_hybrid().ok_or(RunError::Program("no hybrid controller".into()))?;
        let source =
            out.sources.get(usize::from(full)).ok_or(RunError::Program("no hybrid controller".into()))?;
        let file = format!("{}.st", source.program.base);
        let text = out.files.iter().find(|(n, _)| *n == file).map_or("", |(_, text)| text.as_str());
        let program = plc::hybrid::closed_loop::Program {
            text,
            bound_per_scan: source.program.pous.iter().map(|(pou, _)| pou.bound()).sum(),
            cycle_ms: source.program.cycle_ms,
        };
        let set = h.net_set()?;
        Ok(plc::hybrid::closed_loop::run(program, &h.plant, &set, &self.name, options, progress)?)
    }

    /// The PLC stage, the one entry of every form ([`Form`]): the program's files under a header naming
    /// every input with its hash and the command that reproduces them, and its report. The event-based
    /// form runs the manifest's sequence net beside the interlocks when it has one (`[net]`); its policy
    /// is the form's when given, else the manifest's (`[plc]`, else `[runtime]` when it has a scan-cycle
    /// form), else random (the scan-cycle form of the random queues). The state-based form reads the `[state]` section (its
    /// report compares the event-based program's size); the hybrid form needs a `[hybrid]` manifest.
    pub fn plc(&self, form: &Form) -> Result<Written, ProjectError> {
        let file = self.file();
        let untimed = match form {
            Form::Hybrid => Some("hybrid controller"),
            Form::State { .. } => Some("state-based program"),
            Form::Event { .. } => None,
        };
        if let Some(form) = untimed.filter(|_| !self.timers.is_empty()) {
            return Err(PlcError::Timers { file, form }.into());
        }
        match form {
            Form::Hybrid => {
                let h = self.hybrid.as_ref().ok_or_else(|| PlcError::Sections { file: file.clone() })?;
                let cycle = self.plc.as_ref().and_then(|p| p.cycle_ms).unwrap_or(10);
                let provenance = self.plc_provenance(&[]);
                let out = plc::hybrid::generate(
                    &h.plant,
                    &h.supervisor,
                    &self.name,
                    cycle,
                    &provenance,
                    &Config::default(),
                )?;
                Ok(Written::Hybrid(out))
            }
            Form::Event { encoding, avalanche, policy } => {
                Ok(Written::Event(self.event_program(*encoding, *avalanche, *policy)?))
            }
            Form::State { options, engine } => {
                let in_file = |source| PlcError::Feedback { file: file.clone(), source: Box::new(source) };
                let signals = self.state.as_ref().ok_or(FeedbackError::Missing).and_then(|s| Ok(s.check()?));
                let signals = signals.map_err(in_file)?;
                let opts = self.plc_options(Some(ScanPolicy::First)).map_err(|e| {
                    in_file(FeedbackError::Vector { key: "plc".into(), message: e.to_string() })
                })?;
                let provenance = self.plc_provenance(&options.words(engine));
                match engine {
                    Engine::Explicit => {
                        let event_based = self.plc_options(None).ok().and_then(|o| {
                            plc::event_figures(&self.set, &PlcOptions { encoding: Encoding::Int, ..o }).ok()
                        });
                        let out = state_based::generate(
                            &self.set,
                            signals,
                            &opts,
                            *options,
                            &provenance,
                            event_based,
                            &file,
                        )?;
                        Ok(Written::State(out))
                    }
                    Engine::Symbolic { cfg, options: symbolic } => {
                        if self.models.specs.is_empty() {
                            return Err(ProjectError::Nothing { file });
                        }
                        let guards = Guards::compute(&self.models.plants, &self.models.specs, cfg, symbolic)?;
                        let out = state_based::from_guards(
                            &self.set,
                            signals,
                            &guards,
                            &opts,
                            *options,
                            &provenance,
                            &file,
                        )?;
                        Ok(Written::Symbolic(out))
                    }
                }
            }
        }
    }

    /// The sequence net of the project's `[net]` section bound to its set's events, if it has one.
    pub fn sequence(&self) -> Result<Option<Interpretation>, ProjectError> {
        let Some(spec) = &self.net else { return Ok(None) };
        let automata: Vec<_> = self.set.members().iter().map(|m| &m.automaton).collect();
        let net = crate::net::interpretation(spec, &self.file(), &automata).map_err(PlcError::from)?;
        Ok(Some(net))
    }

    /// The event-based program's options: the policy `policy` when given, else the manifest's, else
    /// random.
    fn plc_options(&self, policy: Option<ScanPolicy>) -> Result<PlcOptions, PlcError> {
        let opts = PlcOptions::new(&self.name, &self.runtime, self.plc.as_ref(), policy)?;
        Ok(PlcOptions { timers: self.timers.clone(), efa: self.efa.clone(), ..opts })
    }

    /// The manifest, or the set's name without one: what errors of the project name.
    fn file(&self) -> PathBuf {
        match &self.origin {
            Origin::Manifest { path, .. } => path.clone(),
            Origin::Files { .. } | Origin::Code => PathBuf::from(&self.name),
        }
    }

    /// A state feedback's error, in the manifest (or the set's name without one).
    fn feedback(&self, source: FeedbackError) -> ProjectError {
        ProjectError::Feedback { file: self.file(), source: Box::new(source) }
    }

    /// The provenance of a PLC program written with the form's command-line words `form`: every input
    /// with its hash, the command that reproduces it (paths as given, every option spelt out).
    fn plc_provenance(&self, form: &[String]) -> Provenance {
        let mut words = vec![String::from("codegen plc")];
        match &self.origin {
            Origin::Manifest { path, .. } => words.push(path.display().to_string()),
            Origin::Files { sources, .. } => {
                words.push(format!("--name {}", self.name));
                words.extend(sources.words());
            }
            Origin::Code => words.push(format!("(automata of '{}' built in code)", self.name)),
        }
        let manifest_choice = match &self.origin {
            Origin::Manifest { runtime, .. } => runtime.supervisors,
            Origin::Files { .. } | Origin::Code => SupervisorChoice::Full,
        };
        if self.runtime.supervisors != manifest_choice {
            words.push(format!("--supervisors {}", self.runtime.supervisors));
        }
        words.extend(form.iter().cloned());
        self.provenance(words.join(" ").replace('\\', "/"))
    }

    /// The firmware-image stage: emits the tables into `dir/tables.rs` and builds the QEMU firmware on
    /// them (`cell-qemu`, which runs supervisor tables and, with `mode = "state"`, state tables alike);
    /// returns the ELF, `dir/firmware.elf`. Tables that do not fit the lm3s6965's flash are refused
    /// first ([`Project::fit`]).
    pub fn image(&self, dir: &Path) -> Result<PathBuf, ProjectError> {
        self.fit(Core::CortexM3, &Core::CortexM3.flash())?;
        Ok(build_qemu_image(&self.tables_file(dir)?, &dir.join("firmware.elf"))?)
    }

    /// Refuses, before anything is built, a set whose tables the firmware for `core` cannot run within
    /// `flash` (its layout's limits, or more bytes than the flash leaves the tables), naming the layout,
    /// the size, the limit and what would fit. The state tables (`mode = "state"`) are checked by their
    /// own writer.
    pub fn fit(&self, core: Core, flash: &crate::target::flash::Flash) -> Result<(), ProjectError> {
        if self.runtime.mode == Mode::Event {
            fit::choose(&self.set, &self.runtime, core, Some(flash))?;
        }
        Ok(())
    }

    /// The same stage for the Raspberry Pi Pico: the tables, with the board's pin map, built into the
    /// Pico firmware (`cell-pico`); returns the ELF, `dir/firmware.elf`. State-based tables are refused
    /// ([`Project::for_board`]).
    pub fn pico_image(&self, dir: &Path) -> Result<PathBuf, ProjectError> {
        self.for_board()?;
        self.fit(Core::CortexM0Plus, &Core::CortexM0Plus.flash())?;
        Ok(build_pico_image(&self.tables_file(dir)?, &dir.join("firmware.elf"))?)
    }

    /// Builds the Pico's link build on this project's tables in `dir` (the supervisors driven over UART0
    /// by `codegen plant --connect serial:…`); returns the ELF. As [`Project::pico_image`], but no
    /// `[board]` pin map is needed.
    pub fn pico_link_image(&self, dir: &Path) -> Result<PathBuf, ProjectError> {
        self.pico_link_build(dir, build_pico_link_image, "firmware-link.elf")
    }

    /// Builds the Pico's USB link build on this project's tables in `dir` (the supervisors driven over
    /// the Pico's USB port, a CDC-ACM serial device, by `codegen plant --connect serial:…`); returns the
    /// ELF. As [`Project::pico_link_image`].
    pub fn pico_usb_image(&self, dir: &Path) -> Result<PathBuf, ProjectError> {
        self.pico_link_build(dir, build_pico_usb_image, "firmware-usb.elf")
    }

    /// A link build of the Pico (`build`: the UART's or the USB's) on this project's tables, as
    /// `dir/elf`; the tables fitted to the Cortex-M0+ first.
    fn pico_link_build(
        &self,
        dir: &Path,
        build: fn(&Path, &Path) -> Result<PathBuf, ImageError>,
        elf: &str,
    ) -> Result<PathBuf, ProjectError> {
        self.for_board()?;
        self.fit(Core::CortexM0Plus, &Core::CortexM0Plus.flash())?;
        Ok(build(&self.tables_file(dir)?, &dir.join(elf))?)
    }

    /// Refuses `mode = "state"` for a board's application (the Pico image, a `codegen new` project's
    /// build script), naming the key: the board applications feed their pins' edges to the supervisor
    /// runtime, and none samples its pins into the state runtime's signal word yet, so the state tables
    /// would fail to compile there with no word of why.
    pub fn for_board(&self) -> Result<(), ProjectError> {
        if self.runtime.mode == Mode::State {
            return Err(self.feedback(FeedbackError::Vector {
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

/// The timers in the table digests ([`emit::timers::seal`]): the project emits, the build script proves.
#[cfg(test)]
mod timer_digests {
    use std::path::Path;

    use firmware::build::image::{check_source, digest_hex, images_in};

    use super::Project;

    /// The cylinder's project (`examples/cylinder`) with its timer's delay set to `ms`, or without its
    /// timers (`None`).
    fn cylinder(ms: Option<u32>) -> Project {
        let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/cylinder/cylinder.toml");
        let mut project = Project::load(&manifest).unwrap();
        match ms {
            Some(ms) => project.timers[0].ms = ms,
            None => project.timers.clear(),
        }
        project
    }

    #[test]
    fn a_timers_delay_changes_the_digest_and_tables_without_timers_keep_their_images() {
        let (on_time, longer) = (cylinder(Some(2000)), cylinder(Some(2100)));
        let digests = on_time.table_digests().unwrap();
        assert_eq!(digests.len(), 2, "the Cortex-M3's and the Cortex-M0+'s");
        assert_ne!(digests, longer.table_digests().unwrap(), "the timer's ms is in the digest");
        // The build script proves the digests the file declares, timers and all.
        let text = on_time.emit().unwrap();
        assert_eq!(check_source(&text).unwrap(), digests.join(" "));
        // Without timers, the digests are the images' own, as before timers.
        let plain = cylinder(None);
        let text = plain.emit().unwrap();
        let images: Vec<String> =
            images_in(&text).unwrap().iter().map(|(_, image)| digest_hex(image)).collect();
        assert_eq!(plain.table_digests().unwrap(), images);
        assert!(digests.iter().all(|d| !images.contains(d)), "{digests:?} {images:?}");
    }
}
