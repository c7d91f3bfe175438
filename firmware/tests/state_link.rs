//! The state-based runtime behind the same event loop and link protocol as the supervisor runtime
//! (`firmware::runtime::Decide`): commands out, STATUS, RESET back to the initial word, STEP's one decision,
//! an unexpected sensor event noted and counted, SAFE under the safe-state policy.

mod common;

use common::Wire;
use firmware::choice::First;
use firmware::event_loop::{EventLoop, Note, Poll};
use firmware::fault::FaultPolicy;
use firmware::input_queue::InputQueue;
use firmware::link::{self, Hold};
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Counters};
use firmware::state::{Cube, Reading, Rule, StateRuntime, StateTables};

// A valve, input X (bit 0), output Y (bit 1): closed (!Y !X) –open(0)→ opening (Y !X) –opened(1)→ open
// (Y X) –close(2)→ closing (!Y X) –closed(3)→ closed.
static RULES: [Rule; 2] = [Rule { event: 0, end: 1 }, Rule { event: 2, end: 2 }];
static CUBES: [Cube; 2] = [Cube { mask: 0b11, value: 0b00 }, Cube { mask: 0b11, value: 0b11 }];
static WRITES: [Cube; 4] = [
    Cube { mask: 0b10, value: 0b10 },
    Cube { mask: 0b01, value: 0b01 },
    Cube { mask: 0b10, value: 0b00 },
    Cube { mask: 0b01, value: 0b00 },
];
static READINGS: [Reading<1>; 4] = [
    Reading { cube: Cube { mask: 0b11, value: 0b00 }, leaving: [0b0001], code: 0 },
    Reading { cube: Cube { mask: 0b11, value: 0b10 }, leaving: [0b0010], code: 1 },
    Reading { cube: Cube { mask: 0b11, value: 0b11 }, leaving: [0b0100], code: 2 },
    Reading { cube: Cube { mask: 0b11, value: 0b01 }, leaving: [0b1000], code: 3 },
];
static TABLES: StateTables<'static, 1> = StateTables {
    initial: 0,
    rules: &RULES,
    cubes: &CUBES,
    writes: &WRITES,
    holders: &[1, 1, 1, 1],
    components: &[4],
    readings: &READINGS,
    controllable: [0b0101],
    plant_events: &[[0b0101]],
    sites: &[],
};
const OPEN: u8 = 0;
const OPENED: u8 = 1;
const CLOSE: u8 = 2;
const CLOSED: u8 = 3;

/// Runs the loop on `bytes` from the host until it settles; what it sent and noted.
fn session(on_fault: FaultPolicy, bytes: &[&[u8]]) -> (Wire, Counters, u32) {
    let config = Config { guard: true, on_fault, reseed_every: 0 };
    let mut rt =
        StateRuntime::<'_, First, SeedEntropy, 1, 1>::new(&TABLES, config, First, SeedEntropy::new(1));
    let (mut tx, mut rx) = Box::leak(Box::new(InputQueue::<16>::new())).split();
    let (hold, mut event_loop, mut wire) = (Hold::new(), EventLoop::new(), Wire::default());
    for burst in bytes {
        for &b in *burst {
            if let Some(b) = hold.filter(b) {
                tx.push(b).unwrap();
            }
        }
        for _ in 0..100 {
            if event_loop.turn(&mut rt, &mut rx, &hold, &mut wire) != Poll::Busy {
                break;
            }
        }
    }
    (wire, *rt.counters(), rt.word())
}

fn status(sent: &[u8]) -> Counters {
    let at = sent.iter().position(|&b| b == link::STATUS).unwrap();
    Counters::from_status(sent[at + 1..at + 1 + link::STATUS_BYTES].try_into().unwrap())
}

#[test]
fn a_cycle_of_commands_and_sensor_events_then_status_and_reset() {
    let (wire, counters, word) =
        session(FaultPolicy::Continue, &[&[], &[OPENED], &[CLOSED, link::STATUS], &[link::RESET]]);
    // The loop drains its input (closed, STATUS) before it decides again.
    assert_eq!(wire.sent[..3], [OPEN, CLOSE, link::STATUS], "{:?}", wire.sent);
    let s = status(&wire.sent);
    assert_eq!((s.events_in, s.commands_out, s.unexpected), (2, 2, 0));
    assert_eq!(wire.sent[3 + link::STATUS_BYTES], OPEN, "closed again: open");
    assert!(wire.sent.ends_with(&[link::READY, OPEN]), "RESET: the initial word, then open: {:?}", wire.sent);
    assert_eq!((counters.commands_out, word), (1, 0b10));
}

#[test]
fn step_takes_one_decision_and_holds() {
    let (wire, _, _) = session(FaultPolicy::Continue, &[&[link::HOLD], &[link::STEP], &[OPENED]]);
    assert_eq!(wire.sent, [OPEN, link::SYNC], "one decision, then SYNC and held");
}

#[test]
fn an_unexpected_sensor_event_is_noted_and_safe_state_stops_deciding() {
    let (wire, counters, _) = session(FaultPolicy::SafeState, &[&[CLOSED], &[OPENED]]);
    assert_eq!(wire.notes[0], Note::Unexpected { event: CLOSED, automaton: 0 });
    // `opened` from closed is unexpected too (the safe state still takes inputs, and decides nothing).
    assert_eq!(wire.notes[1..3], [Note::Safe, Note::Unexpected { event: OPENED, automaton: 0 }]);
    assert_eq!(counters.unexpected, 2);
    assert!(wire.sent.contains(&link::SAFE), "{:?}", wire.sent);
    assert!(!wire.sent.contains(&CLOSE), "no decision in the safe state: {:?}", wire.sent);
}
