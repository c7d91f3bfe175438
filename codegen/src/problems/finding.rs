//! What a check reports: the problem, where, and how to get there.

use std::fmt;

/// The implementation problems of Fabian & Hellgren that can be read off a closed loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Problem {
    /// One event fires twice in a row between different states (a scan-cycle controller takes both).
    Avalanche,
    /// Two controllable events do not commute: which one the controller picks matters.
    Choice,
    /// A controllable and an uncontrollable event do not commute: a race while choosing can
    /// desynchronise controller and plant.
    InexactSynchronisation,
    /// Two uncontrollable events do not commute: an input sampled late loses their order.
    Simultaneity,
}

impl Problem {
    /// Every problem, in report order.
    pub const ALL: [Problem; 4] =
        [Problem::Avalanche, Problem::Choice, Problem::InexactSynchronisation, Problem::Simultaneity];

    /// The name `--check` takes and reports print.
    pub fn name(self) -> &'static str {
        match self {
            Problem::Avalanche => "avalanche",
            Problem::Choice => "choice",
            Problem::InexactSynchronisation => "inexact-synchronisation",
            Problem::Simultaneity => "simultaneity",
        }
    }

    /// The problem called `name`.
    pub fn from_name(name: &str) -> Option<Problem> {
        Problem::ALL.into_iter().find(|p| p.name() == name)
    }
}

/// How a diamond fails to close; tells a race from events that exclude each other.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Shape {
    /// One event after the other (avalanche: the same event twice).
    Chain,
    /// Neither order is defined: after one event the other is no longer possible (e.g. sensors of
    /// exclusive part types). If both still happen, the model cannot follow.
    Exclusive,
    /// Only one order is defined: the other order is refused by the loop.
    OneOrder,
    /// Both orders are defined but end in different states.
    Diverging,
}

impl Shape {
    /// The name reports print.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Chain => "chain",
            Shape::Exclusive => "exclusive",
            Shape::OneOrder => "one-order",
            Shape::Diverging => "diverging",
        }
    }
}

/// One occurrence of a problem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Finding {
    /// Which problem.
    pub problem: Problem,
    /// The state where it shows (for avalanche, the state the first of the two transitions leaves).
    pub state: String,
    /// The events involved: one for avalanche, two otherwise.
    pub events: Vec<String>,
    /// A shortest trace from the initial state to [`Finding::state`].
    pub trace: Vec<String>,
    /// How the diamond fails ([`Shape::Chain`] for avalanche).
    pub shape: Shape,
    /// What goes wrong, e.g. `a·b reaches 1, b·a is undefined`.
    pub detail: String,
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let trace = if self.trace.is_empty() { "ε".to_owned() } else { self.trace.join(" ") };
        write!(
            f,
            "{} at state {} on {}: {} (trace: {})",
            self.problem.name(),
            self.state,
            self.events.join(", "),
            self.detail,
            trace
        )
    }
}
