//! Readers and writers for the field's automaton file formats.
//!
//! | format | extension | reads | writes | automata per file |
//! |---|---|---|---|---|
//! | IDES3 / Nadzoru | `.xmd` | [`xmd::read`] | [`xmd::write`] | one |
//! | TCT | `.ads` / `.ADS` (+ event map) | [`ads::read`] | [`ads::write`] | one |
//!
//! [`read_path`] picks the format from the extension (case-insensitive) and, failing that, from the
//! content. Every reader returns automata that passed [`Automaton::validate`] and were
//! [canonicalized](Automaton::canonicalize), or a [`ParseError`] naming the file and the line; no input
//! makes a reader panic. Single-automaton formats name the automaton after the file stem.

pub mod ads;
mod builder;
pub mod dot;
mod error;
pub mod xmd;
mod xml;

use std::path::Path;

use error::ErrorKind;
pub use error::{ParseError, WriteError};

use crate::model::Automaton;

/// A file format this module knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// IDES3 `.xmd` XML.
    Xmd,
    /// TCT `.ADS` text.
    Ads,
}

impl Format {
    /// The format an extension names (case-insensitive), if any.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "xmd" => Some(Format::Xmd),
            "ads" => Some(Format::Ads),
            _ => None,
        }
    }

    /// The format the content looks like, if any.
    pub fn sniff(text: &str) -> Option<Format> {
        let head = text.trim_start();
        if head.starts_with('<') && text.contains("<model") {
            return Some(Format::Xmd);
        }
        if text.lines().any(|l| l.starts_with("State size")) && text.contains("Transitions") {
            return Some(Format::Ads);
        }
        None
    }
}

/// Reads every automaton in the file at `path` (format by extension, then by content).
///
/// A TCT `.ADS` file takes its event names from the map `<stem>.events` beside it when that exists
/// (see [`ads`]); use [`read_path_with_events`] to name another map.
pub fn read_path(path: &Path) -> Result<Vec<Automaton>, ParseError> {
    read_path_with_events(path, None)
}

/// [`read_path`] with an explicit TCT event map for an `.ADS` file (refused for other formats).
pub fn read_path_with_events(path: &Path, event_map: Option<&Path>) -> Result<Vec<Automaton>, ParseError> {
    let bytes = read_file(path)?;
    let text = decode(path, &bytes)?;
    let format = detect(path, text)?;
    if format != Format::Ads {
        if let Some(map) = event_map {
            return Err(ParseError::new(
                map,
                None,
                ErrorKind::Syntax(format!(
                    "an event map applies to TCT .ADS files only, not to {}",
                    path.display()
                )),
            ));
        }
        return read_text(path, text, format);
    }
    let sidecar = ads::event_map_for(path);
    let map_path = match event_map {
        Some(p) => Some(p),
        None => sidecar.is_file().then_some(sidecar.as_path()),
    };
    let map_bytes = map_path.map(read_file).transpose()?;
    let map = match (map_path, &map_bytes) {
        (Some(p), Some(bytes)) => Some((p, decode(p, bytes)?)),
        _ => None,
    };
    Ok(vec![ads::read(path, text, map)?])
}

/// Reads every automaton in `bytes`, the content of a file called `path` (used for the format and
/// errors). Touches no other file: an `.ADS` file is read without an event map.
pub fn read_bytes(path: &Path, bytes: &[u8]) -> Result<Vec<Automaton>, ParseError> {
    let text = decode(path, bytes)?;
    read_text(path, text, detect(path, text)?)
}

fn read_text(path: &Path, text: &str, format: Format) -> Result<Vec<Automaton>, ParseError> {
    match format {
        Format::Xmd => Ok(vec![xmd::read(path, text)?]),
        Format::Ads => Ok(vec![ads::read(path, text, None)?]),
    }
}

fn detect(path: &Path, text: &str) -> Result<Format, ParseError> {
    Format::from_path(path)
        .or_else(|| Format::sniff(text))
        .ok_or_else(|| ParseError::new(path, None, ErrorKind::UnknownFormat))
}

fn read_file(path: &Path) -> Result<Vec<u8>, ParseError> {
    std::fs::read(path).map_err(|e| ParseError::new(path, None, ErrorKind::Io(e)))
}

/// Writes `automata` to `path` in the format its extension names (`.dot` too).
pub fn write_path(path: &Path, automata: &[Automaton]) -> Result<(), WriteError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let text = match ext.as_deref() {
        Some("dot") => dot::write(automata),
        Some("xmd") => xmd::write(single(path, "xmd", automata)?),
        Some("ads") => return ads::write_files(path, single(path, "ads", automata)?),
        _ => return Err(WriteError::UnknownFormat(path.to_path_buf())),
    };
    write_file(path, &text)
}

/// The one automaton of `automata`, for formats that hold exactly one.
fn single<'a>(
    path: &Path,
    format: &'static str,
    automata: &'a [Automaton],
) -> Result<&'a Automaton, WriteError> {
    match automata {
        [a] => Ok(a),
        _ => Err(WriteError::TooMany { file: path.to_path_buf(), format, count: automata.len() }),
    }
}

/// Writes `text` to `path`.
fn write_file(path: &Path, text: &str) -> Result<(), WriteError> {
    std::fs::write(path, text).map_err(|source| WriteError::Io { file: path.to_path_buf(), source })
}

/// `bytes` as UTF-8 text (a leading byte-order mark dropped), or an error at the first bad byte's line.
fn decode<'b>(path: &Path, bytes: &'b [u8]) -> Result<&'b str, ParseError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        ParseError::new(path, Some(line), ErrorKind::NotUtf8)
    })
}

/// The automaton name a single-automaton file gives: its stem (`cell/S1.xmd` → `S1`).
fn file_stem(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}
