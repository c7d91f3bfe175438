//! Emitting the Rust source the firmware compiles: the tables of a supervisor set in their layout as one
//! image of bytes in flash (`firmware::table::image`: the records of every automaton, the out-mask pool,
//! and the `SupervisorSet` sliced from it; checked when written and again by the firmware's build
//! script, which hands the compiler a digest instead of evaluating the check), with the side
//! tables the runtime's hot path needs, event ids as constants, event and automaton names apart for
//! logs, the choice-policy type and the runtime's type sized exactly, and the run-time configuration,
//! under a provenance header ([`crate::provenance`]).
//!
//! # Overview
//!
//! * [`rust`] — the writer. The side tables (per event the automata holding it, per plant the
//!   controllable events it generates, the choice sites) come from `firmware::build::SideTables`, with
//!   the runtime's limits checked ([`firmware::table::MAX_AUTOMATA`], every controllable event generated
//!   by a plant). Same inputs, byte-identical output: nothing in it depends on the time, the machine or a
//!   hash map's order.
//! * `header` — the comment block both writers open with: what the file holds, its provenance, the
//!   run-time options.
//! * [`board`] — the board tables of the manifest's `[board]` section ([`BoardSpec`](crate::config::BoardSpec)): pins of inputs and
//!   outputs for a real board.
//! * [`state`] — the state-based firmware's tables (`[runtime] mode = "state"`): the state feedback of
//!   [`crate::feedback`] as cubes over the packed signal word, no supervisor tables.
//! * [`policy`] — the firmware types the run-time configuration ([`RuntimeConfig`](crate::config::RuntimeConfig)) names, and the RAM
//!   each choice policy costs.
//!
//! Why a `codegen emit` subcommand rather than a `build.rs` calling this library: `codegen` depends on the
//! firmware's runtime (the virtual plant and the host tests run the very code that ships), so the
//! firmware cannot depend on `codegen` without a cycle. The committed `apps/cell/src/generated/cell.rs` is
//! kept fresh by a test that emits it again and compares the bytes.

pub mod board;
mod error;
mod header;
pub mod policy;
pub mod rust;
pub mod state;

pub use crate::provenance::{Input, Provenance};
pub use board::BoardError;
pub use error::EmitError;
pub use rust::emit;
