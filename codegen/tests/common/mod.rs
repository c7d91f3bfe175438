//! Helpers the command-line tests that work outside the checkout share: a scratch directory that
//! cleans up after itself, and paths into the checkout.

use std::path::{Path, PathBuf};

/// A directory removed when dropped.
pub struct Temp(pub PathBuf);

impl Drop for Temp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The path `rel` in the checkout (relative to the workspace root).
pub fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}
