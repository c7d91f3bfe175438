//! The symbolic engine against the explicit one: on random small sets and on the generated families,
//! the same supervisor (equal state and transition counts, equal generated and marked languages) and
//! the same conflict verdicts; and exact counts beyond 2⁶⁴ against a product whose size is known.

use num_bigint::BigUint;
use proptest::prelude::*;

use super::*;
use crate::model::testing::{arb_automaton, with_kind};
use crate::model::Kind;
use crate::synth::families::{generate, random_seeded};
use crate::synth::{language, local_modular, verify};

fn no_merge() -> Config {
    Config { merge_conflicting: false, ..Config::default() }
}

/// Symbolic and explicit monolithic synthesis agree on `plants` and `specs`, in both variable orders.
fn same_supervisor(plants: &[Automaton], specs: &[Automaton]) -> Result<(), TestCaseError> {
    let cfg = Config::default();
    let explicit = match crate::synth::monolithic(plants, specs, &cfg) {
        Ok(sup) => sup.automaton,
        // The explicit engine's verdict "no supervisor exists": the symbolic supervisor is empty.
        Err(crate::synth::SynthError::NoSupervisor(_)) => {
            for order in [Order::EventGraph, Order::Given] {
                let s = monolithic(plants, specs, &cfg, &Options { order, ..Options::default() }).unwrap();
                prop_assert_eq!(&s.states, &BigUint::from(0u32), "states, {:?}", order);
            }
            return Ok(());
        }
        Err(e) => return Err(TestCaseError::fail(e.to_string())),
    };
    for order in [Order::EventGraph, Order::Given] {
        let s = monolithic(plants, specs, &cfg, &Options { order, ..Options::default() }).unwrap();
        prop_assert_eq!(&s.states, &BigUint::from(explicit.states.len()), "states, {:?}", order);
        prop_assert_eq!(
            &s.transitions,
            &BigUint::from(explicit.transitions.len()),
            "transitions, {:?}",
            order
        );
        let listed = s.automaton.as_ref().unwrap();
        listed.validate().unwrap();
        prop_assert_eq!(listed.states.len(), explicit.states.len());
        prop_assert_eq!(listed.transitions.len(), explicit.transitions.len());
        if !explicit.states.is_empty() {
            prop_assert_eq!(language::equal(listed, &explicit).unwrap(), None, "languages, {:?}", order);
        }
    }
    Ok(())
}

/// A configuration whose conflict check lets the explicit engine build `explicit_states` states first
/// (`0`: the symbolic engine; a small number: `auto` switching to the symbolic engine mid-way).
fn hooked(explicit_states: usize) -> (Config, std::sync::Arc<Check>) {
    let check = std::sync::Arc::new(Check { explicit_states, ..Check::default() });
    (Config { nonblocking: Some(check.clone()), ..no_merge() }, check)
}

/// The symbolic conflict check of the unmerged local modular set agrees with the explicit one, and so
/// does the `auto` check whether it stays explicit (a cap above the product) or switches to the symbolic
/// engine mid-way (a cap of `auto_cap` states, below it).
fn same_conflict_verdict(
    plants: &[Automaton],
    specs: &[Automaton],
    auto_cap: usize,
) -> Result<(), TestCaseError> {
    let set = match local_modular(plants, specs, &no_merge()) {
        Ok(set) => set,
        // A specification with no supervisor: no set to check for conflict, with either check.
        Err(crate::synth::SynthError::NoSupervisor(_)) => {
            for explicit_states in [0, auto_cap, AUTO_EXPLICIT_STATES] {
                let hooked = local_modular(plants, specs, &hooked(explicit_states).0);
                prop_assert!(matches!(hooked, Err(crate::synth::SynthError::NoSupervisor(_))));
            }
            return Ok(());
        }
        Err(e) => return Err(TestCaseError::fail(e.to_string())),
    };
    let sups: Vec<Automaton> = set.supervisors.into_iter().map(|s| s.automaton).collect();
    let explicit = verify::nonblocking(&sups, &Config::default()).unwrap().is_none();
    prop_assert_eq!(nonblocking(&sups, &Config::default(), &Options::default()).unwrap(), explicit);
    let product = crate::synth::product(&sups, &Config::default()).unwrap().states.len();
    // The check runs one independent subsystem (supervisors sharing no event) at a time: the symbolic
    // engine runs when one subsystem's product passes the cap, and it never runs past a product within it.
    let largest = subsystems(&sups)
        .iter()
        .map(|part| {
            let members: Vec<Automaton> = part.iter().map(|&i| sups[i].clone()).collect();
            crate::synth::product(&members, &Config::default()).unwrap().states.len()
        })
        .max()
        .unwrap_or(0);
    for explicit_states in [0, auto_cap, AUTO_EXPLICIT_STATES] {
        let (cfg, check) = hooked(explicit_states);
        prop_assert_eq!(
            local_modular(plants, specs, &cfg).unwrap().nonconflicting,
            explicit,
            "cap {}",
            explicit_states
        );
        // The symbolic engine ran exactly when the explicit product passed the cap (or there was none).
        let symbolic = check.ran.load(Ordering::Relaxed);
        prop_assert!(!symbolic || product > explicit_states, "cap {}", explicit_states);
        if explicit {
            // Nonconflicting: every subsystem was checked.
            prop_assert_eq!(symbolic, largest > explicit_states, "cap {}", explicit_states);
        }
    }
    Ok(())
}

