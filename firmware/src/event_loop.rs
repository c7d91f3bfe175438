//! The firmware's event loop, one turn at a time: the input buffer's bytes (events from the UART or from
//! the pins' interrupts, and the protocol's control bytes) into the decider, then at most one decision,
//! its command out through a [`Port`]. The decider is any [`Decide`]: the supervisor runtime
//! ([`crate::runtime::Runtime`]) or the state-based one ([`crate::state::StateRuntime`]). The same loop
//! runs every application — QEMU's over its UART, the Pico's on its pins — and the host-compiled
//! runtime in the tests.
//!
//! The loop also owns the manifest's timers ([`Timers`], `N` of them, none by default): they observe
//! every event the runtime takes or fires, and time advances them — the link's TIME message
//! ([`crate::link::TIME`]) when a host drives the loop in lock-step, [`EventLoop::elapse`] from a
//! hardware millisecond tick on a board. A timeout that falls due is taken by the runtime as an
//! uncontrollable event, as the plant's are, and sent through the [`Port`] as a command is.

use crate::input_queue::InputConsumer;
use crate::link::{
    Hold, EXIT, GO, HOLD, MAX_EVENT, READY, RESET, SAFE, STATUS, STEP, SYNC, TABLES, TABLES_BYTES, TIME,
};
use crate::runtime::{Applied, Decide, Decision};
use crate::timer::{TimerSpec, Timers};

/// Where the loop's outgoing bytes and notes go (a UART and a log on the target, a vector in tests).
pub trait Port {
    /// Sends one byte to the host.
    fn send(&mut self, byte: u8);

    /// Something worth a log line happened (nothing by default).
    fn note(&mut self, _note: Note) {}
}

/// A log-worthy event of [`EventLoop::turn`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Note {
    /// An uncontrollable input some automaton holding it could not take.
    Unexpected {
        /// The event.
        event: u8,
        /// The first automaton that could not take it.
        automaton: u8,
    },
    /// A byte that means nothing here.
    Unknown(u8),
    /// The runtime entered the safe state.
    Safe,
    /// A choice was dropped by the inexact-synchronisation guard.
    Redecided,
}

/// What the caller does after a [`EventLoop::turn`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Poll {
    /// Work may remain: call again.
    Busy,
    /// Nothing to do until the next input: sleep (`wfi`).
    Idle,
    /// Deciding is on hold: sleep until the next input or GO.
    Held,
    /// The host asked to end: exit with this status.
    Exit(u8),
}

impl Poll {
    /// Whether, after a turn that returned this, the loop may sleep until the next interrupt: nothing
    /// waits in `rx` and, if the turn stopped at a hold, the hold is still on. A GO puts nothing in
    /// `rx`, so one that lands between the turn and this check would otherwise be slept through, with
    /// the host waiting for a decision. Call it with interrupts masked, `wfi` in the same critical
    /// section: what lands after the check leaves its interrupt pending, which wakes the `wfi`. A loop
    /// that cannot exit sleeps on `Exit` as on `Idle`.
    pub fn may_sleep(self, rx: &InputConsumer<'_>, hold: &Hold) -> bool {
        match self {
            Poll::Busy => false,
            Poll::Idle | Poll::Exit(_) => rx.is_empty(),
            Poll::Held => rx.is_empty() && hold.is_held(),
        }
    }
}

/// Where the loop is in a TIME message: its bytes come one at a time, possibly across turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Time {
    /// Not in one.
    Out,
    /// TIME came; its Δ's low byte is next.
    Low,
    /// The low byte came; the high byte is next.
    High(u8),
}

/// No timers: the specs of a loop whose tables have none.
static NO_TIMERS: [TimerSpec; 0] = [];

/// The loop's state beyond the runtime's: whether SAFE was announced, a SYNC or STEP pending, the
/// digest of the tables it answers TABLES with, and the `N` timers of the tables (none by default).
#[derive(Debug)]
pub struct EventLoop<const N: usize = 0> {
    safe_announced: bool,
    /// A SYNC came in and waits for the runtime to be idle.
    sync_asked: bool,
    /// A STEP came in: the next decision is the last before the loop holds again.
    step: bool,
    /// The hex digits of the runtime's tables' digest, sent in answer to TABLES; `None`: TABLES is an
    /// unknown byte here.
    tables: Option<&'static [u8; TABLES_BYTES]>,
    /// The manifest's timers.
    timers: Timers<N>,
    /// Where the loop is in a TIME message.
    time: Time,
}

impl Default for EventLoop {
    fn default() -> Self {
        Self::new()
    }
}

impl EventLoop {
    /// A loop that has not announced anything yet (the caller sends READY at boot), does not report
    /// its tables — TABLES is an unknown byte, as in a firmware from before it (a board on its pins,
    /// which no host asks) — and has no timers (TIME and its Δ are taken and ignored).
    pub const fn new() -> Self {
        Self {
            safe_announced: false,
            sync_asked: false,
            step: false,
            tables: None,
            timers: Timers::new(&NO_TIMERS),
            time: Time::Out,
        }
    }

