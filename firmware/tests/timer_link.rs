//! Timers in the event loop: the link's TIME message (its bytes one at a time, across reads), timeouts
//! taken by the runtime and sent to the host, stops and restarts, RESET, a board's millisecond tick, and
//! a loop without timers ignoring TIME — on a small cylinder whose end switch must come within 100 ms.

mod common;

use common::{encode, Role, Spec, Wire};
use firmware::choice::LocalQueue;
use firmware::event_loop::{EventLoop, Note, Poll};
use firmware::fault::FaultPolicy;
use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
use firmware::link::{self, Hold};
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Runtime};
use firmware::table::CheckedSet;
use firmware::timer::TimerSpec;

type Rt = Runtime<'static, LocalQueue<2>, SeedEntropy, 1, 1, false, 1, { firmware::table::layout::RANKED }>;

/// Event ids: `extend` and `ack` are commands; `at_end`, `timeout` and `kick` come from the plant (the
/// timeout from the timer).
const EXTEND: u8 = 0;
const AT_END: u8 = 1;
const TIMEOUT: u8 = 2;
const ACK: u8 = 3;
const KICK: u8 = 4;

/// The timer: `extend` or `kick` (re)starts it, `at_end` stops it, `timeout` after 100 ms.
static TIMERS: [TimerSpec; 1] =
    [TimerSpec { start: &[EXTEND, KICK], stop: &[AT_END], timeout: TIMEOUT, ms: 100 }];

/// The cylinder: home (0) –extend→ moving (1) –at_end→ home, moving –kick→ moving, moving –timeout→
/// fault (2) –ack→ home. One plant, no supervisor: the runtime extends whenever it is home.
fn runtime() -> Rt {
    let spec = Spec {
        role: Role::Plant,
        states: 3,
        initial: 0,
        transitions: vec![(0, EXTEND, 1), (1, AT_END, 0), (1, KICK, 1), (1, TIMEOUT, 2), (2, ACK, 0)],
        alphabet: vec![EXTEND, AT_END, TIMEOUT, ACK, KICK],
    };
    let set =
        encode(&["extend", "at_end", "timeout", "ack", "kick"], &[true, false, false, true, false], &[spec]);
    let config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 0 };
    Rt::new(CheckedSet::new(set).unwrap(), config, LocalQueue::default(), SeedEntropy::new(1))
}

/// The loop on the cylinder as a host drives it (on hold from boot), with `N` timers.
struct Bench<const N: usize> {
    rt: Rt,
    tx: InputProducer<'static>,
    rx: InputConsumer<'static>,
    hold: Hold,
    event_loop: EventLoop<N>,
    wire: Wire,
}

impl<const N: usize> Bench<N> {
    fn new(event_loop: EventLoop<N>) -> Self {
        let (tx, rx) = Box::leak(Box::new(InputQueue::<16>::new())).split();
        Bench { rt: runtime(), tx, rx, hold: Hold::on_hold(), event_loop, wire: Wire::default() }
    }

    /// `bytes` from the host through the receive interrupt's filter, then turns until the loop waits;
    /// returns what it sent meanwhile.
    fn send(&mut self, bytes: &[u8]) -> Vec<u8> {
        for &b in bytes {
            if let Some(b) = self.hold.filter(b) {
                self.tx.push(b).unwrap();
            }
        }
        for _ in 0..100 {
            let poll = self.event_loop.turn(&mut self.rt, &mut self.rx, &self.hold, &mut self.wire);
            if poll != Poll::Busy {
                return std::mem::take(&mut self.wire.sent);
            }
        }
        panic!("the loop never settled");
    }
}

/// TIME with Δ `ms`, as the host sends it.
fn time(ms: u16) -> [u8; 3] {
    let [low, high] = ms.to_le_bytes();
    [link::TIME, low, high]
}

fn timed() -> Bench<1> {
    Bench::new(EventLoop::with_tables("0123456789abcdef").with_timers(&TIMERS))
}

