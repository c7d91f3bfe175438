//! The manifest's `[net]` section: a sequence drawn as a Petri net (a PNML file) and its interpretation —
//! per transition a Boolean condition over input signals, per place the outputs it sets while marked,
//! optional delays — with the signals no automaton carries and the initial values of those that one does.
//!
//! ```toml
//! [net]
//! pnml = "net1.pnml"                            # ISO/IEC 15909-2 place/transition net
//! free = ["ack", "d05s"]                        # inputs no automaton carries: either value
//! fixed = { start = 1, cycle = 1 }              # inputs no automaton carries: a fixed value
//! outputs = ["l_start", "l_error"]              # outputs no automaton carries
//! initial = { sb = 1, sl = 1 }                  # initial values of carried signals (default 0)
//! [net.conditions]                              # Y(t); a transition left out is always input-enabled
//! t1 = "start"
//! t6 = "sl AND NOT si"
//! [net.actions]                                 # Z(p): signal = value, set while the place is marked
//! p2 = { l_start = 0, al = 1 }
//! [net.delays]                                  # D(t) in milliseconds (default 0)
//! t3 = 4000
//! [net.events]                                  # explicit event → signal edge (default: `af1` = af rising)
//! grip = { signal = "ag1", value = 1 }
//! ```
//!
//! Values are given as 0/1 or false/true. These are plain values: names are checked against the net and
//! the automata by [`crate::net`], which also reports the line of a bad one (the spans kept here).

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::Deserialize;
use toml::Spanned;

/// The `[net]` section.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetSpec {
    /// The PNML file holding the net, relative to the manifest.
    pub pnml: Spanned<PathBuf>,
    /// Input signals no automaton carries that may take either value (timeouts, acknowledgements).
    #[serde(default)]
    pub free: Vec<Spanned<String>>,
    /// Input signals no automaton carries, held at a fixed value.
    #[serde(default)]
    pub fixed: BTreeMap<Spanned<String>, Level>,
    /// Output signals no automaton carries (lamps): set at once when a place is marked.
    #[serde(default)]
    pub outputs: Vec<Spanned<String>>,
    /// Initial values of signals the automata carry (default 0).
    #[serde(default)]
    pub initial: BTreeMap<Spanned<String>, Level>,
    /// Y(t): the condition of each transition, by transition id.
    #[serde(default)]
    pub conditions: BTreeMap<Spanned<String>, Spanned<String>>,
    /// Z(p): the signal values each place sets while marked, by place id.
    #[serde(default)]
    pub actions: BTreeMap<Spanned<String>, BTreeMap<Spanned<String>, Level>>,
    /// D(t): the on-delay of each transition in milliseconds, by transition id.
    #[serde(default)]
    pub delays: BTreeMap<Spanned<String>, u32>,
    /// Explicit signal edges for events whose names do not follow the `<signal><0|1>` convention.
    #[serde(default)]
    pub events: BTreeMap<Spanned<String>, EventEdge>,
    /// Byte offset of the start of each line of the manifest text (set by [`NetSpec::locate`]), so that
    /// a span becomes a line.
    #[serde(skip)]
    line_starts: Vec<usize>,
}

/// A signal value: `0`/`1` or `false`/`true`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(try_from = "LevelText")]
pub struct Level(pub bool);

/// How a [`Level`] may be written.
#[derive(Deserialize)]
#[serde(untagged)]
enum LevelText {
    Bool(bool),
    Int(i64),
}

impl TryFrom<LevelText> for Level {
    type Error = String;

    fn try_from(t: LevelText) -> Result<Level, String> {
        match t {
            LevelText::Bool(b) => Ok(Level(b)),
            LevelText::Int(0) => Ok(Level(false)),
            LevelText::Int(1) => Ok(Level(true)),
            LevelText::Int(n) => Err(format!("a signal value is 0 or 1, not {n}")),
        }
    }
}

/// The signal edge an event is.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventEdge {
    /// The signal.
    pub signal: String,
    /// The value it changes to: 1 rising, 0 falling.
    pub value: Level,
}

impl NetSpec {
    /// Records where the lines of the manifest `text` start, for [`NetSpec::line`].
    pub fn locate(&mut self, text: &str) {
        self.line_starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
    }

    /// The 1-based manifest line of byte offset `at` (0 when the text was not located).
    pub fn line(&self, at: usize) -> usize {
        self.line_starts.partition_point(|&s| s <= at)
    }
}
