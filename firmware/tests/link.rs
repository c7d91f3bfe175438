//! The link protocol and every fault path, driven through `EventLoop::turn` as the QEMU application does.

mod common;

use common::{livelock, A, B, TO1, TO4};
use firmware::choice::LocalQueue;
use firmware::event_loop::{EventLoop, Note, Poll, Port};
use firmware::fault::FaultPolicy;
use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
use firmware::link::{self, Hold};
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Runtime};
use firmware::table::{CheckedSet, SupervisorSet};

/// Records what the link sends and notes.
#[derive(Default)]
struct Wire {
    sent: Vec<u8>,
    notes: Vec<Note>,
}

impl Port for Wire {
    fn send(&mut self, byte: u8) {
        self.sent.push(byte);
    }

    fn note(&mut self, note: Note) {
        self.notes.push(note);
    }
}

type Rt = Runtime<'static, LocalQueue<2>, SeedEntropy, 1, 1, false, 1>;

fn runtime(set: &'static SupervisorSet<'static, 1>, on_fault: FaultPolicy) -> Rt {
    let config = Config { guard: true, on_fault, reseed_every: 0 };
    Rt::new(CheckedSet::new(set).unwrap(), config, LocalQueue::default(), SeedEntropy::new(1))
}

/// Services until idle or exit; returns the last poll.
fn settle(
    event_loop: &mut EventLoop,
    rt: &mut Rt,
    rx: &mut InputConsumer<'_>,
    hold: &Hold,
    wire: &mut Wire,
) -> Poll {
    for _ in 0..100 {
        match event_loop.turn(rt, rx, hold, wire) {
            Poll::Busy => {}
            other => return other,
        }
    }
    panic!("link never settled");
}

fn send(tx: &mut InputProducer<'_>, hold: &Hold, bytes: &[u8]) {
    for &b in bytes {
        if let Some(b) = hold.filter(b) {
            tx.push(b).unwrap();
        }
    }
}

fn status(sent: &[u8]) -> [u32; 6] {
    assert_eq!(sent[0], link::STATUS, "{sent:?}");
    let mut out = [0; 6];
    for (i, w) in out.iter_mut().enumerate() {
        *w = u32::from_le_bytes(sent[1 + 4 * i..5 + 4 * i].try_into().unwrap());
    }
    out
}

#[test]
fn commands_status_reset_and_exit() {
    let (set, _) = livelock();
    let mut rt = runtime(set, FaultPolicy::Continue);
    let mut q = InputQueue::<8>::new();
    let (mut tx, mut rx) = q.split();
    let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
    assert_eq!(settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire), Poll::Idle);
    assert_eq!(wire.sent, [A, A], "1 -a-> 3 -a-> 4");
    send(&mut tx, &hold, &[TO1]);
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    assert_eq!(wire.sent[2..], [B], "local queue at 1 now takes b");
    wire.sent.clear();
    send(&mut tx, &hold, &[link::STATUS]);
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    assert_eq!(status(&wire.sent), [1, 3, 0, 0, 0, 0]);
    wire.sent.clear();
    send(&mut tx, &hold, &[link::RESET, link::STATUS]);
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    assert_eq!(wire.sent[0], link::READY);
    assert_eq!(status(&wire.sent[1..]), [0, 0, 0, 0, 0, 0]);
    assert_eq!(wire.sent[26..], [A, A], "back in state 1 with fresh cursors");
    send(&mut tx, &hold, &[link::EXIT]);
    assert_eq!(settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire), Poll::Exit(0));
}

#[test]
fn a_status_answer_reads_back_as_the_runtimes_counters() {
    let (set, _) = livelock();
    let mut rt = runtime(set, FaultPolicy::Continue);
    let mut q = InputQueue::<8>::new();
    let (mut tx, mut rx) = q.split();
    let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    // An unexpected event and a byte that means nothing, so that several counters differ.
    send(&mut tx, &hold, &[TO4, 0xFE, link::STATUS]);
    wire.sent.clear();
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    let at = wire.sent.iter().position(|&b| b == link::STATUS).unwrap();
    let answer: &[u8; link::STATUS_BYTES] =
        wire.sent[at + 1..at + 1 + link::STATUS_BYTES].try_into().unwrap();
    let counters = firmware::runtime::Counters::from_status(answer);
    assert_eq!(counters, *rt.counters());
    assert_eq!((counters.commands_out, counters.unexpected, counters.unknown_bytes), (2, 1, 1));
}

