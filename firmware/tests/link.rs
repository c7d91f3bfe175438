//! The link protocol and every fault path, driven through `EventLoop::turn` as the QEMU application does.

mod common;

use common::{livelock, Wire, A, B, TO1, TO4};
use firmware::choice::LocalQueue;
use firmware::event_loop::{EventLoop, Note, Poll};
use firmware::fault::FaultPolicy;
use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
use firmware::link::{self, Hold};
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Runtime};
use firmware::table::{CheckedSet, SupervisorSet};

type Rt = Runtime<'static, LocalQueue<2>, SeedEntropy, 1, 1, false, 1, { firmware::table::layout::RANKED }>;

fn runtime(set: &'static SupervisorSet<'static, 1>, on_fault: FaultPolicy) -> Rt {
    let config = Config { guard: true, on_fault, reseed_every: 0 };
    Rt::new(CheckedSet::new(set).unwrap(), config, LocalQueue::default(), SeedEntropy::new(1))
}

/// One loop on the livelock example as the QEMU application wires it: the runtime (fault policy given),
/// an input queue of `Q` slots — leaked, so that its two ends live as long as the test — the hold gate
/// the receive interrupt sets, the loop, and the wire it sends on.
struct Bench {
    rt: Rt,
    tx: InputProducer<'static>,
    rx: InputConsumer<'static>,
    hold: Hold,
    event_loop: EventLoop,
    wire: Wire,
}

impl Bench {
    fn new<const Q: usize>(on_fault: FaultPolicy) -> Bench {
        let (set, _) = livelock();
        let (tx, rx) = Box::leak(Box::new(InputQueue::<Q>::new())).split();
        let (hold, event_loop, wire) = (Hold::new(), EventLoop::new(), Wire::default());
        Bench { rt: runtime(set, on_fault), tx, rx, hold, event_loop, wire }
    }

    /// One turn of the loop.
    fn turn(&mut self) -> Poll {
        self.event_loop.turn(&mut self.rt, &mut self.rx, &self.hold, &mut self.wire)
    }

    /// Turns until idle or exit; returns the last poll.
    fn settle(&mut self) -> Poll {
        for _ in 0..100 {
            match self.turn() {
                Poll::Busy => {}
                other => return other,
            }
        }
        panic!("link never settled");
    }

