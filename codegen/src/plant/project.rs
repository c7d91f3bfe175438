//! A project ready for the closed loop: the supervisor set a manifest describes (supervisors given, or
//! synthesised local modular from plants and specifications), its run-time options, and the emitted
//! tables the firmware is built on.

use std::path::Path;

use crate::emit::{self, EmitError, Input, Provenance};
use crate::manifest::{Manifest, ManifestError};
use crate::model::Automaton;
use crate::pack::{ranked, PackError, PackSet};

/// A manifest's supervisor set with everything the closed loop and the firmware build need.
#[derive(Clone, Debug)]
pub struct Project {
    /// Plants first, then supervisors, over the event numbering the firmware uses.
    pub set: PackSet,
    /// Run-time options (`[runtime]` of the manifest, name included); tests change them before
    /// [`Project::emit`].
    pub runtime: emit::Options,
    /// Where the tables come from, for the emitted file's header.
    pub provenance: Provenance,
}

/// A project could not be put together.
#[derive(Debug, thiserror::Error)]
pub enum ProjectError {
    /// The manifest or a model file is bad.
    #[error(transparent)]
    Manifest(#[from] ManifestError),
    /// The manifest names neither supervisors nor specifications to synthesise them from.
    #[error("{}: no supervisors and no specifications to synthesise them from", file.display())]
    Nothing {
        /// The manifest file.
        file: std::path::PathBuf,
    },
    /// Synthesis failed.
    #[error("synthesis: {0}")]
    Synth(#[from] crate::synth::SynthError),
    /// The set cannot be packed.
    #[error(transparent)]
    Pack(#[from] PackError),
}

impl Project {
    /// Loads `manifest`: reads its automata, synthesises the local modular supervisors of its
    /// specifications (beside the ready supervisors it names, which come first) and takes its
    /// `[runtime]` options.
    pub fn load(manifest: &Path) -> Result<Self, ProjectError> {
        let m = Manifest::load(manifest)?;
        let models = m.read_automata()?;
        let supervisors = models.all_supervisors()?;
        if supervisors.is_empty() && models.plants.is_empty() {
            return Err(ProjectError::Nothing { file: m.file.clone() });
        }
        let runtime = emit::Options {
            name: m.name.clone(),
            policy: m.runtime.policy,
            seed: m.runtime.seed,
            guard: m.runtime.guard,
            on_fault: m.runtime.on_fault,
            input_buffer: m.runtime.input_buffer,
            board: m.board.clone(),
            ..emit::Options::default()
        };
        let files = std::iter::once(m.file.clone())
            .chain(m.plants.iter().chain(&m.specs).chain(&m.supervisors).map(|p| m.resolve(p)));
        let inputs = files
            .map(|f| Input::read(&f).unwrap_or_else(|_| Input::of(&f.display().to_string(), &[])))
            .collect();
        let command = format!("codegen run {} (local modular synthesis, ranked layout)", manifest.display());
        Ok(Project {
            set: PackSet::new(models.plants, supervisors)?,
            runtime,
            provenance: Provenance { inputs, command },
        })
    }

    /// A project from automata built in code, with `runtime` options.
    pub fn new(
        plants: Vec<Automaton>,
        supervisors: Vec<Automaton>,
        runtime: emit::Options,
    ) -> Result<Self, PackError> {
        let command = format!("closed loop of '{}' (automata built in code)", runtime.name);
        Ok(Project {
            set: PackSet::new(plants, supervisors)?,
            runtime,
            provenance: Provenance { inputs: Vec::new(), command },
        })
    }

    /// The Rust tables the firmware includes (`SCT_TABLES`).
    pub fn emit(&self) -> Result<String, EmitError> {
        let packed = ranked::encode(&self.set)?;
        emit::emit(&packed, &self.runtime, &self.provenance)
    }
}