/// `automata` grouped into the components of the "shares an event" graph (by event name).
fn subsystems(automata: &[Automaton]) -> Vec<Vec<usize>> {
    let shares =
        |a: &Automaton, b: &Automaton| a.events.iter().any(|e| b.events.iter().any(|f| f.name == e.name));
    let mut parts: Vec<Vec<usize>> = Vec::new();
    let mut seen = vec![false; automata.len()];
    for start in 0..automata.len() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut part = vec![start];
        let mut k = 0;
        while k < part.len() {
            for j in 0..automata.len() {
                if !seen[j] && shares(&automata[part[k]], &automata[j]) {
                    seen[j] = true;
                    part.push(j);
                }
            }
            k += 1;
        }
        parts.push(part);
    }
    parts
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn random_sets_give_the_explicit_supervisor(
        g0 in arb_automaton("G0".into(), 4, 4),
        g1 in arb_automaton("G1".into(), 4, 3),
        e0 in arb_automaton("E0".into(), 4, 3),
        e1 in arb_automaton("E1".into(), 4, 2),
    ) {
        let plants = [with_kind(g0, Kind::Plant), with_kind(g1, Kind::Plant)];
        let specs = [with_kind(e0, Kind::Spec), with_kind(e1, Kind::Spec)];
        same_supervisor(&plants, &specs)?;
        same_conflict_verdict(&plants, &specs, 3)?;
    }

    #[test]
    fn random_families_give_the_explicit_supervisor(n in 2usize..=4, seed in 1u64..u64::MAX) {
        let inst = random_seeded(n, seed);
        same_supervisor(&inst.plants, &inst.specs)?;
        same_conflict_verdict(&inst.plants, &inst.specs, 3)?;
    }
}

#[test]
fn the_families_give_the_explicit_supervisors() {
    for (family, n) in
        [("transfer-line", 4), ("transfer-line-k3", 3), ("factory", 3), ("philosophers", 4), ("cat-mouse", 1)]
    {
        let inst = generate(family, n).unwrap();
        same_supervisor(&inst.plants, &inst.specs).unwrap_or_else(|e| panic!("{family}-{n}: {e}"));
        same_conflict_verdict(&inst.plants, &inst.specs, 10).unwrap_or_else(|e| panic!("{family}-{n}: {e}"));
    }
}

#[test]
fn counts_beyond_two_to_the_64_are_exact() {
    // 70 independent machines, all states marked, under a specification that allows every start:
    // supC is the whole product, 2^70 states with one step per machine in each.
    let n = 70u32;
    let plants: Vec<Automaton> = (0..n)
        .map(|i| {
            let mut m = crate::model::testing::machine(&format!("M{i}"), &format!("s{i}"), &format!("f{i}"));
            m.states.iter_mut().for_each(|s| s.marked = true);
            m
        })
        .collect();
    let starts: Vec<String> = (0..n).map(|i| format!("s{i}")).collect();
    let names: Vec<&str> = starts.iter().map(String::as_str).collect();
    let edges: Vec<(&str, &str, &str)> = names.iter().map(|&e| ("x", e, "x")).collect();
    let mut spec = crate::model::testing::build("Free", &["x"], &names, &edges);
    spec.kind = Kind::Spec;
    spec.states[0].marked = true;
    let s = monolithic(&plants, &[spec], &Config::default(), &Options::default()).unwrap();
    let states = BigUint::from(1u8) << n;
    assert_eq!(s.states.to_string(), "1180591620717411303424");
    assert_eq!(s.transitions, &states * BigUint::from(n));
    assert_eq!(s.states, states);
    assert!(s.automaton.is_none(), "2^70 states are not listed");
}

#[test]
fn the_memory_limit_stops_a_fixed_point_naming_its_bdd() {
    let inst = generate("transfer-line-k3", 3).unwrap();
    let cfg = Config { memory_limit: Some(1), ..Config::default() };
    let err = monolithic(&inst.plants, &inst.specs, &cfg, &Options::default()).unwrap_err();
    assert!(matches!(err, SynthError::BddMemoryLimit { limit: 1, .. }), "{err:?}");
    assert!(err.to_string().contains("BDDs of"), "{err}");
}
