//! What the runtime does when something from outside goes wrong: an unexpected event, an input buffer
//! overflow or an unknown byte on the link. Each is always counted and reported; the policy says whether
//! the loop keeps deciding.

/// The configured reaction to a fault (manifest `[runtime] on_fault`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaultPolicy {
    /// Count and report, then keep deciding: an unexpected event leaves the automata that cannot take it
    /// where they are, an overflowed or unknown byte is dropped.
    Continue,
    /// Count and report, then turn every output off and stop deciding until a reset (inputs are still
    /// tracked and counted).
    SafeState,
}
