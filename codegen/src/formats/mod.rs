//! Readers and writers for the field's automaton file formats.
//!
//! | format | extension | reads | writes | automata per file |
//! |---|---|---|---|---|
//! | IDES3 | `.xmd` | [`xmd::read`] | [`xmd::write`] | one |
//! | Nadzoru2 | `.xml` (also `.xmd`) | [`xmd::read`] ([`nadzoru`]) | [`nadzoru::write`] | one |
//! | libFAUDES / DESTool | `.gen` (token or XML form) | [`gen::read`] | [`gen::write`] (token form) | one |
//! | Supremica / Waters | `.wmod` | [`wmod::read`] | [`wmod::write`] | one per component |
//! | TCT | `.ads` / `.ADS` (+ event map) | [`ads::read`] | [`ads::write`] | one |
//! | Graphviz | `.dot` | — | [`dot::write`] | any |
//!
//! [`read_path`] picks the format from the extension (case-insensitive) and, failing that, from the
//! content (a `.xml` file always by its content: Nadzoru2, IDES3, libFAUDES or Supremica). Every reader
//! returns automata that pass [`Automaton::validate`] and are [canonical](Automaton::canonicalize), or a
//! [`ParseError`] naming the file and the line; no input makes a reader panic ([`check_reader`] states
//! this contract as code, for the fuzz targets and tests). Single-automaton formats name the automaton
//! after the file stem; [`write_path`] refuses, with a [`WriteError`], what a format cannot hold (several
//! automata in a single-automaton format, names the format would change) and what a format must say that
//! the automaton leaves unsaid (controllability, for every format but `.gen`; the role, for `.wmod`) —
//! a writer never invents a fact.

pub mod ads;
mod builder;
mod contract;
mod decode;
pub mod dot;
pub mod efa;
mod error;
mod faudes_xml;
pub mod gen;
mod gen_tokens;
pub(crate) mod hash;
pub mod nadzoru;
pub mod wmod;
mod wmod_graph;
pub mod xmd;
mod xml;

use std::path::{Path, PathBuf};

pub use contract::check_reader;
pub(crate) use decode::decode;
use error::ErrorKind;
pub use error::{ParseError, Unsaid, WriteError};
pub(crate) use xml::{escape as xml_escape, line as xml_line, parse as parse_xml};

use crate::model::{Automaton, Kind};

/// A file format this module knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// IDES3 `.xmd` XML.
    Xmd,
    /// TCT `.ADS` text.
    Ads,
    /// libFAUDES `.gen` tokens.
    Gen,
    /// Supremica `.wmod` XML.
    Wmod,
}

impl Format {
    /// The format an extension names (case-insensitive), if any.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "xmd" => Some(Format::Xmd),
            "ads" => Some(Format::Ads),
            "gen" => Some(Format::Gen),
            "wmod" => Some(Format::Wmod),
            _ => None,
        }
    }

    /// The format the content looks like, if any (a Nadzoru2 file reads as [`Format::Xmd`], whose
    /// reader tells the two dialects of `<model>` apart).
    pub fn sniff(text: &str) -> Option<Format> {
        let head = text.trim_start();
        if head.starts_with("<Generator") || text.contains("<TransRel>") {
            return Some(Format::Gen);
        }
        if head.starts_with('<') && (text.contains("<Generator ") || text.contains("<Generator>")) {
            return Some(Format::Gen);
        }
        if head.starts_with('<') && text.contains("<Module") {
            return Some(Format::Wmod);
        }
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

/// Every automaton of every file in `paths`, in order ([`read_path`] on each).
pub fn read_paths(paths: &[PathBuf]) -> Result<Vec<Automaton>, ParseError> {
    let mut out = Vec::new();
    for p in paths {
        out.extend(read_path(p)?);
    }
    Ok(out)
}

/// [`read_path`] with an explicit TCT event map for an `.ADS` file (refused for other formats).
pub fn read_path_with_events(path: &Path, event_map: Option<&Path>) -> Result<Vec<Automaton>, ParseError> {
    let bytes = read_file(path)?;
    let text = decode(path, &bytes)?;
    let text = text.as_ref();
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
    Ok(vec![ads::read(path, text, map.as_ref().map(|(p, t)| (*p, t.as_ref())))?])
}

/// Reads every automaton in `bytes`, the content of a file called `path` (used for the format and
/// errors). Touches no other file: an `.ADS` file is read without an event map.
pub fn read_bytes(path: &Path, bytes: &[u8]) -> Result<Vec<Automaton>, ParseError> {
    let text = decode(path, bytes)?;
    read_text(path, &text, detect(path, &text)?)
}

/// The variables, guards and actions of the Supremica module at `path` as written, when it has any
/// (`None` for a plain module and for files of other formats, which have no variables).
pub fn read_efa_path(path: &Path) -> Result<Option<efa::Efa>, ParseError> {
    let bytes = read_file(path)?;
    let text = decode(path, &bytes)?;
    match detect(path, &text)? {
        Format::Wmod => wmod::read_efa(path, &text),
        _ => Ok(None),
    }
}

fn read_text(path: &Path, text: &str, format: Format) -> Result<Vec<Automaton>, ParseError> {
    match format {
        Format::Xmd => Ok(vec![xmd::read(path, text)?]),
        Format::Ads => Ok(vec![ads::read(path, text, None)?]),
        Format::Gen => Ok(vec![gen::read(path, text)?]),
        Format::Wmod => wmod::read(path, text),
    }
}

fn detect(path: &Path, text: &str) -> Result<Format, ParseError> {
    Format::from_path(path)
        .or_else(|| Format::sniff(text))
        .ok_or_else(|| ParseError::new(path, None, ErrorKind::UnknownFormat))
}

/// The bytes of the file at `path`, or an error naming it.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, ParseError> {
    std::fs::read(path).map_err(|e| ParseError::new(path, None, ErrorKind::Io(e)))
}