#[test]
fn hold_queues_a_burst_and_go_releases_it() {
    let (set, _) = livelock();
    let mut rt = runtime(set, FaultPolicy::Continue);
    let mut q = InputQueue::<8>::new();
    let (mut tx, mut rx) = q.split();
    let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
    send(&mut tx, &hold, &[link::HOLD]);
    assert_eq!(settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire), Poll::Held);
    assert!(wire.sent.is_empty(), "held: no decision");
    send(&mut tx, &hold, &[link::GO]);
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    assert_eq!(wire.sent, [A, A]);
    // Held again, a burst of two inputs is applied in order before the next decision.
    send(&mut tx, &hold, &[link::HOLD, TO1]);
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    send(&mut tx, &hold, &[link::GO]);
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    assert_eq!(wire.sent[2..], [B]);
}

#[test]
fn a_go_after_a_held_turn_keeps_the_loop_awake() {
    let (set, _) = livelock();
    let mut rt = runtime(set, FaultPolicy::Continue);
    let mut q = InputQueue::<8>::new();
    let (mut tx, mut rx) = q.split();
    let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
    assert_eq!(settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire), Poll::Idle);
    assert_eq!(wire.sent, [A, A], "in the marked state, nothing enabled");
    // A burst between HOLD and GO whose GO reaches the receive interrupt only after the turn that took
    // the burst saw the hold: nothing is in the buffer, yet the loop must not sleep.
    send(&mut tx, &hold, &[link::HOLD, TO1]);
    let poll = settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    assert_eq!(poll, Poll::Held);
    assert!(poll.may_sleep(&rx, &hold), "held, nothing waiting: sleep until GO");
    send(&mut tx, &hold, &[link::GO]);
    assert!(rx.is_empty(), "GO is taken by the receive interrupt, not buffered");
    assert!(!poll.may_sleep(&rx, &hold), "released since the turn: decide, do not sleep");
    assert_eq!(event_loop.turn(&mut rt, &mut rx, &hold, &mut wire), Poll::Busy);
    assert_eq!(wire.sent, [A, A, B]);
    // Idle with nothing waiting sleeps; an input that landed since wakes it.
    let idle = Poll::Idle;
    assert!(idle.may_sleep(&rx, &hold));
    send(&mut tx, &hold, &[TO1]);
    assert!(!idle.may_sleep(&rx, &hold));
    assert!(!Poll::Busy.may_sleep(&rx, &hold));
}

#[test]
fn guard_drops_a_choice_when_an_input_arrived() {
    let (set, _) = livelock();
    let mut rt = runtime(set, FaultPolicy::Continue);
    assert_eq!(rt.decide(|| true), firmware::runtime::Decision::Redecide);
    assert_eq!(rt.counters().guard_redecisions, 1);
    assert_eq!(rt.counters().commands_out, 0);
    let config = Config { guard: false, on_fault: FaultPolicy::Continue, reseed_every: 0 };
    let mut unguarded =
        Rt::new(CheckedSet::new(set).unwrap(), config, LocalQueue::default(), SeedEntropy::new(1));
    assert_eq!(unguarded.decide(|| true), firmware::runtime::Decision::Fired(A));
}

#[test]
fn faults_are_counted_and_continue_keeps_deciding() {
    let (set, _) = livelock();
    let mut rt = runtime(set, FaultPolicy::Continue);
    let mut q = InputQueue::<4>::new();
    let (mut tx, mut rx) = q.split();
    let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    // In state 4: to4 is unexpected; 0xF9 and event 200 are unknown; a (controllable) from the host too.
    send(&mut tx, &hold, &[TO4, 0xF9, 200]);
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    send(&mut tx, &hold, &[A]);
    for b in [TO1, TO1] {
        if tx.push(b).is_err() {
            tx.count_overflow();
        }
    }
    tx.count_overflow();
    settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
    assert_eq!(
        wire.notes.iter().filter(|n| matches!(n, Note::Unexpected { event: TO4, automaton: 0 })).count(),
        1
    );
    assert_eq!(wire.notes.iter().filter(|n| matches!(n, Note::Unknown(_))).count(), 3);
    let c = rt.counters();
    // The second to1 finds the plant back in 1, where it is unexpected too.
    assert_eq!((c.unexpected, c.unknown_bytes, c.overflows, c.events_in), (2, 3, 1, 3));
    assert!(!rt.is_safe());
    assert!(!wire.sent.contains(&link::SAFE));
    assert_eq!(wire.sent.last(), Some(&B), "still deciding after the faults");
}

