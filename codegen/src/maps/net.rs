//! `[net]` against the set's events: the net read and its interpretation bound, as `verify` and `plc`
//! bind it, so that a bad name there is reported with the other maps' problems.

use std::path::Path;

use crate::config::NetSpec;
use crate::manifest::ModelSet;
use crate::net::NetError;

use super::Problems;

/// Reads the net of `spec` (in the manifest `file`) and binds it to the events of `models`; the first
/// problem of the section, if any, joins the others (the binder stops at the first). A net file that
/// cannot be read is no map's problem: the command that reads the net reports it, naming the file.
pub(super) fn check(spec: &NetSpec, file: &Path, models: &ModelSet, p: &mut Problems) {
    let automata: Vec<_> = super::members(models).collect();
    if let Err(NetError::Spec { line, message, .. }) = crate::net::interpretation(spec, file, &automata) {
        p.at_line(Some(line), "net", message);
    }
}
