//! A closed-loop session: the virtual plant and the monitor driving a firmware over a byte link.
//!
//! The session owns the link protocol's control side. [`Session::sync`] brings the firmware to a known
//! point (HOLD, STATUS to collect its counters, RESET, wait for READY, GO); [`Session::run`] then
//! exchanges events until the monitor has seen the requested number: the plant's events go out after
//! their drawn delays (bursts as one write), every command coming back is judged, taken by the plant
//! and may be answered at once (a race). A violation, an unresolved desynchronisation, a firmware fault
//! or a stall resets both sides and the run goes on; all of it is counted.
//!
//! A stall — the closed loop blocked — is judged on what the two sides did, never on how long they
//! took, so that a loaded machine cannot make one: in lock-step a round in which neither the plant nor
//! the firmware moved, in steps a step in which neither moved, in realtime a firmware that, asked
//! (HOLD, STATUS: every command it fired is judged), fired nothing while plants ‖ supervisors enable
//! no command. Time limits only catch a firmware that stopped answering or deciding
//! ([`SessionConfig`]).
//!
//! In lock-step ([`SessionConfig::lockstep`], the default) time plays no part: every round the plant's
//! emission goes out while the firmware is held, followed by a SYNC request and GO, and the next round
//! starts when the firmware answers SYNC (it decided until nothing was enabled). So every decision is
//! taken on every event sent before it, and the trace is a function of the seeds alone — the same
//! whatever the table layout or the machine's load. Commands are judged as taken after the round's
//! events were read.
//!
//! In steps ([`SessionConfig::step`]), while the plant steers towards transitions not taken yet and
//! whatever the timing, the firmware stays on hold and the plant takes a turn before each of its
//! decisions: it sends the events the steering prefers to the controller's choice (none when the
//! controller's is better), then STEP, and the firmware decides once on all of them, answers SYNC and
//! holds again. A controller that never runs out of commands (actuators it may switch at will) would
//! otherwise fire hundreds of commands between two looks of the plant, and every target behind one of
//! the plant's events would stay out of reach. Once coverage is full, the run goes on in its timing —
//! unless the controller never ran out of commands in a step: lock-step rounds would never end, and
//! in realtime it would outrun the plant, which would decide on states long left. Such a run stays in
//! steps to its end, the plant taking its turn in its own measure (a drawn burst length per step).
//!
//! A project with timers (`[[timers]]`: the monitor has [`Timers`](crate::monitor::Timers)) runs on a
//! *virtual clock* in milliseconds, always in lock-step rounds and steps. The plant's delays are drawn
//! in it: after a command `c`, the plant's next emission is due `c`'s answer delay later
//! ([`PlantConfig::answer_delay_us`](crate::plant::PlantConfig::answer_delay_us), in whole ms), after an
//! emission the plant's own delay later. Each round (or step) first moves the clock on, with the target
//! held, by [`TIME`](crate::link::protocol::TIME) messages sent before the round's events:
//!
//! - to the plant's emission, when it is due before the earliest deadline `d` of a running timer — the
//!   round then carries the emission;
//! - else to `d - 1` (a round without events: a timeout raised in it is early), then to `d + slack` (a
//!   timeout raised in it is on time; a timer still running once the target has answered SYNC is a
//!   missing timeout). This *deadline round* is split: HOLD, TIME, STATUS, and the timeouts the held
//!   target raised come back before the STATUS answer and are judged; only then are the round's events
//!   drawn (an emission due by `d + slack`: a late sensor), sent with SYNC and GO — so the target takes
//!   the timeout, then the late event, and decides on both, as a controller does whose sensor comes
//!   between the timeout and its reaction.
//!
//! While the plant steers and a timeout leads to a transition not taken yet sooner than any of its own
//! events, the plant holds its emission back to the deadline round, within the delay range the emission
//! was drawn from ([`Session::awaits_timeout`]) — so the fault path after a late sensor is reached in a
//! few hundred events rather than by the chance of a draw landing in the slack.
//!
//! The target reports each timeout as a byte with its event id; the session hands it to the monitor
//! ([`Monitor::timeout`]), and the plant takes it from the monitor's state: the plant never raises a
//! timeout itself. So the trace stays a function of the seeds.

use std::time::{Duration, Instant};

use crate::link::protocol::{time, Decoder, Frame, GO, HOLD, RESET, STATUS, STEP, SYNC, TABLES};
use crate::link::ByteLink;
use crate::model::EventId;
use crate::monitor::{FirmwareCounters, Monitor, Move, Report, Verdict};
use crate::plant::VirtualPlant;

/// Longest single wait on the link, so the plant's timers stay accurate.
const POLL: Duration = Duration::from_millis(2);
/// Realtime: how long a firmware may be silent, while the plant has nothing to do, before the plant
/// asks where it is ([`Session::probe`]). Only the speed of the run depends on it, never a verdict.
const PROBE_AFTER: Duration = Duration::from_millis(100);
/// How often the progress callback runs.
const PROGRESS_EVERY: Duration = Duration::from_millis(200);
/// Most events the steering adds to an emission to get ahead of the controller's decision.
const MAX_STEERED_BURST: usize = 8;
/// Events without a new transition after which the plant starts to mix its own timing into the
/// steering, and per how many more events the mix grows by a tenth (up to a half).
const STAGNATION: u64 = 250;
/// Lock-step clock: a round's events are stamped at an even multiple of it and its commands one tick
/// later, beyond any read window, so that the controller counts as having read them.
const TICK_US: u64 = 1 << 32;
/// Most commands in one lock-step round: a controller that never goes idle is a stall.
const MAX_ROUND_COMMANDS: usize = 4096;
/// The time a step's command is judged at: after every event sent before its STEP, all of them read.
const READ_ALL: u64 = u64::MAX;

/// What a round awaits from the target ([`Session::await_round`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Answer {
    /// SYNC: it decided until nothing was enabled (or took a STEP's one decision).
    Sync,
    /// STATUS: it took every byte before the request (a deadline round's TIME, while held).
    Status,
}

