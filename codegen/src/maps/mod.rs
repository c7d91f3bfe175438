//! Where the maps meet the model: the manifest's `[board]`, `[plc]`, `[state]` and `[net]` sections
//! checked against the set's automata in one pass that reports every problem at once, each with the
//! manifest line and key (`12: board.inputs[1].pin: …`), before any command writes a table, a program
//! or a project from them.
//!
//! What each section must be:
//!
//! - **`[board]`** (`board`): every event one of the set's, inputs uncontrollable and outputs
//!   controllable; one event per pin edge (two entries on the rising edge of one pin would make one
//!   sensor two events), one input per event, one pull per pin, one direction per pin; the words
//!   (`edge`, `pull`, `action`) and the pulse length as the section documents them; and every pin one
//!   the board has and leaves free (`pins`) — the board a command builds for (`codegen new --board`,
//!   `run --target rp2040`, a project's build), else the one `[board] name` names.
//! - **`[plc]`** (`plc`): events as for the board; one event per variable edge, one address per
//!   variable and one variable per address; each address a `BOOL`'s located address of the standard's
//!   grammar (`address`) in the area its role reads or writes (`%I` or `%M` for an input, `%Q` or
//!   `%M` for an output); pulses of 1 to 32 767 scans, never mixed with set/clear on one variable.
//! - **`[state]`** (`state`): the section readable ([`crate::config::StateSpec::check`]); one
//!   component per plant, one formula per state, one command per controllable event of the plant; the
//!   signals' addresses as for `[plc]` (inputs `%I`, outputs `%Q`), one signal per address and per pin,
//!   pins the board's.
//! - **`[net]`** (`net`): the net read and its interpretation bound to the set's events
//!   ([`crate::net::interpretation()`]), unless `[hybrid]` makes the net the plant.
//!
//! `[events]` entries are checked where the automata are read ([`crate::manifest`]), as they must be
//! before the alphabets are.

mod address;
pub mod bench;
mod board;
mod net;
pub mod pins;
mod plc;
mod state;

use std::fmt;
use std::path::{Path, PathBuf};

pub use address::{Address, Area};
pub use pins::{Board, Pin};

use crate::config::BoardSpec;
use crate::manifest::{Key, Lines, Manifest, ModelSet};
use crate::model::{Automaton, EventTable, ModelError};

/// One problem of a map: where it is and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Problem {
    /// The manifest line (1-based), when known.
    pub line: Option<usize>,
    /// The key (`board.inputs[1].pin`).
    pub key: String,
    /// What is wrong, naming the values and the other entries involved.
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, "{line}: ")?;
        }
        write!(f, "{}: {}", self.key, self.message)
    }
}

/// The maps of a manifest do not fit its model: every problem, in the order of the file.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{}: {} the model:\n  {}",
    file.display(),
    if problems.len() == 1 { "a map does not fit".to_owned() } else { format!("{} problems where the maps meet", problems.len()) },
    problems.iter().map(Problem::to_string).collect::<Vec<_>>().join("\n  ")
)]
pub struct MapsError {
    /// The manifest (or the file holding the `[board]` section).
    pub file: PathBuf,
    /// Every problem, sorted by line.
    pub problems: Vec<Problem>,
}

/// The problems found so far, and the text that locates a key.
struct Problems<'a> {
    lines: &'a Lines,
    list: Vec<Problem>,
}

impl Problems<'_> {
    /// A problem at `key`.
    fn at(&mut self, key: &Key, message: impl Into<String>) {
        self.list.push(Problem { line: self.lines.line(key), key: key.to_string(), message: message.into() });
    }

    /// A problem at `line` in the manifest, under the section name `key`.
    fn at_line(&mut self, line: Option<usize>, key: &str, message: impl Into<String>) {
        self.list.push(Problem { line, key: key.to_owned(), message: message.into() });
    }

    /// `Ok`, or every problem of `file` in the file's order.
    fn finish(mut self, file: &Path) -> Result<(), MapsError> {
        if self.list.is_empty() {
            return Ok(());
        }
        self.list.sort_by(|a, b| (a.line.is_none(), a.line, &a.key).cmp(&(b.line.is_none(), b.line, &b.key)));
        self.list.dedup();
        Err(MapsError { file: file.to_owned(), problems: self.list })
    }
}

