//! Emitting the Rust source the firmware compiles: the `offset` tables of a supervisor set as `static`
//! data in flash, with the side tables the runtime's hot path needs, event names as constants, the
//! choice-policy type sized exactly and the run-time configuration, under a provenance header.
//!
//! # Overview
//!
//! * [`side`] — per event the automata holding it, per controllable event its owning plant, the choice
//!   sites; checks the runtime's limits ([`firmware::table::MAX_AUTOMATA`],
//!   [`firmware::table::MAX_SITE_EVENTS`], every controllable event owned by a plant).
//! * [`options`] — the manifest's `[runtime]` choices and the RAM each choice policy costs.
//! * [`provenance`] — input file hashes (SHA-256), tool version and options for the header.
//! * [`rust`] — the writer. Same inputs, byte-identical output: nothing in it depends on the time, the
//!   machine or a hash map's order.
//!
//! Why a `codegen emit` subcommand rather than a `build.rs` calling this library: `codegen` depends on the
//! firmware's runtime (the virtual plant and the host tests run the very code that ships), so the
//! firmware cannot depend on `codegen` without a cycle. The committed `firmware/src/generated/cell.rs` is
//! kept fresh by a test that emits it again and compares the bytes.

pub mod options;
pub mod provenance;
pub mod rust;
pub mod side;

pub use options::{OnFault, Options, Policy};
pub use provenance::{Input, Provenance};
pub use rust::emit;
pub use side::{EmitError, HostTables, SideTables};