    /// [`EventLoop::new`], answering TABLES with `digest`: the `DIGEST` of the emitted tables the
    /// runtime runs (16 hex digits, `firmware::table::image::digest`), so that a host refuses to drive
    /// a firmware built from other tables. A `digest` of another length is reported as none.
    pub const fn with_tables(digest: &'static str) -> Self {
        let tables = if digest.len() == TABLES_BYTES { digest.as_bytes().first_chunk() } else { None };
        Self { tables, ..Self::new() }
    }

    /// This loop, running the timers `specs` (the emitted tables' `TIMERS`): every timer idle.
    pub const fn with_timers<const N: usize>(self, specs: &'static [TimerSpec; N]) -> EventLoop<N> {
        let Self { safe_announced, sync_asked, step, tables, timers: _, time } = self;
        EventLoop { safe_announced, sync_asked, step, tables, timers: Timers::new(specs), time }
    }
}

impl<const N: usize> EventLoop<N> {
    /// `ms` milliseconds passed (a board's hardware tick; a host's TIME goes through
    /// [`EventLoop::turn`]): advances the timers, and each timeout that falls due, earliest first, is
    /// taken by `rt` as an uncontrollable input and sent through `port`. A runtime in the safe state
    /// takes them as it takes any input (and decides nothing on them).
    pub fn elapse(&mut self, ms: u32, rt: &mut impl Decide, port: &mut impl Port) {
        if N == 0 || ms == 0 {
            return;
        }
        let mut raised = [0u8; N];
        let count = self.timers.advance(ms, &mut raised);
        for &timeout in raised.iter().take(count) {
            self.take(timeout, rt, port);
            port.send(timeout);
        }
    }

    /// The runtime takes uncontrollable `event` (the plant's, or a timeout); the timers observe it if
    /// it was taken.
    fn take(&mut self, event: u8, rt: &mut impl Decide, port: &mut impl Port) {
        match rt.apply(event) {
            Applied::Taken => self.timers.observe(event),
            Applied::Unexpected { automaton } => port.note(Note::Unexpected { event, automaton }),
            Applied::Unknown => port.note(Note::Unknown(event)),
        }
    }

    /// One byte of a TIME message, `time` where the loop was in it: the low byte is kept, the high
    /// byte completes Δ and time moves on. A Δ of 0 is malformed: counted as an unknown byte.
    fn time_byte(&mut self, time: Time, byte: u8, rt: &mut impl Decide, port: &mut impl Port) {
        self.time = match time {
            Time::Out | Time::Low => Time::High(byte),
            Time::High(low) => {
                match u16::from_le_bytes([low, byte]) {
                    0 => {
                        rt.note_unknown_byte();
                        port.note(Note::Unknown(TIME));
                    }
                    ms => self.elapse(u32::from(ms), rt, port),
                }
                Time::Out
            }
        };
    }

    /// One turn of the loop: drains the input buffer into the runtime, then takes at most one decision
    /// (unless held) and sends what it fired.
    pub fn turn(
        &mut self,
        rt: &mut impl Decide,
        rx: &mut InputConsumer<'_>,
        hold: &Hold,
        port: &mut impl Port,
    ) -> Poll {
        while let Some(byte) = rx.pop() {
            if self.time != Time::Out {
                self.time_byte(self.time, byte, rt, port);
                continue;
            }
            match byte {
                0..=MAX_EVENT => self.take(byte, rt, port),
                TIME => self.time = Time::Low,
                RESET => {
                    rt.reset();
                    self.timers.reset();
                    self.safe_announced = false;
                    port.send(READY);
                }
                STATUS => {
                    port.send(STATUS);
                    for word in rt.counters().to_array() {
                        for b in word.to_le_bytes() {
                            port.send(b);
                        }
                    }
                }
                // Without a digest, TABLES falls through to the unknown bytes.
                TABLES if self.tables.is_some() => {
                    port.send(TABLES);
                    self.tables.into_iter().flatten().for_each(|&b| port.send(b));
                }
                EXIT => return Poll::Exit(u8::from(rt.is_safe())),
                SYNC => self.sync_asked = true,
                STEP => {
                    hold.release();
                    self.step = true;
                }
                HOLD | GO => {
                    hold.filter(byte);
                }
                other => {
                    rt.note_unknown_byte();
                    port.note(Note::Unknown(other));
                }
            }
        }
        rt.note_overflows(rx.overflows());
        if rt.is_safe() && !self.safe_announced {
            self.safe_announced = true;
            port.send(SAFE);
            port.note(Note::Safe);
        }
        if hold.is_held() {
            return Poll::Held;
        }
        match rt.decide(|| !rx.is_empty()) {
            Decision::Fired(c) => {
                self.timers.observe(c);
                port.send(c);
                self.end_step(hold, port);
                Poll::Busy
            }
            Decision::Redecide => {
                port.note(Note::Redecided);
                Poll::Busy
            }
            Decision::Idle | Decision::Halted => {
                if core::mem::take(&mut self.sync_asked) && !self.step {
                    port.send(SYNC);
                }
                self.end_step(hold, port);
                Poll::Idle
            }
        }
    }

    /// After a decision (a command, or none to take): a STEP's one decision is taken, so the loop holds
    /// again and answers SYNC.
    fn end_step(&mut self, hold: &Hold, port: &mut impl Port) {
        if core::mem::take(&mut self.step) {
            hold.hold();
            self.sync_asked = false;
            port.send(SYNC);
        }
    }
}
