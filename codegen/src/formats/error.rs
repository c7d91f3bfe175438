//! Errors of the readers and writers: which file, where in it, and what is wrong.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::model::ModelError;

/// A model file could not be read into automata.
///
/// Opaque on purpose: callers print it (`file: line N: what`) or ask for the file and the line; the
/// message wording may improve without breaking them. Every reader returns this for every malformed
/// input, never a panic.
#[derive(Debug)]
pub struct ParseError(Box<Inner>);

/// The parts of a [`ParseError`], boxed so that `Result<_, ParseError>` stays one pointer wide.
#[derive(Debug)]
struct Inner {
    file: PathBuf,
    line: Option<usize>,
    kind: ErrorKind,
}

/// What went wrong, without the position.
#[derive(Debug)]
pub(crate) enum ErrorKind {
    /// The file could not be opened or read.
    Io(std::io::Error),
    /// The bytes are not UTF-8.
    NotUtf8,
    /// Neither the extension nor the content says which format this is.
    UnknownFormat,
    /// Malformed XML (the message is the XML parser's).
    Xml(String),
    /// The text does not follow the format's grammar.
    Syntax(String),
    /// The format allows this, but this tool refuses to guess its meaning.
    Unsupported(String),
    /// The automaton breaks a model invariant (duplicate, dangling reference, nondeterminism).
    Model(ModelError),
}

impl ParseError {
    pub(crate) fn new(file: &Path, line: Option<usize>, kind: ErrorKind) -> Self {
        ParseError(Box::new(Inner { file: file.to_path_buf(), line, kind }))
    }

    /// A grammar error at `line`.
    pub(crate) fn syntax(file: &Path, line: usize, msg: impl Into<String>) -> Self {
        Self::new(file, Some(line), ErrorKind::Syntax(msg.into()))
    }

    /// A model invariant broken at `line` (or somewhere in the file when `None`).
    pub(crate) fn model(file: &Path, line: Option<usize>, err: ModelError) -> Self {
        Self::new(file, line, ErrorKind::Model(err))
    }

    /// A construct this tool refuses, at `line`.
    pub(crate) fn unsupported(file: &Path, line: usize, msg: impl Into<String>) -> Self {
        Self::new(file, Some(line), ErrorKind::Unsupported(msg.into()))
    }

    /// The file the error is about, as the caller named it.
    pub fn file(&self) -> &Path {
        &self.0.file
    }

    /// The 1-based line the error is at, when it is tied to one.
    pub fn line(&self) -> Option<usize> {
        self.0.line
    }

    /// Whether the file could not be read at all (as opposed to being malformed).
    pub fn is_io(&self) -> bool {
        matches!(self.0.kind, ErrorKind::Io(_))
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.0.file.display())?;
        if let Some(line) = self.0.line {
            write!(f, "line {line}: ")?;
        }
        match &self.0.kind {
            ErrorKind::Io(e) => write!(f, "cannot read: {e}"),
            ErrorKind::NotUtf8 => f.write_str("not UTF-8 text"),
            ErrorKind::UnknownFormat => f.write_str(
                "unknown format: expected a .xmd, .ads, .gen or .wmod file (by extension or content)",
            ),
            ErrorKind::Xml(msg) => write!(f, "malformed XML: {msg}"),
            ErrorKind::Syntax(msg) => f.write_str(msg),
            ErrorKind::Unsupported(msg) => write!(f, "unsupported: {msg}"),
            ErrorKind::Model(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ParseError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.0.kind {
            ErrorKind::Io(e) => Some(e),
            _ => None,
        }
    }
}

/// Automata could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The output path's extension names no format this tool writes.
    #[error("{}: unknown output format: expected .xmd, .ads, .gen, .wmod or .dot", .0.display())]
    UnknownFormat(PathBuf),
    /// The format holds one automaton but several were given.
    #[error("{}: {format} holds one automaton, got {count}", .file.display())]
    TooMany {
        /// Output file.
        file: PathBuf,
        /// Format name.
        format: &'static str,
        /// How many automata were given.
        count: usize,
    },
    /// The automaton cannot be expressed in the format.
    #[error("{}: {msg}", .file.display())]
    Unrepresentable {
        /// Output file.
        file: PathBuf,
        /// Why.
        msg: String,
    },
    /// The file could not be written.
    #[error("{}: cannot write: {source}", .file.display())]
    Io {
        /// Output file.
        file: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
}
