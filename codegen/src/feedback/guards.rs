//! The rules from guards read off the symbolic engine's BDDs ([`crate::symbolic::Guards`]) instead of
//! the explicit closed loop ([`Sfbc`](super::Sfbc)): per controllable event, F_σ minimised between the
//! valuations of the reachable plant states it allows and those no reachable plant state produces (none
//! with `exact`) — the same formula [`rules`](super::rules) gives, without listing a state.

use crate::pack::PackSet;
use crate::symbolic::Guards;

use super::minimise::Universe;
use super::{FeedbackError, Rule, Vector};

/// The rules of `guards` (of the plants of `set`, bound to `vector`), in event id order; memory deciding
/// an event somewhere is [`FeedbackError::Memory`] (a feedback from guards keeps no memory).
pub fn rules(
    set: &PackSet,
    vector: &Vector,
    guards: &Guards,
    exact: bool,
) -> Result<Vec<Rule>, FeedbackError> {
    let n = vector.signals.signals.len();
    let u = Universe::new(n);
    let reachable = guards.to_signals(&guards.reachable, &vector.cubes, n);
    let dc = if exact { u.union(&[]) } else { reachable.not() };
    let mut order: Vec<(crate::model::EventId, &crate::symbolic::Guard)> =
        guards.guards.iter().filter_map(|g| Some((set.events().id(&g.event)?, g))).collect();
    order.sort_by_key(|(e, _)| *e);
    order
        .into_iter()
        .map(|(event, g)| {
            if !g.memory.is_false() {
                return Err(FeedbackError::Memory(format!(
                    "{}: the supervisor's memory decides it at {} plant states (the guard is no function of \
                     the plant state; --memory needs the explicit engine)",
                    g.event,
                    guards.count(&g.memory)
                )));
            }
            let on = guards.to_signals(&g.allowed, &vector.cubes, n);
            Ok(Rule { event, cubes: u.minimise(&on, &dc), command: vector.command(event) })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use num_bigint::BigUint;
    use proptest::prelude::*;

    use super::*;
    use crate::feedback::Sfbc;
    use crate::model::testing::{arb_automaton, with_kind};
    use crate::model::{Automaton, Kind};
    use crate::symbolic::Options;
    use crate::synth::families::random_seeded;
    use crate::synth::{Config, SynthError};

    /// The guards agree with the explicit feedback of the set plants ‖ supC, state by state: the same
    /// reachable plant states, f_σ(x) equal on each, and memory deciding at the same (state, event)s.
    fn same_feedback(plants: &[Automaton], specs: &[Automaton]) -> Result<(), TestCaseError> {
        let cfg = Config::default();
        let sup = match crate::synth::monolithic(plants, specs, &cfg) {
            Ok(sup) => sup.automaton,
            Err(SynthError::NoSupervisor(_)) => return Ok(()),
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        let Ok(set) = PackSet::new(plants.to_vec(), vec![sup]) else { return Ok(()) };
        let f = Sfbc::compute(&set, false).unwrap();
        let g = Guards::compute(plants, specs, &cfg, &Options::default()).unwrap();
        prop_assert_eq!(g.count(&g.reachable), BigUint::from(f.entries.len()));
        let mut guards: Vec<&crate::symbolic::Guard> = g.guards.iter().collect();
        guards.sort_by_key(|g| set.events().id(&g.event));
        let names: Vec<&str> = guards.iter().map(|g| g.event.as_str()).collect();
        let want: Vec<&str> = f.controllable.iter().map(|&e| set.events().name(e)).collect();
        prop_assert_eq!(names, want);
        for entry in &f.entries {
            prop_assert!(g.holds(&g.reachable, &entry.state));
            for (guard, &allowed) in guards.iter().zip(&entry.allowed) {
                let at = &entry.state;
                prop_assert_eq!(g.holds(&guard.allowed, at), allowed, "{} at {:?}", guard.event, at);
                let decides =
                    f.conflicts.iter().any(|c| &c.state == at && set.events().name(c.event) == guard.event);
                prop_assert_eq!(g.holds(&guard.memory, at), decides, "memory, {} at {:?}", guard.event, at);
            }
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

        #[test]
        fn random_sets_give_the_explicit_feedback(
            g0 in arb_automaton("G0".into(), 4, 4),
            g1 in arb_automaton("G1".into(), 4, 3),
            e0 in arb_automaton("E0".into(), 4, 3),
        ) {
            let plants = [with_kind(g0, Kind::Plant), with_kind(g1, Kind::Plant)];
            same_feedback(&plants, &[with_kind(e0, Kind::Spec)])?;
        }

        #[test]
        fn random_families_give_the_explicit_feedback(n in 2usize..=4, seed in 1u64..u64::MAX) {
            let inst = random_seeded(n, seed);
            same_feedback(&inst.plants, &inst.specs)?;
        }
    }
}