/// How a round (or step) moves the virtual clock on ([`Session::advance`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Advance {
    /// The round carries the plant's emission.
    emits: bool,
    /// The clock moved.
    moved: bool,
    /// Its TIME reaches a running timer's deadline (and slack): the timeouts it raises come back before
    /// the emission is drawn ([`Session::pass_deadline`]).
    deadline: bool,
}

/// How a session takes turns with the firmware, and how long it waits for it.
///
/// The default is what `codegen run` does: lock-step rounds, in steps while the plant steers. Every
/// verdict of such a run — violations, stalls, coverage — is a function of the seeds alone, so a loaded
/// machine makes it slower, never different. The time limits below only end a run whose firmware has
/// stopped answering; they are far beyond anything load does to one that answers (QEMU and the
/// host-compiled runtime answer in milliseconds; the emulated RP2040's USB link, on a loaded 2-core
/// machine, once took more than 10 s to answer a STATUS — hence 30 s).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SessionConfig {
    /// How long to wait for a READY, STATUS or SYNC answer before the run fails
    /// ([`SessionError::NoAnswer`]).
    pub answer_timeout: Duration,
    /// Realtime only: with nothing for the plant to do, and plants ‖ supervisors enabling a command the
    /// firmware does not fire for this long, the firmware has stopped deciding — a stall (reset). A loop
    /// that is blocked (no command enabled) is a stall as soon as the firmware, asked (HOLD, STATUS),
    /// shows it fired nothing, whatever the time.
    pub stall_timeout: Duration,
    /// Lock-step rounds instead of the plant's timing (see the module documentation): a reproducible
    /// trace, without races or stale decisions. Off ([`SessionConfig::realtime`]) only where timing is
    /// the subject (races, bursts) or the firmware does not answer SYNC (the RP2040 harness).
    pub lockstep: bool,
    /// While the plant steers, run in steps (see the module documentation): the firmware understands
    /// STEP — the QEMU and host-compiled firmware do; the RP2040 harness and the PLC driver do not.
    pub step: bool,
    /// Events without a new transition after which the steering restarts the closed loop: the monitor's
    /// mirror of the controller's choice rounds may have lost step (a choice the guard dropped still
    /// counts in the firmware's round), and a reset puts both back in step.
    pub steering_reset: u64,
    /// The controller's own delays, if it has any ([`OwnDelays`]).
    pub own_delays: Option<OwnDelays>,
}

/// A controller's own delays: timers of its own that no `[[timers]]` entry carries (a sequence net's
/// `[net.delays]` in a PLC program), whose clock moves on the link's TIME alone. A round (or step) in
/// which neither side moved is then a stall only once they have had their time: the session first sends
/// TIME `quantum_ms` at a time, each in a round of its own, until the controller fires or `wait_ms`
/// have passed. Time passes only while the loop waits on nothing else, so the run stays a function of
/// the seeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OwnDelays {
    /// How long to wait in all: the longest delay and one scan.
    pub wait_ms: u64,
    /// The time one round lets pass: shorter than the shortest delay, so a delay started by a command
    /// in a round cannot end in it before the plant had its turn.
    pub quantum_ms: u64,
}

impl Default for SessionConfig {
    fn default() -> Self {
        SessionConfig {
            answer_timeout: Duration::from_secs(30),
            stall_timeout: Duration::from_secs(10),
            lockstep: true,
            step: true,
            steering_reset: 2_000,
            own_delays: None,
        }
    }
}

impl SessionConfig {
    /// The default with the plant's own timing instead of lock-step rounds (`--timing realtime`): its
    /// delays, bursts and races against the firmware's decisions.
    pub fn realtime() -> Self {
        SessionConfig { lockstep: false, ..SessionConfig::default() }
    }
}

/// A session failed to talk to the firmware.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    /// The link failed or closed.
    #[error("link: {0}")]
    Io(#[from] std::io::Error),
    /// The firmware did not answer in time.
    #[error("no {what} answer from the firmware within {} ms", timeout.as_millis())]
    NoAnswer {
        /// What was awaited.
        what: &'static str,
        /// How long.
        timeout: Duration,
    },
    /// The firmware runs other tables than the project's ([`Session::check_tables`]).
    #[error(
        "the firmware runs tables {firmware}, the project's are {}: it was built from another manifest (or \
         before the models changed); build the firmware from this project and flash or boot it again",
        project.join(" or ")
    )]
    OtherTables {
        /// The digest the firmware reported.
        firmware: String,
        /// The digests of the project's tables (one per image: the Cortex-M3's, the Cortex-M0+'s).
        project: Vec<String>,
    },
    /// The firmware answered STATUS but not TABLES before it ([`Session::check_tables`]).
    #[error(
        "the firmware does not report its tables (no answer to TABLES, 0xF9): it predates the tables check \
         or its application does not report them; build the firmware from this project and flash or boot it \
         again"
    )]
    TablesUnreported,
}

/// The virtual plant and the monitor attached to one firmware link; see the module documentation.
pub struct Session<'a, L: ByteLink + ?Sized> {
    link: &'a mut L,
    plant: &'a mut VirtualPlant,
    monitor: &'a mut Monitor,
    config: SessionConfig,
    decoder: Decoder,
    inbox: std::collections::VecDeque<Frame>,
    start: Instant,
    /// Times the plant's next emission is due; `None` while it has nothing to produce.
    next_emit: Option<Instant>,
    /// Realtime: the firmware's last command or the plant's last emission.
    last_activity: Instant,
    /// Realtime: the firmware was asked where it is ([`Session::probe`]) since `last_activity`.
    probed: bool,
    /// Whether the plant already held back once since the controller's last command.
    waited: bool,
    /// Transitions taken so far, and the event count at which the last new one was taken.
    progress: (usize, u64),
    /// Bytes from the firmware that the protocol does not define in its direction.
    garbled: u64,
    /// Whether the monitor is in step with the firmware: false from a violation, an unresolved
    /// desynchronisation, SAFE or a restart until the next reset; the firmware's commands in between
    /// are not judged.
    in_step: bool,
    /// Lock-step: the firmware was restarted with a SYNC request whose answer the next round awaits.
    settle: bool,
    /// Lock-step: the rounds run so far (the clock).
    round: u64,
    /// The run goes in steps: the firmware holds between decisions (see the module documentation).
    stepping: bool,
    /// A step found the controller without a command: it may run freely once coverage is full.
    idle_seen: bool,
    /// With timers: the virtual clock, in ms (see the module documentation).
    now_ms: u64,
    /// With timers: when the plant's next emission is due on the virtual clock; `None` until drawn.
    emit_at: Option<u64>,
    /// In steps: the plant held back for a command the controller did not fire, and sends at least one
    /// event at the next step.
    plant_turn: bool,
    /// With timers: the latest the plant's next emission may come, the upper end of the delay range it
    /// was drawn from (the steering may hold it back until then, see [`Session::awaits_timeout`]).
    emit_latest: u64,
}

