//! What the two XML formats (`.xmd`, `.wmod`) share: parsing with positions, and escaping.

use std::borrow::Cow;
use std::path::Path;

use roxmltree::{Document, Node, ParsingOptions};

use super::error::ErrorKind;
use super::ParseError;
use crate::model::Automaton;

/// Parses `text`, turning the XML parser's error into a [`ParseError`] with its line.
pub(crate) fn parse<'i>(file: &Path, text: &'i str) -> Result<Document<'i>, ParseError> {
    // No DTDs: model files have none, and entity expansion is a way to blow up memory.
    let options = ParsingOptions { allow_dtd: false, ..ParsingOptions::default() };
    Document::parse_with_options(text, options).map_err(|e| {
        // Errors about the end of the text are reported at its last line, not where the parser began.
        let line = match e {
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode => {
                text.lines().count().max(1)
            }
            _ => e.pos().row as usize,
        };
        ParseError::new(file, Some(line), ErrorKind::Xml(e.to_string()))
    })
}

/// The 1-based line where `node` starts.
pub(crate) fn line(doc: &Document, node: Node) -> usize {
    doc.text_pos_at(node.range().start).row as usize
}

/// Whether every name of `a` survives an XML document: not empty, no surrounding whitespace (readers
/// trim it), no control characters other than tab (XML 1.0 cannot hold them).
pub(crate) fn check_names(a: &Automaton) -> Result<(), String> {
    let names = std::iter::once(&a.name)
        .chain(a.states.iter().map(|s| &s.name))
        .chain(a.events.iter().map(|e| &e.name));
    for name in names {
        if name.is_empty() || name.trim() != name || name.chars().any(|c| c.is_control() && c != '\t') {
            return Err(format!("name '{}' cannot be written to XML unchanged", name.escape_debug()));
        }
    }
    Ok(())
}

/// `s` with the five XML special characters escaped, for attribute values and text.
pub(crate) fn escape(s: &str) -> Cow<'_, str> {
    if !s.contains(['&', '<', '>', '"', '\'']) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}
