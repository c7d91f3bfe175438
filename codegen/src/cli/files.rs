//! The files a command works on, as every command that takes a project names them: a manifest, one or
//! several modules or model files (one project, read as their files say), or model files in roles.

use std::path::PathBuf;

use codegen::project::{Loaded, Sources};

use super::Error;

/// The error of a command given no files.
pub const NO_INPUT: &str = "no input: give a manifest, modules or model files, or --plant/--spec/--sup";

/// A project (manifest, modules, model files) and model files in roles; loaded by
/// [`Sources::load`], the one loader of every command.
#[derive(Debug, clap::Args)]
pub struct Files {
    /// A project: a manifest (TOML), or Supremica modules (.wmod) and model files (.xmd, .ads, .gen)
    /// read as their files say (components by their kinds, others as plants) — together one project.
    pub files: Vec<PathBuf>,
    /// Plant model files (of a module, its PLANT components).
    #[arg(long = "plant", num_args = 1.., value_name = "FILE")]
    pub plants: Vec<PathBuf>,
    /// Specification model files (of a module, its SPEC components).
    #[arg(long = "spec", num_args = 1.., value_name = "FILE")]
    pub specs: Vec<PathBuf>,
    /// Ready supervisor model files (of a module, its SUPERVISOR components).
    #[arg(long = "sup", num_args = 1.., value_name = "FILE")]
    pub supervisors: Vec<PathBuf>,
}

impl Files {
    /// The files as [`Sources`].
    pub fn sources(&self) -> Sources {
        Sources {
            files: self.files.clone(),
            plants: self.plants.clone(),
            specs: self.specs.clone(),
            supervisors: self.supervisors.clone(),
            board: None,
        }
    }

    /// Loads the project, saying on stderr which module components were left out.
    pub fn load(&self) -> Result<Loaded, Error> {
        let sources = self.sources();
        if sources.is_empty() {
            return Err(NO_INPUT.into());
        }
        let loaded = sources.load()?;
        super::say_skipped(&loaded.left_out);
        Ok(loaded)
    }
}