impl<'a, L: ByteLink + ?Sized> Session<'a, L> {
    /// A session over `link`; nothing is sent until [`Session::sync`].
    pub fn new(
        link: &'a mut L,
        plant: &'a mut VirtualPlant,
        monitor: &'a mut Monitor,
        config: SessionConfig,
    ) -> Self {
        let now = Instant::now();
        // Virtual time goes in rounds and steps: a run with timers is in lock-step whatever it was told.
        let config = SessionConfig { lockstep: config.lockstep || !monitor.timers().is_empty(), ..config };
        Session {
            link,
            plant,
            monitor,
            config,
            decoder: Decoder::default(),
            inbox: Default::default(),
            start: now,
            next_emit: Some(now),
            last_activity: now,
            probed: false,
            waited: false,
            progress: (0, 0),
            garbled: 0,
            in_step: true,
            settle: false,
            round: 0,
            stepping: false,
            idle_seen: false,
            now_ms: 0,
            emit_at: None,
            plant_turn: false,
            emit_latest: 0,
        }
    }

    /// The virtual clock, in ms (0 all along without timers).
    pub fn virtual_ms(&self) -> u64 {
        self.now_ms
    }

    /// With timers, moves the virtual clock on for the next round or step (see the module
    /// documentation) and appends its TIME messages to `bytes`. Without timers: the emission, no time.
    fn advance(&mut self, bytes: &mut Vec<u8>) -> Advance {
        if self.monitor.timers().is_empty() {
            return Advance { emits: true, moved: false, deadline: false };
        }
        let now = self.now_ms;
        let mut emit_at = match self.emit_at {
            Some(t) => t,
            None => {
                let (_, hi) = self.plant.delay_range_us(None);
                self.emit_latest = now + hi / 1000;
                *self.emit_at.insert(now + self.plant.next_delay_us(None) / 1000)
            }
        };
        let deadline = self.monitor.timers().next_deadline();
        if let Some(d) = deadline {
            if emit_at < d && d <= self.emit_latest && self.awaits_timeout() {
                emit_at = d;
                self.emit_at = Some(d);
            }
        }
        let slack = self.monitor.timers().slack_ms();
        let (to, emits, deadline) = match deadline {
            Some(d) if emit_at >= d && now + 1 < d => (d - 1, false, false),
            Some(d) if emit_at >= d => (d + slack, emit_at <= d + slack, true),
            _ => (emit_at, true, false),
        };
        let to = to.max(now);
        bytes.extend(time(to - now));
        self.now_ms = to;
        self.monitor.clock(to);
        Advance { emits, moved: to > now, deadline }
    }

    /// Steering, with a timer running: whether the plant should hold its emission back until the
    /// timer's deadline, because a timeout leads to a transition not taken yet sooner than any of the
    /// plant's own events — a sensor that comes late, the very fault a timeout is there for. The plant
    /// holds back only within the delay range its emission was drawn from ([`Session::advance`]), and
    /// its emission then comes in the deadline round, after the timeout.
    fn awaits_timeout(&mut self) -> bool {
        if !self.plant.steers() || !self.monitor.is_steering() {
            return false;
        }
        let timeouts: Vec<EventId> = self.monitor.timers().timeouts().collect();
        let Some(best) = timeouts.into_iter().filter_map(|e| self.monitor.rank_after(e)).min() else {
            return false;
        };
        let own = self.plant.enabled_uncontrollable();
        own.into_iter().all(|e| self.monitor.rank_after(e).is_none_or(|r| r > best))
    }

    /// With timers, a round (or step) whose TIME reaches a running timer's deadline: the target, held,
    /// is asked for STATUS after the TIME, and every timeout it raised comes back before the answer and
    /// is judged before the round's events are drawn — so that the plant's emission due in the same
    /// round (a late sensor) comes after the timeout, and the controller decides on both. Returns
    /// whether the round goes on (`false`: it ended in a restart).
    fn pass_deadline(&mut self, mut bytes: Vec<u8>, t: u64) -> Result<bool, SessionError> {
        bytes.push(STATUS);
        self.link.send(&bytes)?;
        Ok(self.await_round(t, Answer::Status)?.is_some())
    }

    /// With timers, after a round's emission: the next one is drawn afresh, unless the plant held it
    /// back with events to send (the steering let the controller go first).
    fn emitted(&mut self, sent: usize) {
        if sent > 0 || self.plant.enabled_uncontrollable().is_empty() {
            self.emit_at = None;
        }
    }

    /// With timers, once the target answered a round: the timers it let run past their deadline and
    /// slack are missing timeouts (a violation: both sides are reset). Returns whether it was so.
    fn judge_missing(&mut self) -> Result<bool, SessionError> {
        if self.monitor.timers().is_empty() || self.monitor.missing_timeouts() != Verdict::Violation {
            return Ok(false);
        }
        self.out_of_step()?;
        Ok(true)
    }

    /// The monitor's figures so far.
    pub fn report(&self) -> &Report {
        self.monitor.report()
    }