#[test]
fn each_fault_enters_the_safe_state_which_reset_leaves() {
    let (set, _) = livelock();
    type Inject = fn(&mut InputProducer<'_>);
    let faults: [(&str, Inject); 4] = [
        ("unexpected", |tx| tx.push(TO4).unwrap()),
        ("unknown control byte", |tx| tx.push(0xF7).unwrap()),
        ("event beyond the set", |tx| tx.push(77).unwrap()),
        ("overflow", |tx| tx.count_overflow()),
    ];
    for (what, inject) in faults {
        let mut rt = runtime(set, FaultPolicy::SafeState);
        let mut q = InputQueue::<4>::new();
        let (mut tx, mut rx) = q.split();
        let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
        settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
        assert_eq!(wire.sent, [A, A], "{what}");
        inject(&mut tx);
        tx.push(TO1).unwrap();
        settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
        assert_eq!(wire.sent[2..], [link::SAFE], "{what}: SAFE once, no decision after");
        tx.push(link::STATUS).unwrap();
        settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
        assert_eq!(wire.sent[3], link::STATUS, "{what}: no second SAFE");
        tx.push(link::EXIT).unwrap();
        assert_eq!(settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire), Poll::Exit(1), "{what}");
        wire.sent.clear();
        tx.push(link::RESET).unwrap();
        settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
        assert_eq!(wire.sent, [link::READY, A, A], "{what}: reset leaves the safe state");
    }
}

/// What the wire carried: the commands fired and the counters of every STATUS answer, in order.
fn read_wire(sent: &[u8]) -> (u32, Vec<[u32; 6]>) {
    let (mut commands, mut answers, mut i) = (0, Vec::new(), 0);
    while i < sent.len() {
        match sent[i] {
            link::STATUS => {
                answers.push(status(&sent[i..]));
                i += 1 + link::STATUS_BYTES;
            }
            A | B => {
                commands += 1;
                i += 1;
            }
            other => panic!("the firmware sent {other:#04x}"),
        }
    }
    (commands, answers)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]

    /// Any bytes from the host, in any chunks: no panic, and every byte accounted for — an uncontrollable
    /// event of the set is taken (`events_in`), anything else that is not a control byte is an unknown
    /// byte; the commands on the wire are the commands counted; STATUS answers never go backwards.
    /// (RESET, which zeroes the counters, and EXIT are left out here; `commands_status_reset_and_exit`
    /// covers them.)
    #[test]
    fn any_host_bytes_are_accounted_for(
        chunks in proptest::collection::vec(proptest::collection::vec(proptest::prelude::any::<u8>(), 0..8), 0..40),
    ) {
        let (set, _) = livelock();
        let mut rt = runtime(set, FaultPolicy::Continue);
        let mut q = InputQueue::<8>::new();
        let (mut tx, mut rx) = q.split();
        let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
        let (mut events, mut unknown) = (0u32, 0u32);
        for chunk in &chunks {
            let chunk: Vec<u8> = chunk.iter().copied().filter(|&b| b != link::RESET && b != link::EXIT).collect();
            for &b in &chunk {
                match b {
                    TO4 | TO1 => events += 1,
                    link::STATUS | link::HOLD | link::GO => {}
                    _ => unknown += 1,
                }
            }
            send(&mut tx, &hold, &chunk);
            // Released at the end of each chunk, so the loop always gets to decide.
            send(&mut tx, &hold, &[link::GO]);
            settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire);
        }
        let c = *rt.counters();
        proptest::prop_assert_eq!((c.events_in, c.unknown_bytes, c.overflows), (events, unknown, 0));
        proptest::prop_assert!(c.unexpected <= c.events_in);
        let (commands, answers) = read_wire(&wire.sent);
        proptest::prop_assert_eq!(commands, c.commands_out);
        for pair in answers.windows(2) {
            proptest::prop_assert!(pair[0].iter().zip(&pair[1]).all(|(a, b)| a <= b), "{:?}", answers);
        }
    }

    /// Any bytes at all, RESET and EXIT included, under the safe-state policy: no panic, and after EXIT
    /// the loop reports the exit status the runtime's state gives.
    #[test]
    fn any_host_bytes_never_panic_the_loop(bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..200)) {
        let (set, _) = livelock();
        let mut rt = runtime(set, FaultPolicy::SafeState);
        let mut q = InputQueue::<8>::new();
        let (mut tx, mut rx) = q.split();
        let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
        for chunk in bytes.chunks(7) {
            send(&mut tx, &hold, chunk);
            if let Poll::Exit(status) = settle(&mut event_loop, &mut rt, &mut rx, &hold, &mut wire) {
                proptest::prop_assert_eq!(status, u8::from(rt.is_safe()));
                break;
            }
        }
    }
}
