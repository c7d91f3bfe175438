//! What a run of a PLC program showed that a firmware's run cannot: its scans (`codegen run --target
//! plc`, [`crate::plc::closed_loop`] is where they are counted), carried by the closed loop's report
//! ([`Report`](super::Report)).

use std::fmt;

use serde::Serialize;

/// The scan figures of a PLC program's run under the interpreter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ScanFigures {
    /// Scans from the session's first RESET on that made an input's edge (the state-based program:
    /// read a changed input) or fired a command (the scans a PLC repeats while it waits for its plant
    /// or the host or works off what is pending, the boot scan, the scans before the session holds
    /// the program and a RESET's scan not counted — so the figure is a function of the seed). A
    /// hybrid controller's run counts every scan after the boot scan: its plant's clock
    /// ([`crate::plc::hybrid::closed_loop`]).
    pub scans: u64,
    /// Most statements one of those scans executed.
    pub max_statements: u64,
    /// The bound on statements per scan the program's report states (`codegen plc`); a run never
    /// exceeds it.
    pub bound_per_scan: u64,
    /// The task's interval, in milliseconds: the PLC's clock advances by it every scan.
    pub cycle_ms: u32,
}

impl fmt::Display for ScanFigures {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "  scans     {} scans of {} ms, at most {} statements in one (bound {})",
            self.scans, self.cycle_ms, self.max_statements, self.bound_per_scan
        )
    }
}