    /// Asks the firmware which tables it runs (HOLD, TABLES, STATUS) and refuses it unless it reports the
    /// digest of one of `project` (the digests of the project's table images): driving a firmware built
    /// from other tables would judge it against the wrong supervisors. A firmware that does not know
    /// TABLES answers STATUS alone (and counts an unknown byte): refused at once, without waiting out a
    /// timeout. The firmware is left on hold; call before [`Session::sync`].
    pub fn check_tables(&mut self, project: &[String]) -> Result<(), SessionError> {
        self.link.send(&[HOLD, TABLES, STATUS])?;
        let mut reported = None;
        self.await_frame("STATUS", false, |f| match f {
            Frame::Tables(digest) => {
                reported = Some(digest);
                false
            }
            frame => matches!(frame, Frame::Status(_)),
        })?;
        let firmware = String::from_utf8_lossy(&reported.ok_or(SessionError::TablesUnreported)?).into_owned();
        if project.contains(&firmware) {
            return Ok(());
        }
        Err(SessionError::OtherTables { firmware, project: project.to_vec() })
    }

    /// Brings the firmware to its initial state, in step with plant and monitor, and lets it decide.
    /// With `count`, the counters the firmware had (since its last reset) go into the report; the first
    /// sync of a run passes `false`, since what the firmware did before was not monitored.
    pub fn sync(&mut self, count: bool) -> Result<(), SessionError> {
        self.restart(count)?;
        if count {
            self.monitor.report_mut().resyncs += 1;
        }
        Ok(())
    }

    /// Resets firmware, plant and monitor to the initial state (the firmware's counters collected when
    /// `count`) and lets the firmware decide again.
    fn restart(&mut self, count: bool) -> Result<(), SessionError> {
        self.hold_and_collect(count)?;
        self.link.send(&[RESET])?;
        self.await_frame("READY", count, |f| f == Frame::Ready)?;
        self.plant.reset();
        self.monitor.reset();
        self.emit_at = None;
        self.plant_turn = false;
        self.in_step = true;
        let steps_on = self.monitor.is_steering() || (self.stepping && !self.idle_seen);
        self.stepping = self.config.step && self.plant.steers() && steps_on;
        if self.stepping {
            // On hold (the RESET kept it) until the first step.
            self.settle = false;
            self.active();
            return Ok(());
        }
        self.release()
    }

    /// Lets the firmware decide freely in the session's timing. Lock-step: the decisions from here end
    /// with a SYNC answer, awaited by the next round; the request goes before GO so that nothing reaches
    /// the firmware while it decides.
    fn release(&mut self) -> Result<(), SessionError> {
        self.stepping = false;
        self.settle = self.config.lockstep;
        self.link.send(if self.settle { &[SYNC, GO][..] } else { &[GO][..] })?;
        self.next_emit = Some(Instant::now());
        self.active();
        Ok(())
    }

    /// Stops the firmware deciding and adds its counters to the report (with `count`). Commands it fired
    /// before the HOLD reached it are judged as they arrive, with `count`; after the STATUS answer it
    /// fires none. Call at the end of a run, or before a reset.
    pub fn hold_and_collect(&mut self, count: bool) -> Result<FirmwareCounters, SessionError> {
        self.link.send(&[HOLD, STATUS])?;
        let mut counters = FirmwareCounters::default();
        self.await_frame("STATUS", count, |f| match f {
            Frame::Status(c) => {
                counters = c.into();
                true
            }
            _ => false,
        })?;
        if count {
            self.monitor.firmware_counters(counters);
        }
        Ok(counters)
    }

    /// Runs the closed loop until the monitor has seen `events` events in all, calling `progress` now
    /// and then.
    pub fn run(&mut self, events: u64, progress: &mut dyn FnMut(&Report)) -> Result<(), SessionError> {
        self.run_steps(events, progress)?;
        if self.config.lockstep {
            return self.run_lockstep(events, progress);
        }
        let mut last_progress = Instant::now();
        let mut buf = [0u8; 256];
        while self.monitor.report().events < events {
            self.explore_when_stuck()?;
            let now = Instant::now();
            if self.next_emit.is_some_and(|t| t <= now) {
                self.emit()?;
            }
            let wait = match self.next_emit {
                _ if !self.inbox.is_empty() => Duration::ZERO,
                Some(t) => t.saturating_duration_since(Instant::now()).min(POLL),
                None => POLL,
            };
            let n = self.link.recv(&mut buf, wait)?;
            for &b in &buf[..n] {
                if let Some(frame) = self.decoder.push(b) {
                    self.inbox.push_back(frame);
                }
            }
            while let Some(frame) = self.inbox.pop_front() {
                self.handle(frame)?;
                // A steering plant looks after every command, before the next is judged.
                let due = self.next_emit.is_some_and(|t| t <= Instant::now());
                if due && self.plant.steers() && self.monitor.is_steering() {
                    break;
                }
            }
            if self.next_emit.is_none() {
                let silent = self.last_activity.elapsed();
                if !self.probed && silent > PROBE_AFTER {
                    self.probe()?;
                } else if silent > self.config.stall_timeout {
                    self.monitor.report_mut().stalls += 1;
                    self.sync(true)?;
                }
            }
            if last_progress.elapsed() >= PROGRESS_EVERY {
                last_progress = Instant::now();
                progress(self.monitor.report());
            }
        }
        Ok(())
    }

    /// [`Session::run`] in steps while the plant steers (see the module documentation); the firmware is
    /// released when coverage is full, unless it never ran out of commands.
    fn run_steps(&mut self, events: u64, progress: &mut dyn FnMut(&Report)) -> Result<(), SessionError> {
        let mut last_progress = Instant::now();
        while self.stepping && self.monitor.report().events < events {
            self.explore_when_stuck()?;
            if !self.stepping {
                break;
            }
            self.step()?;
            if self.stepping && self.idle_seen && !self.monitor.is_steering() {
                self.release()?;
            }
            if last_progress.elapsed() >= PROGRESS_EVERY {
                last_progress = Instant::now();
                progress(self.monitor.report());
            }
        }
        Ok(())
    }

