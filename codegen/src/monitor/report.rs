//! The figures of a closed-loop run: what the monitor judged and what the firmware counted.

use std::fmt;

use firmware::runtime::Counters;
use serde::Serialize;
use sha2::{Digest, Sha256};

use super::board::BoardFigures;
use super::scan::ScanFigures;

/// Version of the JSON form of [`Report`]; bumped when a field changes meaning or goes away (2: `target`
/// and `board`; 3: `scan`, and `seconds` the PLC's own clock on target `plc`).
pub const SCHEMA: u32 = 3;

/// The firmware's own counters ([`Counters`], the link's STATUS answer) summed over every reset of a run,
/// as the report prints them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FirmwareCounters {
    /// Uncontrollable events it took into its input buffer.
    pub events_in: u64,
    /// Commands it fired.
    pub commands_out: u64,
    /// Events an automaton had in its alphabet but no transition for.
    pub unexpected: u64,
    /// Events dropped because the input buffer was full (reported, never silent).
    pub overflows: u64,
    /// Decisions dropped because an event arrived while choosing (the inexact-synchronisation guard).
    pub guard_redecisions: u64,
    /// Bytes that were neither an event id nor a known control byte.
    pub unknown_bytes: u64,
}

impl From<Counters> for FirmwareCounters {
    fn from(c: Counters) -> Self {
        FirmwareCounters {
            events_in: c.events_in.into(),
            commands_out: c.commands_out.into(),
            unexpected: c.unexpected.into(),
            overflows: c.overflows.into(),
            guard_redecisions: c.guard_redecisions.into(),
            unknown_bytes: c.unknown_bytes.into(),
        }
    }
}

impl FirmwareCounters {
    /// Adds `other` field by field.
    pub fn add(&mut self, other: FirmwareCounters) {
        self.events_in += other.events_in;
        self.commands_out += other.commands_out;
        self.unexpected += other.unexpected;
        self.overflows += other.overflows;
        self.guard_redecisions += other.guard_redecisions;
        self.unknown_bytes += other.unknown_bytes;
    }
}

/// Coverage of one supervisor: distinct controllable transitions taken, out of those the closed loop
/// can reach (`None` when it was too large to explore).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct CoverageLine {
    /// Supervisor name.
    pub supervisor: String,
    /// Transitions taken during the run.
    pub taken: usize,
    /// Transitions reachable in plants ‖ supervisors.
    pub reachable: Option<usize>,
}

