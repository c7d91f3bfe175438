//! A project ready for the closed loop: the supervisor set a manifest describes (supervisors given, or
//! synthesised local modular from plants and specifications), its run-time options, and the emitted
//! tables the firmware is built on.

use crate::emit::{self, EmitError, Provenance};
use crate::model::Automaton;
use crate::pack::{offset, PackError, PackSet};

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
    /// Synthesis failed.
    #[error("synthesis: {0}")]
    Synth(#[from] crate::synth::SynthError),
    /// The set cannot be packed.
    #[error(transparent)]
    Pack(#[from] PackError),
}

impl Project {
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
        let packed = offset::encode(&self.set)?;
        emit::emit(&packed, &self.runtime, &self.provenance)
    }
}