    /// One step: the plant's events while the steering prefers them to the controller's choice (at most
    /// [`MAX_STEERED_BURST`]; after full coverage, a drawn burst length), then STEP, and the firmware's
    /// one decision judged. Neither moving is a stall.
    fn step(&mut self) -> Result<(), SessionError> {
        let t = self.micros();
        let mut bytes = Vec::new();
        let Advance { emits, moved, deadline } = self.advance(&mut bytes);
        if deadline && !self.pass_deadline(std::mem::take(&mut bytes), t)? {
            return Ok(());
        }
        let most = match emits {
            false => 0,
            true if self.monitor.is_steering() => MAX_STEERED_BURST,
            true => self.plant.burst_len(),
        };
        let timed = bytes.len();
        let turn = std::mem::take(&mut self.plant_turn);
        while bytes.len() - timed < most
            && ((turn && bytes.len() == timed) || self.monitor.next_move() != Move::Controller)
        {
            let monitor = &mut *self.monitor;
            let Some(e) = self.plant.emit_one(|e| monitor.rank_after(e)) else { break };
            bytes.push(e.as_u32() as u8);
            if self.monitor.uncontrollable(e, t) == Verdict::Violation {
                self.link.send(&bytes)?;
                return self.out_of_step();
            }
        }
        let sent = bytes.len() - timed;
        if emits {
            self.emitted(sent);
        }
        bytes.push(STEP);
        self.link.send(&bytes)?;
        self.active();
        let commands = self.await_round(READ_ALL, Answer::Sync)?;
        if commands.is_some() && self.judge_missing()? {
            return Ok(());
        }
        self.idle_seen |= commands == Some(0);
        if commands == Some(0) && sent == 0 && !moved {
            if emits && !turn && !self.plant.enabled_uncontrollable().is_empty() {
                // The plant held back for a command the controller did not fire (one that only fires
                // what its sequence asks for): the plant's turn, at the next step.
                self.plant_turn = true;
            } else if !self.wait_own_delays()? {
                self.monitor.report_mut().stalls += 1;
                self.sync(true)?;
            }
        }
        Ok(())
    }

    /// [`Session::run`] in lock-step rounds (see the module documentation).
    fn run_lockstep(&mut self, events: u64, progress: &mut dyn FnMut(&Report)) -> Result<(), SessionError> {
        let mut last_progress = Instant::now();
        while self.monitor.report().events < events {
            self.explore_when_stuck()?;
            if std::mem::take(&mut self.settle)
                && self.await_round((2 * self.round + 1) * TICK_US, Answer::Sync)?.is_none()
            {
                continue;
            }
            self.round += 1;
            let mut bytes = vec![HOLD];
            let Advance { emits, moved, deadline } = self.advance(&mut bytes);
            if deadline && !self.pass_deadline(std::mem::take(&mut bytes), 2 * self.round * TICK_US)? {
                continue;
            }
            let (events, _, violated) =
                if emits { self.draw(2 * self.round * TICK_US) } else { (Vec::new(), false, false) };
            let sent = events.len();
            if emits {
                self.emitted(sent);
            }
            bytes.extend(events);
            bytes.extend([SYNC, GO]);
            self.link.send(&bytes)?;
            if violated {
                self.out_of_step()?;
                continue;
            }
            match self.await_round((2 * self.round + 1) * TICK_US, Answer::Sync)? {
                Some(_) if self.judge_missing()? => {}
                Some(0) if sent == 0 && !moved && !self.wait_own_delays()? => {
                    self.monitor.report_mut().stalls += 1;
                    self.sync(true)?;
                }
                _ => {}
            }
            if last_progress.elapsed() >= PROGRESS_EVERY {
                last_progress = Instant::now();
                progress(self.monitor.report());
            }
        }
        Ok(())
    }