/// Writes `automata` to `path` in the format its extension names (`.dot` too; `.xml` is Nadzoru2's).
/// Refuses automata that leave unsaid what the format must say: controllability (every format but
/// `.gen`, which can leave it unsaid, and `.dot`, which draws it as unsaid) and, for `.wmod`, the role.
pub fn write_path(path: &Path, automata: &[Automaton]) -> Result<(), WriteError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let unrepresentable = |msg| WriteError::Unrepresentable { file: path.to_path_buf(), msg };
    let said = |format: &'static str, role: bool| {
        let unsaid: Vec<Unsaid> = automata
            .iter()
            .filter_map(|a| {
                let what = Unsaid {
                    automaton: a.name.clone(),
                    role: role && a.kind == Kind::Unknown,
                    controllability: a.controllability_unsaid,
                };
                (what.role || what.controllability).then_some(what)
            })
            .collect();
        match unsaid.is_empty() {
            true => Ok(()),
            false => Err(WriteError::Unsaid { file: path.to_path_buf(), format, unsaid }),
        }
    };
    let text = match ext.as_deref() {
        Some("dot") => dot::write(automata),
        Some("xmd") => {
            let a = single(path, "xmd", automata)?;
            said("IDES3 .xmd", false)?;
            xml::check_names(a).map_err(unrepresentable)?;
            xmd::write(a)
        }
        Some("xml") => {
            let a = single(path, "xml", automata)?;
            said("Nadzoru2 .xml", false)?;
            xml::check_names(a).map_err(unrepresentable)?;
            nadzoru::write(a)
        }
        Some("gen") => {
            let a = single(path, "gen", automata)?;
            gen::check(a).map_err(unrepresentable)?;
            gen::write(a)
        }
        Some("ads") => {
            let a = single(path, "ads", automata)?;
            said("TCT .ADS", false)?;
            return ads::write_files(path, a);
        }
        Some("wmod") => {
            said("Supremica .wmod", true)?;
            automata.iter().try_for_each(xml::check_names).map_err(unrepresentable)?;
            wmod::write(&file_stem(path), automata).map_err(unrepresentable)?
        }
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

/// The automaton name a single-automaton file gives: its stem (`cell/S1.xmd` → `S1`).
fn file_stem(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Kind;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("codegen-formats-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn one_state(state: &str) -> Automaton {
        let mut a = Automaton::new("A", Kind::Plant);
        a.initial = Some(a.add_state(state, true).unwrap());
        a
    }

    #[test]
    fn write_path_refuses_what_the_format_cannot_hold() {
        let two = [one_state("s"), one_state("t")];
        let err = write_path(&scratch("two.xmd"), &two).unwrap_err().to_string();
        assert!(err.ends_with("two.xmd: xmd holds one automaton, got 2"), "{err}");
        let err = write_path(&scratch("hash.gen"), &[one_state("s#1")]).unwrap_err().to_string();
        assert!(err.contains("state name 's#1' contains '#'"), "{err}");
        let err = write_path(&scratch("space.xmd"), &[one_state(" s")]).unwrap_err().to_string();
        assert!(err.contains("name ' s' cannot be written to XML unchanged"), "{err}");
        let err =
            write_path(&scratch("two.wmod"), &[one_state("s"), one_state("t")]).unwrap_err().to_string();
        assert!(err.ends_with("two automata are called 'A'"), "{err}");
    }

    #[test]
    fn ads_sidecar_event_map_is_written_and_read_back() {
        let mut a = one_state("s");
        let go = a.add_event("go", true).unwrap();
        let s = crate::model::StateId::new(0).unwrap();
        a.add_transition(s, go, s);
        let path = scratch("loop.ADS");
        write_path(&path, std::slice::from_ref(&a)).unwrap();
        assert!(ads::event_map_for(&path).is_file());
        let back = read_path(&path).unwrap().remove(0);
        assert_eq!(back.events, a.events);
        let without = read_path_with_events(&path, Some(&scratch("missing.events"))).unwrap_err();
        assert!(without.is_io(), "{without}");
    }

    #[test]
    fn content_decides_when_the_extension_does_not() {
        let xmd = b"<?xml version=\"1.0\"?><model type=\"FSA\"><data></data></model>";
        assert_eq!(read_bytes(Path::new("x.txt"), xmd).unwrap()[0].states.len(), 0);
        let gen = b"<Generator> <States> s </States> <InitStates> s </InitStates> </Generator>";
        assert_eq!(read_bytes(Path::new("noext"), gen).unwrap()[0].states.len(), 1);
        let msg = read_bytes(Path::new("x.txt"), b"hello").unwrap_err().to_string();
        assert!(msg.starts_with("x.txt: unknown format"), "{msg}");
    }
}
