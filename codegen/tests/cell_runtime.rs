//! The firmware's runtime on the manufacturing cell's tables, on the host, with the default policy
//! (`random-local-queue`): at every state the closed loop can reach it takes each enabled controllable
//! event within a bounded number of decisions, so it takes every reachable controllable transition of the
//! six supervisors; and in a long closed-loop run against a random plant it fires only what the closed
//! loop allows, never meets an unexpected event and never deadlocks.

use std::collections::{BTreeSet, VecDeque};
use std::path::Path;

use codegen::formats::read_path;
use codegen::pack::{ranked, PackSet};
use firmware::build::HostTables;
use firmware::choice::RandomLocalQueue;
use firmware::fault::FaultPolicy;
use firmware::rng::{Rng, SeedEntropy};
use firmware::runtime::{Config, Decision, Runtime};
use firmware::table::{CheckedSet, SupervisorSet};

const N: usize = 10;

fn cell() -> HostTables<1> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/cell");
    let read = |names: &[&str], sub: &str| -> Vec<_> {
        names.iter().flat_map(|n| read_path(&dir.join(sub).join(format!("{n}.xmd"))).unwrap()).collect()
    };
    let plants = read(&["G1", "G2", "G3", "G4"], "plants");
    let sups = read(&["S1", "S2_6", "S3", "S4", "S5", "S7"], "published");
    HostTables::new(ranked::encode(&PackSet::new(plants, sups).unwrap()).unwrap()).unwrap()
}

fn controllable(set: &SupervisorSet<'_, 1>, e: u8) -> bool {
    set.controllable[usize::from(e / 32)] & (1 << (e % 32)) != 0
}

/// The state after `e` if every automaton holding `e` can take it.
fn step(set: &SupervisorSet<'_, 1>, states: &[u16; N], e: u8) -> Option<[u16; N]> {
    let mut next = *states;
    for a in 0..set.automata.len() {
        if set.holders_of(e, set.holder_bytes()).is_some_and(|h| h & (1 << a) != 0) {
            next[a] = set.step(a, states[a], e)?;
        }
    }
    Some(next)
}

/// (supervisor, state, event) for every controllable event the reachable closed loop can fire.
fn reachable_controllable(set: &SupervisorSet<'_, 1>) -> BTreeSet<(usize, u16, u8)> {
    let events = set.events() as u8;
    // Every automaton starts in handle 0, its first record.
    let init = [0u16; N];
    let (mut seen, mut queue, mut out) = (BTreeSet::from([init]), VecDeque::from([init]), BTreeSet::new());
    while let Some(s) = queue.pop_front() {
        for e in 0..events {
            let Some(next) = step(set, &s, e) else { continue };
            if controllable(set, e) {
                out.extend(supervisor_moves(set, &s, e));
            }
            if seen.insert(next) {
                queue.push_back(next);
            }
        }
    }
    out
}

fn supervisor_moves(set: &SupervisorSet<'_, 1>, s: &[u16; N], e: u8) -> Vec<(usize, u16, u8)> {
    (usize::from(set.plants)..N)
        .filter(|&a| set.holders_of(e, set.holder_bytes()).is_some_and(|h| h & (1 << a) != 0))
        .map(|a| (a, s[a], e))
        .collect()
}

type Rt<'t> =
    Runtime<'t, RandomLocalQueue<1, 8>, SeedEntropy, 1, N, false, 3, { firmware::table::layout::RANKED }>;

fn runtime<'t>(set: &'t SupervisorSet<'t, 1>, seed: u64) -> Rt<'t> {
    let config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 1024 };
    Rt::new(CheckedSet::new(set).unwrap(), config, RandomLocalQueue::default(), SeedEntropy::new(seed))
}

/// Decisions at one state within which every enabled event must have been chosen.
const DECISIONS_PER_STATE: usize = 64;

#[test]
fn random_local_queue_takes_every_enabled_event_at_every_reachable_state() {
    let host = cell();
    let (names, set) = (host.event_names(), host.set());
    let mut rt = runtime(&set, 7);
    let init: [u16; N] = rt.states();
    let (mut seen, mut queue, mut taken) = (BTreeSet::from([init]), VecDeque::from([init]), BTreeSet::new());
    while let Some(s) = queue.pop_front() {
        let enabled: BTreeSet<u8> = (0..names.len() as u8)
            .filter(|&e| controllable(&set, e) && step(&set, &s, e).is_some())
            .collect();
        let mut chosen = BTreeSet::new();
        for _ in 0..DECISIONS_PER_STATE {
            if chosen.len() == enabled.len() {
                break;
            }
            rt.restore(&s).unwrap();
            match rt.decide(|| false) {
                Decision::Fired(c) => {
                    assert!(enabled.contains(&c), "fired {} the closed loop forbids", names[usize::from(c)]);
                    chosen.insert(c);
                    taken.extend(supervisor_moves(&set, &s, c));
                }
                Decision::Idle => break,
                other => panic!("{other:?}"),
            }
        }
        assert_eq!(chosen, enabled, "at {s:?}");
        for e in 0..names.len() as u8 {
            if let Some(next) = step(&set, &s, e) {
                if seen.insert(next) {
                    queue.push_back(next);
                }
            }
        }
    }
    let wanted = reachable_controllable(&set);
    assert!(wanted.len() > 300, "{}", wanted.len());
    // A checkpoint naming no state is refused.
    assert!(rt.restore(&[u16::MAX; N]).is_err());
    assert_eq!(taken, wanted);
    assert_eq!(rt.counters().unexpected, 0);
}

/// Steps of the closed-loop run.
const STEPS: usize = 200_000;

#[test]
fn closed_loop_with_a_random_plant_is_safe_and_live() {
    let host = cell();
    let (names, set) = (host.event_names(), host.set());
    for seed in 0..3 {
        let mut rt = runtime(&set, seed);
        let mut plant = Rng::new(SeedEntropy::new(1000 + seed), 0);
        let mut fired = 0;
        for _ in 0..STEPS {
            let before = rt.states();
            let inputs: Vec<u8> = (0..names.len() as u8)
                .filter(|&e| !controllable(&set, e) && step(&set, &before, e).is_some())
                .collect();
            if !inputs.is_empty() && plant.below(2) == 0 {
                rt.apply(inputs[plant.below(inputs.len() as u32) as usize]);
                continue;
            }
            match rt.decide(|| false) {
                Decision::Fired(c) => {
                    assert!(
                        step(&set, &before, c).is_some(),
                        "fired {} the closed loop forbids",
                        names[usize::from(c)]
                    );
                    fired += 1;
                }
                Decision::Idle => assert!(!inputs.is_empty(), "deadlock at {before:?}"),
                other => panic!("{other:?}"),
            }
        }
        assert_eq!(rt.counters().unexpected, 0);
        assert!(fired > STEPS / 5, "seed {seed}: only {fired} commands");
    }
}