/// The verdicts and figures of one run; printed as a table or serialised as JSON (schema [`SCHEMA`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Report {
    /// JSON schema version.
    pub schema: u32,
    /// What ran the firmware: `qemu`, `rp2040` (emulated Pico: its link build over UART0, or the pin
    /// application through its pins, which `board` then describes), or `link` (a firmware started
    /// elsewhere, `codegen plant`).
    pub target: String,
    /// Name of the supervisor set.
    pub name: String,
    /// Seed of the virtual plant.
    pub seed: u64,
    /// Events carried by the link (commands plus uncontrollable events).
    pub events: u64,
    /// Commands received from the controller.
    pub commands: u64,
    /// Uncontrollable events the plant sent.
    pub uncontrollable: u64,
    /// SHA-256 of the event sequence the link carried (one byte per event, its id, in link order), as
    /// lower-case hex: the fingerprint by which two runs — of two layouts, say — took the same trace.
    pub trace_sha256: String,
    /// The running hash behind [`Report::trace_sha256`].
    #[serde(skip)]
    pub trace: Trace,
    /// Safety violations: disabled or impossible commands, refused uncontrollable events, safe-state
    /// faults.
    pub violations: u64,
    /// The first violations, described.
    pub findings: Vec<String>,
    /// Commands decided on stale information (inexact synchronisation).
    pub desyncs: u64,
    /// Times the link was reset to bring plant and controller back together.
    pub resyncs: u64,
    /// Times the plant's steering restarted the closed loop after long without a new transition.
    pub steering_resets: u64,
    /// Times the closed loop blocked: nothing for the plant to do and no command (then reset).
    pub stalls: u64,
    /// READYs the firmware sent unasked: it restarted in mid-run (then resynchronised).
    pub reboots: u64,
    /// Bytes from the firmware the protocol does not define in that direction.
    pub garbled: u64,
    /// Times the closed loop entered a marked state.
    pub marked_visits: u64,
    /// Most events in a row outside the marked states.
    pub longest_marked_gap: u64,
    /// Events since the last marked state.
    pub events_since_marked: u64,
    /// Whether the run ended in a marked state.
    pub marked_at_end: bool,
    /// Per supervisor: controllable transitions taken / reachable.
    pub coverage: Vec<CoverageLine>,
    /// The event count at which every reachable controllable supervisor transition had been taken.
    pub full_coverage_at: Option<u64>,
    /// Reachable controllable supervisor transitions not taken, as `supervisor: state --event-->`
    /// (the first few).
    pub uncovered: Vec<String>,
    /// Input-buffer overflows the firmware reported.
    pub overflows: u64,
    /// Events sent that the firmware neither took nor reported as overflow (lost silently).
    pub lost: u64,
    /// Guard re-decisions the firmware reported.
    pub guard_redecisions: u64,
    /// The firmware's counters, summed over resets.
    pub firmware: FirmwareCounters,
    /// Duration in seconds: wall-clock on a firmware; on target `plc` the PLC's own clock (scans ×
    /// the task's interval), so a program's run is a function of its seed.
    pub seconds: f64,
    /// Events per second over the run.
    pub events_per_second: f64,
    /// What the board's pins showed (`rp2040` through its pins; `None` over a byte link, the Pico's
    /// UART0 included).
    pub board: Option<BoardFigures>,
    /// What the PLC program's scans showed (target `plc`; `None` on a firmware).
    pub scan: Option<ScanFigures>,
    /// How the timeouts the target raised fell against their timers' deadlines (a project with
    /// `[[timers]]`; `None` without).
    pub timeouts: Option<TimeoutFigures>,
}

/// The timeouts of a run with timers, judged against their deadlines in virtual time. Early, late and
/// missing ones are violations too (each one counted in [`Report::violations`] and described in
/// [`Report::findings`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct TimeoutFigures {
    /// Within `[deadline, deadline + slack_ms]`.
    pub on_time: u64,
    /// Before the deadline, or with the timer not running (`timeout_early`).
    pub early: u64,
    /// After `deadline + slack_ms` (`timeout_late`).
    pub late: u64,
    /// Not raised by `deadline + slack_ms` (`timeout_missing`).
    pub missing: u64,
    /// How long after its deadline the target may raise a timeout: 0 on a firmware, the scan cycle on
    /// a PLC.
    pub slack_ms: u64,
}

impl fmt::Display for TimeoutFigures {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "  timeouts  {} on time, {} early, {} late, {} missing (slack {} ms)",
            self.on_time, self.early, self.late, self.missing, self.slack_ms
        )
    }
}

/// The running SHA-256 of a run's event sequence.
#[derive(Clone, Debug, Default)]
pub struct Trace(Sha256);

impl Trace {
    /// Adds event `id` to the sequence.
    pub fn push(&mut self, id: u8) {
        self.0.update([id]);
    }

    /// The digest of the sequence so far, as lower-case hex.
    pub fn hex(&self) -> String {
        self.0.clone().finalize().iter().map(|b| format!("{b:02x}")).collect()
    }
}

impl PartialEq for Trace {
    /// Two traces are equal when their sequences hash alike.
    fn eq(&self, other: &Self) -> bool {
        self.hex() == other.hex()
    }
}

impl Report {
    /// Fills the derived figures once the run is over and the firmware's counters are in.
    pub fn finish(&mut self, seconds: f64) {
        self.schema = SCHEMA;
        self.trace_sha256 = self.trace.hex();
        self.seconds = seconds;
        self.events_per_second = if seconds > 0.0 { self.events as f64 / seconds } else { 0.0 };
        self.overflows = self.firmware.overflows;
        self.guard_redecisions = self.firmware.guard_redecisions;
        self.lost = self.uncontrollable.saturating_sub(self.firmware.events_in + self.firmware.overflows);
    }

