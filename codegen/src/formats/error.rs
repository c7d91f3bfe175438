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
    /// Automata leave unsaid what the format must say (controllability, a component's role): writing
    /// them would invent it.
    #[error(
        "{}: {format} says {}, and {}",
        .file.display(),
        what_it_says(.unsaid),
        .unsaid.iter().map(Unsaid::describe).collect::<Vec<_>>().join("; ")
    )]
    Unsaid {
        /// Output file.
        file: PathBuf,
        /// The format, as named to the user (`TCT .ADS`).
        format: &'static str,
        /// Each automaton and what it leaves unsaid.
        unsaid: Vec<Unsaid>,
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

/// What an automaton leaves unsaid that a format must say.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unsaid {
    /// The automaton.
    pub automaton: String,
    /// Its role: its file says neither plant, specification nor supervisor.
    pub role: bool,
    /// Its events' controllability: its file says nothing of it (a libFAUDES generator without `+C+`,
    /// which takes it from the plant).
    pub controllability: bool,
}

impl Unsaid {
    fn describe(&self) -> String {
        let what = match (self.role, self.controllability) {
            (true, true) => "its role (plant, specification or supervisor) and its events' controllability",
            (true, false) => "its role (plant, specification or supervisor)",
            _ => "its events' controllability (its file takes it from the plant, as libFAUDES does)",
        };
        format!("'{}' leaves unsaid {what}", self.automaton)
    }
}

/// What a format says that `unsaid` leaves unsaid.
fn what_it_says(unsaid: &[Unsaid]) -> &'static str {
    let role = unsaid.iter().any(|u| u.role);
    let controllability = unsaid.iter().any(|u| u.controllability);
    match (role, controllability) {
        (true, true) => "every component's role and every event's controllability",
        (true, false) => "every component's role (PLANT, SPEC, SUPERVISOR)",
        _ => "every event's controllability",
    }
}
