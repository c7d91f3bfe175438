//! `[net]` against the set's events: the net read and its interpretation bound, as `verify` and `plc`
//! bind it, so that a bad name there is reported with the other maps' problems.

use std::path::Path;

use crate::config::NetSpec;
use crate::manifest::ModelSet;
use crate::net::NetError;

use super::Problems;

/// Reads the net of `spec` (in the manifest `file`) and binds it to the events of `models`; its first
/// problem, if any, joins the others (the binder stops at the first).
pub(super) fn check(spec: &NetSpec, file: &Path, models: &ModelSet, p: &mut Problems) {
    let automata: Vec<_> = super::members(models).collect();
    match crate::net::interpretation(spec, file, &automata) {
        Ok(_) => {}
        Err(NetError::Spec { line, message, .. }) => p.at_line(Some(line), "net", message),
        Err(e) => p.at_line(None, "net", e.to_string()),
    }
}
