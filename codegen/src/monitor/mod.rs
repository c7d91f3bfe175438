//! Verdicts on a closed-loop run: safety, liveness, coverage and link health.
//!
//! The [`Monitor`] sees every event the link carries — the plant's uncontrollable events as they are sent,
//! the controller's commands as they arrive — and checks each one against plants ‖ supervisors:
//!
//! - **safety**: no command a supervisor disables or the plant cannot take, every uncontrollable event
//!   accepted by the supervisors (a refused one means a supervisor is not controllable);
//! - **liveness**: the marked states of the closed loop keep being reached (visits, longest gap);
//! - **coverage**: which controllable transitions of each supervisor were taken, out of those reachable in
//!   plants ‖ supervisors (the closed loop explored by synthesis's product walk,
//!   [`crate::synth::Reachable`]);
//! - **time** (a project with `[[timers]]`): every timeout the target raises falls in its timer's
//!   `[deadline, deadline + slack]` of virtual time; an early, a late and a missing one are violations
//!   ([`Timers`]);
//! - **link**: desynchronisations (commands decided before the controller read the plant's latest events),
//!   resets, and the firmware's own counters (overflows, guard re-decisions, unexpected events), from
//!   which events lost silently are derived.
//!
//! The figures end up in a [`Report`], printed as a table or as JSON; a run on a board's pins adds what
//! only pins show ([`BoardFigures`]).

mod board;
mod choice_model;
mod coverage;
mod judge;
mod report;
mod scan;
mod steering;
mod timers;

pub use board::{BoardFigures, CallCost, RuntimeCost};
pub use choice_model::ChoiceModel;
pub use coverage::{Edge, Graph, Taken, TooLarge};
pub use judge::{Monitor, Verdict};
pub use report::{CoverageLine, FirmwareCounters, Report, TimeoutFigures, SCHEMA};
pub use scan::ScanFigures;
pub use steering::Move;
pub use timers::{Timers, Timing};
