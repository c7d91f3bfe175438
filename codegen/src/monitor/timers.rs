//! The timers' deadlines as the monitor keeps them (`[[timers]]`,
//! [`TimerSpec`](crate::manifest::TimerSpec)): a start event arms its timer for `ms` of virtual time, a
//! stop event or its timeout disarms it, and the target (firmware or PLC program, never the virtual
//! plant) raises the timeout. A timeout the target reports at virtual time `t` is on time iff `t` lies in
//! `[deadline, deadline + slack]`, the slack being the target's (0 for the firmware, which counts in
//! whole milliseconds; a scan cycle for a PLC, whose `TON` is only evaluated at scans).

use crate::model::{EventId, EventTable};

/// One timer: its events by global id, its delay, and when it falls due while it runs.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Timer {
    start: Vec<EventId>,
    stop: Vec<EventId>,
    timeout: EventId,
    ms: u64,
    /// The virtual time (ms) of its timeout while it runs.
    deadline: Option<u64>,
}

/// How a timeout the target reported fell against its timer's deadline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timing {
    /// Within `[deadline, deadline + slack]`.
    OnTime,
    /// Before the deadline, or with its timer not running (nothing started it, or a stop came first).
    Early,
    /// After `deadline + slack`.
    Late,
}

/// Every timer of a run, with the slack the target is allowed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Timers {
    timers: Vec<Timer>,
    slack_ms: u64,
}

impl Timers {
    /// The timers `specs` over the numbering of `table` (a spec whose timeout the set does not have is
    /// left out: nothing can raise it), with `slack_ms`.
    pub fn new(specs: &[crate::manifest::TimerSpec], table: &EventTable, slack_ms: u64) -> Self {
        let ids = |names: &[String]| names.iter().filter_map(|n| table.id(n)).collect::<Vec<_>>();
        let timers = specs
            .iter()
            .filter_map(|s| {
                Some(Timer {
                    timeout: table.id(&s.timeout_event())?,
                    start: ids(&s.start),
                    stop: ids(&s.stop),
                    ms: u64::from(s.ms),
                    deadline: None,
                })
            })
            .collect();
        Timers { timers, slack_ms }
    }

    /// Whether there is any timer.
    pub fn is_empty(&self) -> bool {
        self.timers.is_empty()
    }

    /// The slack a timeout may come after its deadline.
    pub fn slack_ms(&self) -> u64 {
        self.slack_ms
    }

    /// Whether `e` is a timer's timeout (the target's event, never the plant's).
    pub fn is_timeout(&self, e: EventId) -> bool {
        self.timers.iter().any(|t| t.timeout == e)
    }

    /// The timeouts, in timer order.
    pub fn timeouts(&self) -> impl Iterator<Item = EventId> + '_ {
        self.timers.iter().map(|t| t.timeout)
    }

    /// Event `e` (not a timeout) was taken at `now_ms`: a start (re)arms its timers, a stop disarms them.
    pub fn take(&mut self, e: EventId, now_ms: u64) {
        for t in &mut self.timers {
            if t.start.contains(&e) {
                t.deadline = Some(now_ms + t.ms);
            } else if t.stop.contains(&e) {
                t.deadline = None;
            }
        }
    }

    /// The target reported timeout `e` at `now_ms`: how it fell; its timer is idle afterwards.
    pub fn timeout(&mut self, e: EventId, now_ms: u64) -> Timing {
        let Some(t) = self.timers.iter_mut().find(|t| t.timeout == e) else { return Timing::Early };
        match t.deadline.take() {
            Some(d) if now_ms < d => Timing::Early,
            Some(d) if now_ms > d + self.slack_ms => Timing::Late,
            Some(_) => Timing::OnTime,
            None => Timing::Early,
        }
    }

    /// The earliest deadline of a running timer.
    pub fn next_deadline(&self) -> Option<u64> {
        self.timers.iter().filter_map(|t| t.deadline).min()
    }

    /// The timeouts missing at `now_ms`: timers still running at `deadline + slack <= now_ms`, when the
    /// target has had every millisecond up to `now_ms` to raise them. They are disarmed (a timeout that
    /// comes after all is then judged early: its timer is no longer running).
    pub fn missing(&mut self, now_ms: u64) -> Vec<EventId> {
        let slack = self.slack_ms;
        let mut out = Vec::new();
        for t in &mut self.timers {
            if t.deadline.is_some_and(|d| d + slack <= now_ms) {
                t.deadline = None;
                out.push(t.timeout);
            }
        }
        out
    }

    /// Every timer idle (a reset).
    pub fn reset(&mut self) {
        for t in &mut self.timers {
            t.deadline = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::TimerSpec;
    use crate::model::{Automaton, Kind};

    /// Timer T (2000 ms, start `go`, stop `end`) over a table of its own events, slack 10 ms.
    fn timers() -> (Timers, EventTable) {
        let spec = TimerSpec {
            name: "T".into(),
            start: vec!["go".into()],
            stop: vec!["end".into()],
            timeout: None,
            ms: 2000,
        };
        let a: Automaton = spec.automaton(|e| Some(e == "go")).unwrap();
        assert_eq!(a.kind, Kind::Plant);
        let table = EventTable::build([&a]).unwrap();
        (Timers::new(&[spec], &table, 10), table)
    }

    #[test]
    fn a_timeout_is_on_time_from_its_deadline_to_the_slack_after_it() {
        let (mut t, table) = timers();
        let (go, out) = (table.id("go").unwrap(), table.id("T_timeout").unwrap());
        assert!(t.is_timeout(out) && !t.is_timeout(go));
        for (at, timing) in
            [(1999, Timing::Early), (2000, Timing::OnTime), (2010, Timing::OnTime), (2011, Timing::Late)]
        {
            t.take(go, 0);
            assert_eq!(t.next_deadline(), Some(2000));
            assert_eq!(t.timeout(out, at), timing, "at {at} ms");
            assert_eq!(t.next_deadline(), None, "the timer is idle after its timeout");
        }
    }

    #[test]
    fn a_restart_moves_the_deadline_and_a_stop_disarms() {
        let (mut t, table) = timers();
        let (go, end, out) =
            (table.id("go").unwrap(), table.id("end").unwrap(), table.id("T_timeout").unwrap());
        t.take(go, 0);
        t.take(go, 1500);
        assert_eq!(t.next_deadline(), Some(3500));
        assert_eq!(t.timeout(out, 2000), Timing::Early, "the restart's deadline counts");
        t.take(go, 4000);
        t.take(end, 5000);
        assert_eq!(t.next_deadline(), None);
        assert!(t.missing(10_000).is_empty(), "a stopped timer is not missing");
        assert_eq!(t.timeout(out, 6000), Timing::Early, "a timeout after a stop has no timer running");
        assert_eq!(t.timeout(out, 0), Timing::Early, "nor one before any start");
    }

    #[test]
    fn a_timer_running_past_its_slack_is_missing_once() {
        let (mut t, table) = timers();
        let (go, out) = (table.id("go").unwrap(), table.id("T_timeout").unwrap());
        t.take(go, 100);
        assert!(t.missing(2109).is_empty(), "within the slack the target may still raise it");
        assert_eq!(t.missing(2110), [out]);
        assert!(t.missing(9999).is_empty(), "counted once");
        t.take(go, 0);
        t.reset();
        assert_eq!(t.next_deadline(), None);
    }
}