/// The changes of one signal (a pin, a variable) that entries claim, so that one change makes one event:
/// rising and falling claimed apart (one event each), or both by one entry.
#[derive(Default)]
struct Changes<'a> {
    claimed: Vec<(Key, &'a str, (bool, bool))>,
}

impl<'a> Changes<'a> {
    /// Claims the changes `(rising, falling)` for `event` at `key`; the entry (key and event) that
    /// claimed one of them first, with the change's name, when one was.
    fn claim(
        &mut self,
        key: Key,
        event: &'a str,
        change: (bool, bool),
    ) -> Option<(Key, &'a str, &'static str)> {
        let clash = self.claimed.iter().find_map(|(k, e, c)| match (change.0 && c.0, change.1 && c.1) {
            (true, _) => Some((k.clone(), *e, "rising")),
            (_, true) => Some((k.clone(), *e, "falling")),
            _ => None,
        });
        self.claimed.push((key, event, change));
        clash
    }
}

/// Why a set's events could not be put in one table for the check (the loader refuses such a set
/// first; this is for sets built otherwise).
fn table(models: &ModelSet) -> Result<EventTable, ModelError> {
    EventTable::build(members(models))
}

fn members(models: &ModelSet) -> impl Iterator<Item = &Automaton> {
    models.plants.iter().chain(&models.specs).chain(&models.supervisors)
}

/// The board a map is checked against: the one a command builds for, else the one `[board] name`
/// names (none: pins are only checked to be GPIO 0 to 63).
fn chosen(spec: &BoardSpec, board: Option<Board>) -> Option<Board> {
    board.or_else(|| Board::named(&spec.name))
}

/// Checks every map of `manifest` against `models` (its automata as read, before synthesis); `board`
/// is the board the command builds for, if it builds for one. Every problem of every section at once.
pub fn check(manifest: &Manifest, models: &ModelSet, board: Option<Board>) -> Result<(), MapsError> {
    let mut p = Problems { lines: &manifest.lines, list: Vec::new() };
    let events = match table(models) {
        Ok(t) => t,
        Err(e) => {
            p.at_line(None, "events", e.to_string());
            return p.finish(&manifest.file);
        }
    };
    let pins = manifest.board.as_ref().and_then(|spec| chosen(spec, board)).or(board);
    if let Some(spec) = &manifest.board {
        // With [state], [net] or [hybrid] commands reach the plant otherwise: only the event-based
        // runtime needs a pin (or `internal`) for every command.
        let every_command = manifest.state.is_none() && manifest.net.is_none() && manifest.hybrid.is_none();
        board::check(spec, &events, pins, board, every_command, &mut p);
    }
    if let Some(spec) = &manifest.plc {
        plc::check(spec, &events, &mut p);
    }
    if let Some(spec) = &manifest.state {
        state::check(spec, models, pins, &mut p);
    }
    if let (Some(spec), None) = (&manifest.net, &manifest.hybrid) {
        net::check(spec, &manifest.file, models, &mut p);
    }
    p.finish(&manifest.file)
}

/// Checks a `[board]` section read from a file of its own (`codegen emit --board FILE`, whose text is
/// `lines`) against `models`.
pub fn check_board(
    spec: &BoardSpec,
    file: &Path,
    lines: &Lines,
    models: &ModelSet,
    board: Option<Board>,
) -> Result<(), MapsError> {
    let mut p = Problems { lines, list: Vec::new() };
    match table(models) {
        Ok(events) => board::check(spec, &events, chosen(spec, board), board, true, &mut p),
        Err(e) => p.at_line(None, "events", e.to_string()),
    }
    p.finish(file)
}

/// Checks only the pins of `spec` (from `file`, whose text is `lines`) against `board`, the board a
/// command builds for: absent and reserved pins, and a map written for another board.
pub fn check_pins(spec: &BoardSpec, file: &Path, lines: &Lines, board: Board) -> Result<(), MapsError> {
    let mut p = Problems { lines, list: Vec::new() };
    board::pins(spec, Some(board), Some(board), &mut p);
    p.finish(file)
}

#[cfg(test)]
mod tests;