    /// A round or step in which nothing moved: lets the controller's own delays pass ([`OwnDelays`]), a
    /// quantum per round (per step while stepping), until it fires (or the round ends in a restart).
    /// Returns whether it moved; without own delays, or once they have passed, it did not (a stall).
    fn wait_own_delays(&mut self) -> Result<bool, SessionError> {
        let Some(delays) = self.config.own_delays else { return Ok(false) };
        let mut waited = 0;
        while waited < delays.wait_ms {
            let quantum = (delays.wait_ms - waited).min(delays.quantum_ms.max(1));
            waited += quantum;
            let (t, mut bytes) = if self.stepping {
                (READ_ALL, Vec::new())
            } else {
                self.round += 1;
                ((2 * self.round + 1) * TICK_US, vec![HOLD])
            };
            bytes.extend(time(quantum));
            bytes.extend(if self.stepping { &[STEP][..] } else { &[SYNC, GO][..] });
            self.link.send(&bytes)?;
            if self.await_round(t, Answer::Sync)? != Some(0) {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Judges the firmware's commands (and timeouts), at time `t`, until it gives `answer`: how many
    /// there were, or `None` when the round ended in a restart (a violation, a fault, a reboot, a
    /// controller that does not go idle).
    fn await_round(&mut self, t: u64, answer: Answer) -> Result<Option<usize>, SessionError> {
        let mut commands = 0;
        let mut buf = [0u8; 256];
        let mut deadline = Instant::now() + self.config.answer_timeout;
        loop {
            while let Some(frame) = self.inbox.pop_front() {
                deadline = Instant::now() + self.config.answer_timeout;
                match frame {
                    Frame::Sync if answer == Answer::Sync => return Ok(Some(commands)),
                    Frame::Status(_) if answer == Answer::Status => return Ok(Some(commands)),
                    Frame::Command(c) => {
                        commands += 1;
                        let verdict = self.judge(c, t);
                        let stuck = commands > MAX_ROUND_COMMANDS;
                        if stuck {
                            self.monitor.report_mut().stalls += 1;
                        }
                        if stuck
                            || matches!(verdict, Verdict::Desync { resolved: false } | Verdict::Violation)
                        {
                            self.out_of_step()?;
                            return Ok(None);
                        }
                    }
                    Frame::Safe | Frame::Ready => {
                        self.handle(frame)?;
                        return Ok(None);
                    }
                    Frame::Status(_) | Frame::Tables(_) | Frame::Sync => {}
                    Frame::Unknown(_) => self.garbled += 1,
                }
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                let what = if answer == Answer::Sync { "SYNC" } else { "STATUS" };
                return Err(SessionError::NoAnswer { what, timeout: self.config.answer_timeout });
            }
            let n = self.link.recv(&mut buf, left.min(Duration::from_millis(50)))?;
            for &b in &buf[..n] {
                if let Some(frame) = self.decoder.push(b) {
                    self.inbox.push_back(frame);
                }
            }
        }
    }

    /// Ends the run: holds the firmware, collects its counters and completes the report.
    pub fn finish(mut self) -> Result<Report, SessionError> {
        self.hold_and_collect(true)?;
        let seconds = self.start.elapsed().as_secs_f64();
        let garbled = self.garbled;
        self.monitor.list_uncovered();
        let report = self.monitor.report_mut();
        report.garbled = garbled;
        report.finish(seconds);
        Ok(report.clone())
    }

    /// Holds the firmware, sends `n` uncontrollable events the plant produces one after another as one
    /// write, and lets the firmware go: a burst of `n` inputs between two of its decisions. Returns
    /// the number sent (fewer when the plant ran out of events).
    pub fn burst(&mut self, n: usize) -> Result<usize, SessionError> {
        self.link.send(&[HOLD])?;
        let mut bytes = Vec::with_capacity(n + 1);
        let t = self.micros();
        while bytes.len() < n {
            let Some(e) = self.plant.emit_one(|_| None) else { break };
            self.monitor.uncontrollable(e, t);
            bytes.push(e.as_u32() as u8);
        }
        let sent = bytes.len();
        bytes.push(GO);
        self.link.send(&bytes)?;
        self.active();
        Ok(sent)
    }

    fn micros(&self) -> u64 {
        u64::try_from(self.start.elapsed().as_micros()).unwrap_or(u64::MAX)
    }

    /// The plant's next emission: one event or a burst, sent as one write. When the plant steers (see
    /// [`Move`]), it first lets the controller choose if that is better, waiting for its command however
    /// long it takes (a slow controller, or a loaded machine, changes when the plant moves, not what it
    /// chooses), and goes on past the drawn length, holding the controller, while its own next event
    /// beats the controller's choice.
    ///
    /// While it steers, the plant first stops the controller ([`Session::pause`]) and decides on the
    /// state the controller really is in: a controller that never runs out of commands (actuators it may
    /// switch at will) fires faster than the plant reads, and an event chosen on the commands read so far
    /// would reach it hundreds of commands late, in a state it was not chosen for.
    fn emit(&mut self) -> Result<(), SessionError> {
        let steers = self.plant.steers();
        let paused = steers && self.monitor.is_steering();
        if paused {
            self.pause()?;
            if !self.in_step {
                return self.out_of_step();
            }
        }
        if steers && !self.waited && self.monitor.next_move() == Move::Controller {
            if paused {
                self.link.send(&[GO])?;
            }
            // The controller has a command to fire: its command ends the wait, however long it takes.
            self.waited = true;
            self.next_emit = None;
            return Ok(());
        }
        let (mut bytes, held, violated) = self.draw(self.micros());
        if bytes.is_empty() {
            if paused {
                self.link.send(&[GO])?;
            }
            self.next_emit = None;
            return Ok(());
        }
        if held || paused {
            if !paused {
                bytes.insert(0, HOLD);
            }
            bytes.push(GO);
        }
        self.link.send(&bytes)?;
        if violated {
            return self.out_of_step();
        }
        self.active();
        self.next_emit = Some(Instant::now() + Duration::from_micros(self.plant.next_delay_us(None)));
        Ok(())
    }

    /// The plant's next emission at time `t`, judged: its events (the drawn length, and more while the
    /// steering gets ahead of the controller), whether it went past the drawn length (then the caller
    /// holds the controller over it), and whether an event was a violation (the last one then).
    fn draw(&mut self, t: u64) -> (Vec<u8>, bool, bool) {
        let steers = self.plant.steers();
        let len = self.plant.burst_len();
        let mut bytes = Vec::with_capacity(len);
        let mut held = false;
        let mut violated = false;
        while !violated {
            if bytes.len() >= len {
                let ahead = steers && bytes.len() < len + MAX_STEERED_BURST;
                if !(ahead && self.monitor.next_move() == Move::PlantFirst) {
                    break;
                }
                held = true;
            }
            let monitor = &mut *self.monitor;
            let Some(e) = self.plant.emit_one(|e| monitor.rank_after(e)) else { break };
            bytes.push(e.as_u32() as u8);
            violated = self.monitor.uncontrollable(e, t) == Verdict::Violation;
        }
        (bytes, held, violated)
    }

    /// Stops the controller deciding and judges every command it fired until then (HOLD, then STATUS,
    /// whose answer comes after the last of them; its counters are not added, for the firmware's
    /// counters since its reset are collected once, at the next reset or the end). The controller stays
    /// on hold until the caller sends GO. Returns whether it fired a command meanwhile.
    fn pause(&mut self) -> Result<bool, SessionError> {
        let commands = self.monitor.report().commands;
        self.link.send(&[HOLD, STATUS])?;
        self.await_frame("STATUS", true, |f| matches!(f, Frame::Status(_)))?;
        let fired = self.monitor.report().commands != commands;
        if fired {
            self.active();
        }
        Ok(fired)
    }

    /// Realtime, the plant with nothing to do and the firmware silent for [`PROBE_AFTER`]: is the loop
    /// blocked, or is the firmware only slow? The firmware is held and every command it fired is judged
    /// ([`Session::pause`]); then it has read every event sent, so it is where the monitor is. A command
    /// among them moves the loop on. Without one, plants ‖ supervisors enabling no command is a stall,
    /// judged on the state and not on the time, so a loaded machine cannot make one; enabling one, the
    /// firmware has it to fire and is let go, and only [`SessionConfig::stall_timeout`] of silence more
    /// makes it a stall.
    fn probe(&mut self) -> Result<(), SessionError> {
        let fired = self.pause()?;
        if !self.in_step {
            return self.out_of_step();
        }
        if fired {
            self.waited = false;
            self.next_emit = Some(Instant::now());
        } else if self.monitor.commands_enabled() {
            self.probed = true;
        } else {
            self.monitor.report_mut().stalls += 1;
            return self.sync(true);
        }
        self.link.send(&[GO])?;
        Ok(())
    }

    /// The firmware fired or the plant sent: the loop moves, and a new silence starts.
    fn active(&mut self) {
        self.last_activity = Instant::now();
        self.probed = false;
    }

    /// Lets the plant mix its own timing into the steering while no new transition is taken, and
    /// restarts the closed loop when that goes on for long.
    fn explore_when_stuck(&mut self) -> Result<(), SessionError> {
        let report = self.monitor.report();
        let taken = report.coverage.iter().map(|c| c.taken).sum();
        if taken != self.progress.0 {
            self.progress = (taken, report.events);
        }
        let stuck = report.events - self.progress.1;
        if stuck >= self.config.steering_reset && self.monitor.is_steering() && self.plant.steers() {
            self.progress.1 = report.events;
            self.monitor.report_mut().steering_resets += 1;
            return self.restart(true);
        }
        let tenths = (stuck / STAGNATION).min(5) as u32;
        self.plant.explore(tenths * 100);
        Ok(())
    }

    fn handle(&mut self, frame: Frame) -> Result<(), SessionError> {
        match frame {
            Frame::Command(c) => {
                self.active();
                self.waited = false;
                match self.judge(c, self.micros()) {
                    Verdict::Ok | Verdict::Desync { resolved: true } => {
                        let mut delay = Duration::from_micros(
                            self.plant.next_delay_us(Some(EventId::from_u32(u32::from(c)))),
                        );
                        // While it steers, the plant looks at every command (see `emit`).
                        if self.plant.steers() && self.monitor.is_steering() {
                            delay = Duration::ZERO;
                        }
                        let due = Instant::now() + delay;
                        self.next_emit = Some(self.next_emit.map_or(due, |t| t.min(due)));
                    }
                    Verdict::Desync { resolved: false } | Verdict::Violation => self.out_of_step()?,
                }
            }
            Frame::Safe => {
                self.monitor.firmware_safe();
                self.out_of_step()?;
            }
            Frame::Ready => {
                // Unasked: the firmware restarted, and its state is no longer the monitor's.
                self.monitor.report_mut().reboots += 1;
                self.out_of_step()?;
            }
            Frame::Status(_) | Frame::Tables(_) | Frame::Sync => {}
            Frame::Unknown(_) => self.garbled += 1,
        }
        Ok(())
    }

    /// The monitor's verdict on command byte `c` at time `t`; where it takes the command, the plant
    /// takes it too.
    ///
    /// With timers, a byte that is a timer's timeout is the target's timeout, judged as such
    /// ([`Monitor::timeout`]); a command taken makes the plant's answer due on the virtual clock after
    /// the command's answer delay (or sooner, when an emission was due already).
    fn judge(&mut self, c: u8, t: u64) -> Verdict {
        let e = EventId::from_u32(u32::from(c));
        let timeout = self.monitor.timers().is_timeout(e);
        let verdict = if timeout { self.monitor.timeout(e, t) } else { self.monitor.command(e, t) };
        if matches!(verdict, Verdict::Ok | Verdict::Desync { resolved: true }) {
            self.plant.set_state(self.monitor.plant_state());
            if !timeout && !self.monitor.timers().is_empty() {
                let due = self.now_ms + self.plant.next_delay_us(Some(e)) / 1000;
                if self.emit_at.is_none_or(|t| due < t) {
                    self.emit_at = Some(due);
                    self.emit_latest = self.now_ms + self.plant.delay_range_us(Some(e)).1 / 1000;
                }
            }
        }
        verdict
    }

    /// The monitor lost step with the firmware (a violation, an unresolved desynchronisation, SAFE, a
    /// restart): both sides are reset, and what the firmware fires until then is not judged.
    fn out_of_step(&mut self) -> Result<(), SessionError> {
        self.in_step = false;
        self.sync(true)
    }

    /// A frame that arrived while [`Session::await_frame`] waited for another: with `judged`, what the
    /// firmware did up to the sync point is judged and counted (a command, SAFE, a restart, a garbled
    /// byte); without, it predates the monitored run and is dropped. Nothing here resynchronises: the
    /// caller is on its way to a reset or to the end, or finds the monitor out of step (`in_step`).
    fn late(&mut self, frame: Frame, judged: bool) {
        if !judged {
            return;
        }
        match frame {
            Frame::Command(_) | Frame::Safe if !self.in_step => {}
            Frame::Command(c) => {
                if matches!(
                    self.judge(c, self.micros()),
                    Verdict::Desync { resolved: false } | Verdict::Violation
                ) {
                    self.in_step = false;
                }
            }
            Frame::Safe => {
                self.monitor.firmware_safe();
                self.in_step = false;
            }
            Frame::Ready => {
                self.monitor.report_mut().reboots += 1;
                self.in_step = false;
            }
            Frame::Status(_) | Frame::Tables(_) | Frame::Sync => {}
            Frame::Unknown(_) => self.garbled += 1,
        }
    }

    /// Reads until `want` accepts a frame; the frames before it go to [`Session::late`].
    fn await_frame(
        &mut self,
        what: &'static str,
        judged: bool,
        mut want: impl FnMut(Frame) -> bool,
    ) -> Result<(), SessionError> {
        let deadline = Instant::now() + self.config.answer_timeout;
        let mut buf = [0u8; 256];
        loop {
            while let Some(frame) = self.inbox.pop_front() {
                if want(frame) {
                    return Ok(());
                }
                self.late(frame, judged);
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(SessionError::NoAnswer { what, timeout: self.config.answer_timeout });
            }
            let n = self.link.recv(&mut buf, left.min(Duration::from_millis(50)))?;
            for &b in &buf[..n] {
                if let Some(frame) = self.decoder.push(b) {
                    self.inbox.push_back(frame);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::VecDeque;
    use std::thread::JoinHandle;

    use super::*;
    use crate::link::memory::{self, MemoryLink};
    use crate::link::protocol::{EXIT, READY, STATUS_BYTES, TIME};
    use crate::manifest::TimerSpec;
    use crate::model::testing::machine;
    use crate::model::EventTable;
    use crate::monitor::{TimeoutFigures, Timers};
    use crate::plant::PlantConfig;

    /// Event ids of the scripted loop: M `go` (command) / `done`, and T's timeout.
    struct Ids {
        go: u8,
        done: u8,
        timeout: u8,
    }

    /// A scripted target on the other end of `link`: it fires `go` whenever M is idle (at each SYNC or
    /// STEP), runs timer T (2000 ms from `go`, stopped by `done`) on the TIME it is sent, and raises the
    /// timeout `skew_ms` after its deadline (negative: before); it answers RESET, STATUS, SYNC and STEP
    /// as a firmware does, and returns its virtual clock on EXIT.
    fn scripted(mut link: MemoryLink, ids: Ids, skew_ms: i64) -> JoinHandle<u64> {
        std::thread::spawn(move || {
            let (mut clock, mut deadline, mut busy) = (0i64, None::<i64>, false);
            let mut queue: VecDeque<u8> = VecDeque::new();
            let mut buf = [0u8; 256];
            link.send(&[READY]).unwrap();
            loop {
                let n = link.recv(&mut buf, Duration::from_millis(20)).unwrap();
                queue.extend(&buf[..n]);
                while let Some(b) = queue.pop_front() {
                    let mut out = Vec::new();
                    match b {
                        RESET => {
                            (busy, deadline) = (false, None);
                            out.push(READY);
                        }
                        STATUS => {
                            out.push(STATUS);
                            out.extend([0; STATUS_BYTES]);
                        }
                        TIME if queue.len() < 2 => {
                            queue.push_front(TIME);
                            break;
                        }
                        TIME => {
                            clock += i64::from(u16::from_le_bytes([queue[0], queue[1]]));
                            queue.drain(..2);
                            if deadline.is_some_and(|d| clock >= d + skew_ms) {
                                deadline = None;
                                out.push(ids.timeout);
                            }
                        }
                        SYNC | STEP => {
                            if !busy {
                                (busy, deadline) = (true, Some(clock + 2000));
                                out.push(ids.go);
                            }
                            out.push(SYNC);
                        }
                        EXIT => return clock as u64,
                        e if e == ids.done => (busy, deadline) = (false, None),
                        _ => {}
                    }
                    link.send(&out).unwrap();
                }
            }
        })
    }

    /// M with timer T over the scripted target skewed by `skew_ms`, for 120 events with the plant's
    /// answer to `go` 1–3 s later: the report, and the virtual clocks of host and target at the end.
    fn run(skew_ms: i64, slack_ms: u64) -> (Report, u64, u64) {
        let m = machine("M", "go", "done");
        let spec = TimerSpec {
            name: "T".into(),
            start: vec!["go".into()],
            stop: vec!["done".into()],
            timeout: None,
            ms: 2000,
        };
        let t = spec.automaton(|e| Some(e == "go")).unwrap();
        let table = EventTable::build([&m, &t]).unwrap();
        let id = |n: &str| table.id(n).unwrap().as_u32() as u8;
        let ids = Ids { go: id("go"), done: id("done"), timeout: id("T_timeout") };
        let config = PlantConfig {
            answer_delay_us: vec![("go".into(), (1_000_000, 3_000_000))],
            ..PlantConfig::default()
        };
        let mut plant = VirtualPlant::new(&[&m, &t], &table, config).unwrap();
        let mut monitor = Monitor::new(&[&m, &t], &[], &table, 500_000).unwrap();
        let timers = Timers::new(&[spec], &table, slack_ms);
        plant.withhold(timers.timeouts());
        monitor.set_timers(timers);
        let (mut host, target) = memory::pair();
        let target = scripted(target, ids, skew_ms);
        let config = SessionConfig { step: false, ..SessionConfig::default() };
        let mut session = Session::new(&mut host, &mut plant, &mut monitor, config);
        session.sync(false).unwrap();
        session.run(120, &mut |_| {}).unwrap();
        let host_ms = session.virtual_ms();
        let report = session.finish().unwrap();
        host.send(&[EXIT]).unwrap();
        (report, host_ms, target.join().unwrap())
    }

    #[test]
    fn the_virtual_clock_runs_both_paths_and_judges_a_target_on_time() {
        let (report, host_ms, target_ms) = run(0, 0);
        let t = report.timeouts.unwrap();
        assert_eq!((report.violations, t.early, t.late, t.missing), (0, 0, 0, 0), "{report:?}");
        assert!(t.on_time > 0, "the plant's 1–3 s answer lets the 2 s timeout come: {t:?}");
        assert!(report.uncontrollable > 0, "and the answer come first: {report:?}");
        assert_eq!(host_ms, target_ms, "every ms the host moved on was sent as TIME");
        assert!(host_ms >= 2000 * t.on_time, "{host_ms}");
        let (again, ..) = run(0, 0);
        assert_eq!(report.trace_sha256, again.trace_sha256, "a function of the seed");
    }

    #[test]
    fn an_early_late_or_missing_timeout_is_a_violation() {
        let early = run(-100, 0).0.timeouts.unwrap();
        assert!(early.early > 0 && early.missing == 0, "{early:?}");
        let missing = run(5, 0).0;
        let t: TimeoutFigures = missing.timeouts.unwrap();
        assert!(t.missing > 0 && t.on_time == 0, "{t:?}");
        assert!(missing.violations >= t.missing, "{missing:?}");
        // Within the slack the host gives, a target 5 ms late is on time.
        let slack = run(5, 5).0;
        assert_eq!((slack.violations, slack.timeouts.unwrap().missing), (0, 0), "{slack:?}");
    }
}
