//! What a firmware is configured with besides its tables: the run-time configuration ([`RuntimeConfig`],
//! the manifest's `[runtime]`) and the pin map of a real board ([`BoardSpec`], `[board]`); and what a PLC
//! program is configured with: its I/O map, policy and cycle ([`PlcSpec`], `[plc]`); a sequence net's
//! interpretation ([`NetSpec`], `[net]`), and the events of an automation net's transitions when that net is
//! the plant of a hybrid controller ([`HybridSpec`], `[hybrid]`); and the plant's state vector a state-based program reads
//! ([`StateSpec`], `[state]`).
//!
//! These are plain values: the manifest deserialises them, `codegen emit`'s options override them, and
//! [`crate::emit`] writes them into the tables. Nothing here reads a file or knows a table.

mod board;
mod hybrid;
mod net;
mod plc;
mod runtime;
mod signals;

pub use board::{BoardSpec, InputSpec, OutputSpec, SamplingSpec};
pub use hybrid::HybridSpec;
pub use net::{EventEdge, Level, NetSpec};
pub use plc::{Action, Edge, PlcInput, PlcOutput, PlcSpec, ScanPolicy};
pub use runtime::{ChoicePolicy, Layout, Mode, OnFault, RuntimeConfig, SupervisorChoice};
pub use signals::{
    Component, ComponentSpec, Cube, Direction, Signal, SignalSpec, Signals, SignalsError, StateSpec,
    MAX_SIGNALS,
};
