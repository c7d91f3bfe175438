//! Why a set cannot be emitted for the runtime.

use firmware::build::image::CheckError;
use firmware::build::BuildError;

use super::BoardError;
use crate::pack::PackError;

/// Why a set cannot be emitted for the runtime.
#[derive(Debug, thiserror::Error)]
pub enum EmitError {
    /// The set breaks a limit of the `ranked` layout.
    #[error(transparent)]
    Pack(#[from] PackError),
    /// The set breaks a limit of the runtime's side tables (more automata than its holder masks have
    /// bits), or the tables do not read back (only tables built by hand or altered after packing).
    #[error(transparent)]
    Tables(#[from] BuildError),
    /// A controllable event no plant has in its alphabet: nothing can generate it.
    #[error("controllable event '{event}' belongs to no plant, so the product system cannot generate it")]
    Unowned {
        /// Event name.
        event: String,
    },
    /// The encoder's tables fail the runtime's check (a fault of codegen, never of the input: the
    /// tables are checked before they are written).
    #[error("the tables codegen encoded fail the firmware's check (a bug of codegen): {0}")]
    Check(CheckError),
    /// The `[board]` section does not fit the set.
    #[error(transparent)]
    Board(#[from] BoardError),
    /// A timer names an event the set does not have (the manifest's check refuses it before).
    #[error("timer '{timer}': the set has no event '{event}'")]
    TimerEvent {
        /// The timer's name.
        timer: String,
        /// The event.
        event: String,
    },
    /// The input buffer capacity is 0 or too large for the firmware's queue.
    #[error("input buffer of {capacity} events: it must hold 1 to 65535")]
    InputBuffer {
        /// The capacity asked for.
        capacity: usize,
    },
}