#[test]
fn a_time_split_across_reads_raises_the_timeout_which_the_runtime_takes_and_the_host_receives() {
    let mut b = timed();
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC], "extend starts the timer");
    // 99 ms in three reads: nothing due.
    let [t, low, high] = time(99);
    assert!(b.send(&[t]).is_empty());
    assert!(b.send(&[low]).is_empty());
    assert!(b.send(&[high]).is_empty());
    // The 100th millisecond: the timeout, taken by the runtime (now in fault) and sent.
    assert_eq!(b.send(&time(1)), [TIMEOUT]);
    assert_eq!(b.rt.counters().events_in, 1);
    assert_eq!(b.rt.counters().unexpected, 0);
    // Deciding on it: ack (the fault path), then extend again, which restarts the timer.
    assert_eq!(b.send(&[link::STEP]), [ACK, link::SYNC]);
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert!(b.send(&time(99)).is_empty(), "100 ms from the new extend");
    assert_eq!(b.send(&time(5000)), [TIMEOUT], "once, however long the step");
    assert!(b.send(&time(5000)).is_empty());
    assert_eq!(b.rt.counters().unknown_bytes, 0);
}

#[test]
fn a_stop_before_the_deadline_disarms_and_a_start_while_running_restarts() {
    let mut b = timed();
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert!(b.send(&time(60)).is_empty());
    assert!(b.send(&[KICK]).is_empty(), "a restart, 100 ms from here");
    assert!(b.send(&time(60)).is_empty(), "120 ms after the extend, 60 after the kick");
    assert_eq!(b.send(&time(40)), [TIMEOUT]);
    assert_eq!(b.send(&[link::STEP]), [ACK, link::SYNC]);
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert!(b.send(&time(99)).is_empty());
    assert!(b.send(&[AT_END]).is_empty(), "the end switch in time stops the timer");
    assert!(b.send(&time(60_000)).is_empty());
    assert_eq!(b.rt.counters().unexpected, 0);
}

#[test]
fn reset_idles_the_timers() {
    let mut b = timed();
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert_eq!(b.send(&[link::RESET]), [link::READY], "held: no decision after the reset");
    assert!(b.send(&time(1000)).is_empty(), "the timer started before the reset is idle");
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert_eq!(b.send(&time(100)), [TIMEOUT], "and runs again from the next start");
}

#[test]
fn time_bytes_are_data_whatever_they_read_as_and_a_zero_step_is_a_fault() {
    // Δ = 246 ms, GO's byte low: not a release, and past the deadline.
    let mut b = timed();
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert_eq!(b.send(&time(link::GO.into())), [TIMEOUT]);
    assert!(b.hold.is_held(), "the GO byte was Δ's, not a release");
    // A Δ of 0: counted as an unknown byte, the timer untouched.
    let mut b = timed();
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert!(b.send(&time(0)).is_empty());
    assert_eq!(b.rt.counters().unknown_bytes, 1);
    assert_eq!(b.wire.notes, [Note::Unknown(link::TIME)]);
    assert!(b.send(&time(99)).is_empty());
    assert_eq!(b.send(&time(1)), [TIMEOUT]);
    // A TIME cut short by EXIT: EXIT's bytes are its data, and the loop goes on.
    assert!(b.send(&[link::TIME, link::EXIT]).is_empty());
    assert_eq!(b.send(&[link::EXIT, link::STATUS])[0], link::STATUS, "Δ = 0xF2F2 ms passed");
}

#[test]
fn a_board_tick_advances_the_same_timers() {
    let mut b = timed();
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    let Bench { rt, event_loop, wire, .. } = &mut b;
    for _ in 0..99 {
        event_loop.elapse(1, rt, wire);
    }
    assert!(wire.sent.is_empty());
    event_loop.elapse(1, rt, wire);
    assert_eq!(wire.sent, [TIMEOUT]);
    assert_eq!(rt.counters().events_in, 1);
}

#[test]
fn a_loop_without_timers_takes_time_and_ignores_it() {
    let mut b = Bench::new(EventLoop::new());
    assert_eq!(b.send(&[link::STEP]), [EXTEND, link::SYNC]);
    assert!(b.send(&time(60_000)).is_empty());
    let [t, low, high] = time(link::STATUS.into());
    assert!(b.send(&[t, low]).is_empty(), "STATUS's byte as Δ's low byte is data");
    assert!(b.send(&[high]).is_empty());
    b.event_loop.elapse(60_000, &mut b.rt, &mut b.wire);
    assert!(b.wire.sent.is_empty());
    let c = b.rt.counters();
    assert_eq!((c.events_in, c.unknown_bytes, c.unexpected), (0, 0, 0));
}
