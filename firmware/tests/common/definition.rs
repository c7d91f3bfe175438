//! The definition the runtime is held to (design notes §4), by brute force over the transition lists:
//! an input moves every automaton holding it that can take it (one that cannot is unexpected), a fired
//! event must be enabled (every automaton holding it can take it), the runtime is idle exactly when
//! nothing is enabled — and [`agree`] runs the runtime and the definition side by side.

use firmware::choice::Choose;
use firmware::rng::Entropy;
use firmware::runtime::{Applied, Decision, Runtime};
use firmware::table::Position;
use proptest::prelude::*;

use super::Spec;

/// One step of a run: an input byte, or a decision.
#[derive(Clone, Debug)]
pub enum Op {
    Input(u8),
    Decide,
}

/// Up to 40 steps over `events` events (inputs up to `events`: one more than the set has).
pub fn ops(events: u8) -> impl Strategy<Value = Vec<Op>> {
    proptest::collection::vec(prop_oneof![(0..=events).prop_map(Op::Input), Just(Op::Decide)], 0..40)
}

/// Where `event` leads `spec` from `state`, if anywhere.
pub fn delta(spec: &Spec, state: usize, event: u8) -> Option<usize> {
    spec.transitions.iter().find(|t| t.0 == state && t.1 == event).map(|t| t.2)
}

/// Runs `ops` on `rt` (over `specs` with `events` events, `controllable` flags per event) and on the
/// definition: the same states after every step (`handles` gives each spec's handle per state), every
/// fired event enabled, idle exactly when nothing is, the same counters.
#[allow(clippy::too_many_arguments)]
pub fn agree<
    P: Choose<W>,
    E: Entropy,
    const W: usize,
    const N: usize,
    const WIDE: bool,
    const MASK: usize,
    const LAYOUT: u8,
    Q: Position,
>(
    rt: &mut Runtime<'_, P, E, W, N, WIDE, MASK, LAYOUT, Q>,
    events: u8,
    specs: &[Spec],
    controllable: &[bool],
    ops: &[Op],
    handles: &[Vec<usize>],
) -> Result<(), TestCaseError> {
    let mut states: Vec<usize> = specs.iter().map(|s| s.initial).collect();
    let (mut events_in, mut unexpected, mut unknown) = (0, 0, 0);
    let enabled_ref = |states: &[usize]| -> Vec<u8> {
        (0..events)
            .filter(|&e| controllable[usize::from(e)])
            .filter(|&e| {
                specs.iter().zip(states).all(|(s, &q)| !s.alphabet.contains(&e) || delta(s, q, e).is_some())
            })
            .collect()
    };
    for op in ops {
        match *op {
            Op::Input(e) => {
                let got = rt.apply(e);
                if e >= events || controllable[usize::from(e)] {
                    unknown += 1;
                    prop_assert_eq!(got, Applied::Unknown);
                } else {
                    events_in += 1;
                    let mut stuck = None;
                    for (a, s) in specs.iter().enumerate().filter(|(_, s)| s.alphabet.contains(&e)) {
                        match delta(s, states[a], e) {
                            Some(t) => states[a] = t,
                            None => stuck = stuck.or(Some(a as u8)),
                        }
                    }
                    match stuck {
                        None => prop_assert_eq!(got, Applied::Taken),
                        Some(automaton) => {
                            unexpected += 1;
                            prop_assert_eq!(got, Applied::Unexpected { automaton });
                        }
                    }
                }
            }
            Op::Decide => {
                let enabled = enabled_ref(&states);
                match rt.decide(|| false) {
                    Decision::Fired(c) => {
                        prop_assert!(enabled.contains(&c), "fired {} not in {:?}", c, enabled);
                        for (a, s) in specs.iter().enumerate().filter(|(_, s)| s.alphabet.contains(&c)) {
                            states[a] = delta(s, states[a], c).unwrap();
                        }
                    }
                    Decision::Idle => prop_assert!(enabled.is_empty(), "idle with {:?} enabled", enabled),
                    other => prop_assert!(false, "unexpected {:?}", other),
                }
            }
        }
        for (a, &q) in states.iter().enumerate() {
            prop_assert_eq!(rt.states()[a].get(), handles[a][q]);
        }
    }
    let c = rt.counters();
    prop_assert_eq!((c.events_in, c.unexpected, c.unknown_bytes), (events_in, unexpected, unknown));
    Ok(())
}