    /// Whether every supervisor took every controllable transition the closed loop can reach.
    pub fn full_coverage(&self) -> bool {
        self.coverage.iter().all(|c| c.reachable == Some(c.taken))
    }

    /// The live one-line progress display.
    pub fn progress_line(&self, target: u64) -> String {
        format!(
            "{} / {} events  {} violations  {} marked visits  {} desyncs  coverage {}/{}",
            self.events,
            target,
            self.violations,
            self.marked_visits,
            self.desyncs,
            self.coverage.iter().map(|c| c.taken).sum::<usize>(),
            self.coverage.iter().map(|c| c.reachable.unwrap_or(0)).sum::<usize>(),
        )
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "closed loop '{}' on {}: {} events ({} commands, {} plant events) in {:.2} s, {:.0} events/s, seed {}",
            self.name,
            self.target,
            self.events,
            self.commands,
            self.uncontrollable,
            self.seconds,
            self.events_per_second,
            self.seed
        )?;
        writeln!(f, "  safety    {} violations", self.violations)?;
        writeln!(f, "  trace     sha256 {}", self.trace_sha256)?;
        for finding in &self.findings {
            writeln!(f, "            {finding}")?;
        }
        if let Some(timeouts) = &self.timeouts {
            write!(f, "{timeouts}")?;
        }
        writeln!(
            f,
            "  liveness  {} marked visits, longest gap {} events, {} since the last",
            self.marked_visits, self.longest_marked_gap, self.events_since_marked
        )?;
        let fw = &self.firmware;
        writeln!(
            f,
            "  link      {} desyncs, {} resyncs, {} steering resets, {} stalls, {} reboots, {} overflows, \
             {} lost, {} guard re-decisions, {} unexpected, {} unknown bytes in, {} garbled bytes out",
            self.desyncs,
            self.resyncs,
            self.steering_resets,
            self.stalls,
            self.reboots,
            self.overflows,
            self.lost,
            self.guard_redecisions,
            fw.unexpected,
            fw.unknown_bytes,
            self.garbled
        )?;
        let width = self.coverage.iter().map(|c| c.supervisor.len()).max().unwrap_or(0).max(10);
        match self.full_coverage_at {
            Some(n) => writeln!(f, "  coverage  complete after {n} events")?,
            None => writeln!(f, "  coverage  incomplete")?,
        }
        writeln!(f, "            {:<width$}  taken / reachable", "supervisor")?;
        for c in &self.coverage {
            let reachable = c.reachable.map_or_else(|| "?".to_owned(), |r| r.to_string());
            let mark = if c.reachable == Some(c.taken) { "" } else { "  (incomplete)" };
            writeln!(f, "            {:<width$}  {:>5} / {reachable}{mark}", c.supervisor, c.taken)?;
        }
        for u in &self.uncovered {
            writeln!(f, "            not taken: {u}")?;
        }
        if let Some(board) = &self.board {
            write!(f, "{board}")?;
        }
        if let Some(scan) = &self.scan {
            write!(f, "{scan}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finish_derives_link_figures_and_the_table_shows_them() {
        let mut r = Report {
            name: "cell".into(),
            events: 30,
            uncontrollable: 10,
            firmware: FirmwareCounters {
                events_in: 7,
                overflows: 2,
                guard_redecisions: 4,
                ..Default::default()
            },
            coverage: vec![CoverageLine { supervisor: "S1".into(), taken: 3, reachable: Some(4) }],
            ..Report::default()
        };
        r.finish(2.0);
        assert_eq!((r.overflows, r.lost, r.guard_redecisions), (2, 1, 4));
        assert_eq!(r.events_per_second, 15.0);
        assert!(!r.full_coverage());
        let table = r.to_string();
        assert!(table.contains("2 overflows, 1 lost, 4 guard re-decisions"), "{table}");
        assert!(table.contains("S1              3 / 4  (incomplete)"), "{table}");
        let json = serde_json::to_value(&r).unwrap();
        assert_eq!(json["schema"], SCHEMA);
        assert_eq!(json["coverage"][0]["reachable"], 4);
    }
}