    /// `bytes` from the host, through the receive interrupt's filter (HOLD and GO act on the gate).
    fn send(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if let Some(b) = self.hold.filter(b) {
                self.tx.push(b).unwrap();
            }
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
    let mut b = Bench::new::<8>(FaultPolicy::Continue);
    assert_eq!(b.settle(), Poll::Idle);
    assert_eq!(b.wire.sent, [A, A], "1 -a-> 3 -a-> 4");
    b.send(&[TO1]);
    b.settle();
    assert_eq!(b.wire.sent[2..], [B], "local queue at 1 now takes b");
    b.wire.sent.clear();
    b.send(&[link::STATUS]);
    b.settle();
    assert_eq!(status(&b.wire.sent), [1, 3, 0, 0, 0, 0]);
    b.wire.sent.clear();
    b.send(&[link::RESET, link::STATUS]);
    b.settle();
    assert_eq!(b.wire.sent[0], link::READY);
    assert_eq!(status(&b.wire.sent[1..]), [0, 0, 0, 0, 0, 0]);
    assert_eq!(b.wire.sent[26..], [A, A], "back in state 1 with fresh cursors");
    b.send(&[link::EXIT]);
    assert_eq!(b.settle(), Poll::Exit(0));
}

#[test]
fn a_status_answer_reads_back_as_the_runtimes_counters() {
    let mut b = Bench::new::<8>(FaultPolicy::Continue);
    b.settle();
    // An unexpected event and a byte that means nothing, so that several counters differ.
    b.send(&[TO4, 0xFE, link::STATUS]);
    b.wire.sent.clear();
    b.settle();
    let at = b.wire.sent.iter().position(|&byte| byte == link::STATUS).unwrap();
    let answer: &[u8; link::STATUS_BYTES] =
        b.wire.sent[at + 1..at + 1 + link::STATUS_BYTES].try_into().unwrap();
    let counters = firmware::runtime::Counters::from_status(answer);
    assert_eq!(counters, *b.rt.counters());
    assert_eq!((counters.commands_out, counters.unexpected, counters.unknown_bytes), (2, 1, 1));
}

#[test]
fn tables_is_answered_with_the_digest_and_unknown_to_a_loop_without_one() {
    let digest = "0123456789abcdef";
    let mut b = Bench::new::<8>(FaultPolicy::Continue);
    b.event_loop = EventLoop::with_tables(digest);
    b.settle();
    b.wire.sent.clear();
    b.send(&[link::HOLD, link::TABLES, link::STATUS]);
    assert_eq!(b.settle(), Poll::Held);
    assert_eq!(b.wire.sent[0], link::TABLES);
    assert_eq!(&b.wire.sent[1..=link::TABLES_BYTES], digest.as_bytes());
    assert_eq!(status(&b.wire.sent[1 + link::TABLES_BYTES..]), [0, 2, 0, 0, 0, 0]);
    // No digest, or one that is not 16 digits: TABLES is an unknown byte, as in a firmware from before
    // it, and the STATUS after it is answered alone (what a host tells such a firmware by).
    for event_loop in [EventLoop::new(), EventLoop::with_tables("0123")] {
        let mut b = Bench::new::<8>(FaultPolicy::Continue);
        b.event_loop = event_loop;
        b.settle();
        b.wire.sent.clear();
        b.send(&[link::HOLD, link::TABLES, link::STATUS]);
        b.settle();
        assert_eq!(status(&b.wire.sent), [0, 2, 0, 0, 0, 1]);
        assert_eq!(b.wire.notes, [Note::Unknown(link::TABLES)]);
    }
}

#[test]
fn hold_queues_a_burst_and_go_releases_it() {
    let mut b = Bench::new::<8>(FaultPolicy::Continue);
    b.send(&[link::HOLD]);
    assert_eq!(b.settle(), Poll::Held);
    assert!(b.wire.sent.is_empty(), "held: no decision");
    b.send(&[link::GO]);
    b.settle();
    assert_eq!(b.wire.sent, [A, A]);
    // Held again, a burst of two inputs is applied in order before the next decision.
    b.send(&[link::HOLD, TO1]);
    b.settle();
    b.send(&[link::GO]);
    b.settle();
    assert_eq!(b.wire.sent[2..], [B]);
}

#[test]
fn a_go_after_a_held_turn_keeps_the_loop_awake() {
    let mut b = Bench::new::<8>(FaultPolicy::Continue);
    assert_eq!(b.settle(), Poll::Idle);
    assert_eq!(b.wire.sent, [A, A], "in the marked state, nothing enabled");
    // A burst between HOLD and GO whose GO reaches the receive interrupt only after the turn that took
    // the burst saw the hold: nothing is in the buffer, yet the loop must not sleep.
    b.send(&[link::HOLD, TO1]);
    let poll = b.settle();
    assert_eq!(poll, Poll::Held);
    assert!(poll.may_sleep(&b.rx, &b.hold), "held, nothing waiting: sleep until GO");
    b.send(&[link::GO]);
    assert!(b.rx.is_empty(), "GO is taken by the receive interrupt, not buffered");
    assert!(!poll.may_sleep(&b.rx, &b.hold), "released since the turn: decide, do not sleep");
    assert_eq!(b.turn(), Poll::Busy);
    assert_eq!(b.wire.sent, [A, A, B]);
    // Idle with nothing waiting sleeps; an input that landed since wakes it.
    let idle = Poll::Idle;
    assert!(idle.may_sleep(&b.rx, &b.hold));
    b.send(&[TO1]);
    assert!(!idle.may_sleep(&b.rx, &b.hold));
    assert!(!Poll::Busy.may_sleep(&b.rx, &b.hold));
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
    let mut b = Bench::new::<4>(FaultPolicy::Continue);
    b.settle();
    // In state 4: to4 is unexpected; 0xFE and event 200 are unknown; a (controllable) from the host too.
    b.send(&[TO4, 0xFE, 200]);
    b.settle();
    b.send(&[A]);
    for event in [TO1, TO1] {
        if b.tx.push(event).is_err() {
            b.tx.count_overflow();
        }
    }
    b.tx.count_overflow();
    b.settle();
    assert_eq!(
        b.wire.notes.iter().filter(|n| matches!(n, Note::Unexpected { event: TO4, automaton: 0 })).count(),
        1
    );
    assert_eq!(b.wire.notes.iter().filter(|n| matches!(n, Note::Unknown(_))).count(), 3);
    let c = b.rt.counters();
    // The second to1 finds the plant back in 1, where it is unexpected too.
    assert_eq!((c.unexpected, c.unknown_bytes, c.overflows, c.events_in), (2, 3, 1, 3));
    assert!(!b.rt.is_safe());
    assert!(!b.wire.sent.contains(&link::SAFE));
    assert_eq!(b.wire.sent.last(), Some(&B), "still deciding after the faults");
}

#[test]
fn each_fault_enters_the_safe_state_which_reset_leaves() {
    type Inject = fn(&mut InputProducer<'_>);
    let faults: [(&str, Inject); 4] = [
        ("unexpected", |tx| tx.push(TO4).unwrap()),
        ("unknown control byte", |tx| tx.push(0xFE).unwrap()),
        ("event beyond the set", |tx| tx.push(77).unwrap()),
        ("overflow", |tx| tx.count_overflow()),
    ];
    for (what, inject) in faults {
        let mut b = Bench::new::<4>(FaultPolicy::SafeState);
        b.settle();
        assert_eq!(b.wire.sent, [A, A], "{what}");
        inject(&mut b.tx);
        b.tx.push(TO1).unwrap();
        b.settle();
        assert_eq!(b.wire.sent[2..], [link::SAFE], "{what}: SAFE once, no decision after");
        b.tx.push(link::STATUS).unwrap();
        b.settle();
        assert_eq!(b.wire.sent[3], link::STATUS, "{what}: no second SAFE");
        b.tx.push(link::EXIT).unwrap();
        assert_eq!(b.settle(), Poll::Exit(1), "{what}");
        b.wire.sent.clear();
        b.tx.push(link::RESET).unwrap();
        b.settle();
        assert_eq!(b.wire.sent, [link::READY, A, A], "{what}: reset leaves the safe state");
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
            link::SYNC => i += 1,
            other => panic!("the firmware sent {other:#04x}"),
        }
    }
    (commands, answers)
}

/// SYNC is answered once the loop is idle and not held, after every command the bytes before it
/// allowed, and once per request: what lets a host run the loop in lock-step.
#[test]
fn sync_is_answered_once_idle_and_not_held() {
    let mut b = Bench::new::<8>(FaultPolicy::Continue);
    b.send(&[link::HOLD, link::SYNC]);
    assert_eq!(b.settle(), Poll::Held);
    assert!(b.wire.sent.is_empty(), "answered while held: {:?}", b.wire.sent);
    b.send(&[link::GO]);
    assert_eq!(b.settle(), Poll::Idle);
    let sent = std::mem::take(&mut b.wire.sent);
    // The livelock plant from its initial state: controllable moves until only an uncontrollable one is
    // left, then the answer, once.
    assert!(sent.len() >= 2, "{sent:?}");
    assert_eq!(sent.iter().filter(|&&x| x == link::SYNC).count(), 1, "{sent:?}");
    assert_eq!(sent.last(), Some(&link::SYNC), "{sent:?}");
    assert!(sent[..sent.len() - 1].iter().all(|&x| x == A || x == B), "{sent:?}");
    // Idle already: the next request is answered at once; none unasked.
    b.send(&[link::SYNC]);
    b.settle();
    b.settle();
    assert_eq!(b.wire.sent, [link::SYNC]);
}

/// STEP: one decision on every byte before it, then held again, answered by SYNC — a command and SYNC
/// while the controller has one, SYNC alone once it has none; GO lets it go on freely.
#[test]
fn step_decides_once_then_holds() {
    let mut b = Bench::new::<8>(FaultPolicy::Continue);
    b.send(&[link::HOLD, link::STEP]);
    assert_eq!(b.settle(), Poll::Held);
    let first = std::mem::take(&mut b.wire.sent);
    assert!(matches!(first[..], [A | B, link::SYNC]), "{first:?}");
    assert!(b.hold.is_held());
    // Step on until the livelock plant has only its uncontrollable move left: one command per STEP.
    let mut steps = 1;
    loop {
        b.send(&[link::STEP]);
        b.settle();
        let sent = std::mem::take(&mut b.wire.sent);
        assert!(b.hold.is_held(), "{sent:?}");
        match sent[..] {
            [A | B, link::SYNC] => steps += 1,
            [link::SYNC] => break,
            _ => panic!("{sent:?}"),
        }
        assert!(steps < 50, "never idle");
    }
    assert_eq!(b.rt.counters().commands_out, steps);
    // A SYNC request under a STEP is answered once, by the step's answer.
    b.send(&[link::SYNC, link::STEP]);
    b.settle();
    assert_eq!(b.wire.sent, [link::SYNC]);
    // GO releases the hold; the loop reads and decides freely again.
    b.wire.sent.clear();
    b.send(&[TO1, link::GO]);
    assert_eq!(b.settle(), Poll::Idle);
    assert!(!b.hold.is_held());
    assert_eq!(b.rt.counters().events_in, 1);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(common::cases(256)))]

    /// Any bytes from the host, in any chunks: no panic, and every byte accounted for — an uncontrollable
    /// event of the set is taken (`events_in`), a TIME takes its two bytes of data whatever they are,
    /// anything else that is not a control byte is an unknown byte; the commands on the wire are the commands counted; STATUS answers never go backwards.
    /// (RESET, which zeroes the counters, and EXIT are left out here; `commands_status_reset_and_exit`
    /// covers them.)
    #[test]
    fn any_host_bytes_are_accounted_for(
        chunks in proptest::collection::vec(proptest::collection::vec(proptest::prelude::any::<u8>(), 0..8), 0..40),
    ) {
        let mut b = Bench::new::<16>(FaultPolicy::Continue);
        let (mut events, mut unknown) = (0u32, 0u32);
        // The bytes of a TIME still to come, and its Δ's low byte: data, whatever their value; a Δ of 0
        // is an unknown byte (the loop has no timers, so any other Δ does nothing).
        let (mut payload, mut low) = (0, 0u8);
        for chunk in &chunks {
            let mut chunk: Vec<u8> = chunk.iter().copied().filter(|&b| b != link::RESET && b != link::EXIT).collect();
            // Released at the end of each chunk, so the loop always gets to decide (unless the GO is
            // a TIME's data).
            chunk.push(link::GO);
            for &b in &chunk {
                if payload > 0 {
                    payload -= 1;
                    if payload == 0 && u16::from_le_bytes([low, b]) == 0 {
                        unknown += 1;
                    }
                    low = b;
                    continue;
                }
                match b {
                    TO4 | TO1 => events += 1,
                    link::TIME => payload = link::TIME_BYTES,
                    link::STATUS | link::HOLD | link::GO | link::SYNC | link::STEP => {}
                    _ => unknown += 1,
                }
            }
            b.send(&chunk);
            b.settle();
        }
        let c = *b.rt.counters();
        proptest::prop_assert_eq!((c.events_in, c.unknown_bytes, c.overflows), (events, unknown, 0));
        proptest::prop_assert!(c.unexpected <= c.events_in);
        let (commands, answers) = read_wire(&b.wire.sent);
        proptest::prop_assert_eq!(commands, c.commands_out);
        for pair in answers.windows(2) {
            proptest::prop_assert!(pair[0].iter().zip(&pair[1]).all(|(a, b)| a <= b), "{:?}", answers);
        }
    }

    /// Any bytes at all, RESET and EXIT included, under the safe-state policy: no panic, and after EXIT
    /// the loop reports the exit status the runtime's state gives.
    #[test]
    fn any_host_bytes_never_panic_the_loop(bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..200)) {
        let mut b = Bench::new::<8>(FaultPolicy::SafeState);
        for chunk in bytes.chunks(7) {
            b.send(chunk);
            if let Poll::Exit(status) = b.settle() {
                proptest::prop_assert_eq!(status, u8::from(b.rt.is_safe()));
                break;
            }
        }
    }
}
