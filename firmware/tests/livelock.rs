//! The livelock example of the design notes (§4.1) under every choice policy: a fixed global queue
//! livelocks a nonblocking plant, a queue per choice site and the random policies do not.

mod common;

use common::{handles, livelock};
use firmware::choice::{Choose, First, GlobalQueue, LocalQueue, Random, RandomGlobalQueue, RandomLocalQueue};
use firmware::fault::FaultPolicy;
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Decision, Runtime};
use firmware::table::CheckedSet;

const CONFIG: Config = Config { guard: true, on_fault: FaultPolicy::Continue, reseed_every: 64 };

/// The states visited (1–4) in `steps` steps: the runtime decides; when nothing is enabled the plant
/// produces its only uncontrollable event.
fn run<P: Choose<1>>(policy: P, seed: u64, steps: usize) -> Vec<usize> {
    let (set, spec) = livelock();
    let hs = handles(&spec);
    let number = |h: u16| hs.iter().position(|&o| o == usize::from(h)).unwrap() + 1;
    let mut rt = Runtime::new(
        CheckedSet::<1, 1, false, 1, { firmware::table::layout::RANKED }>::new(set).unwrap(),
        CONFIG,
        policy,
        SeedEntropy::new(seed),
    );
    let mut visited = vec![number(rt.states()[0])];
    for _ in 0..steps {
        match rt.decide(|| false) {
            Decision::Fired(_) => {}
            Decision::Idle => {
                let mask = set.mask(0, rt.states()[0]).unwrap()[0];
                assert_eq!(mask.count_ones(), 1, "an idle state has exactly one uncontrollable event");
                rt.apply(mask.trailing_zeros() as u8);
            }
            other => panic!("unexpected {other:?}"),
        }
        visited.push(number(rt.states()[0]));
    }
    visited
}

#[test]
fn global_queue_livelocks_between_1_and_3() {
    let v = run(GlobalQueue::default(), 0, 40);
    assert_eq!(&v[..6], &[1, 3, 1, 3, 1, 3]);
    assert!(!v.contains(&4));
}

#[test]
fn local_queue_reaches_the_marked_state() {
    assert_eq!(run(LocalQueue::<2>::default(), 0, 8), vec![1, 3, 4, 1, 2, 4, 1, 3, 1]);
}

#[test]
fn first_always_takes_a() {
    assert_eq!(run(First, 0, 6), vec![1, 3, 4, 1, 3, 4, 1]);
}

#[test]
fn random_global_queue_reaches_4_on_every_seed() {
    // It does not take every transition quickly: a round that starts with `a` at 1 still holds only `b`
    // at 3, so 3 –a→ 4 needs a round that ends at 1 — the global cursor's bias, randomised.
    for seed in 0..300 {
        let v = run(RandomGlobalQueue::<1>::default(), seed, 60);
        assert!(v.contains(&4), "seed {seed}: {v:?}");
    }
}

#[test]
fn random_and_random_local_queue_reach_4_and_take_every_transition_on_every_seed() {
    for seed in 0..300 {
        for (name, v) in [
            // Uniform choice has no memory: give it time enough to take each branch at state 3.
            ("random", run(Random, seed, 240)),
            ("random-local-queue", run(RandomLocalQueue::<1, 2>::default(), seed, 60)),
        ] {
            assert!(v.contains(&4), "{name} seed {seed}: {v:?}");
            for (from, to) in [(1, 3), (1, 2), (3, 4), (3, 1)] {
                assert!(
                    v.windows(2).any(|w| w == [from, to]),
                    "{name} seed {seed}: {from}->{to} never in {v:?}"
                );
            }
        }
    }
}

#[test]
fn random_local_queue_takes_each_site_event_once_per_round() {
    // At state 1 the two events alternate per round: in any two consecutive visits of a round both occur.
    let v = run(RandomLocalQueue::<1, 2>::default(), 5, 400);
    let from1: Vec<usize> = v.windows(2).filter(|w| w[0] == 1 && w[1] != 1).map(|w| w[1]).collect::<Vec<_>>();
    for pair in from1.chunks_exact(2) {
        assert_ne!(pair[0], pair[1], "{from1:?}");
    }
}
