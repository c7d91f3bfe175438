//! The rungs from guards read off the symbolic engine's BDDs ([`crate::symbolic::Guards`]) instead of
//! the explicit closed loop ([`Sfbc`](super::Sfbc)): per controllable event, F_σ minimised between the
//! valuations of the reachable plant states it allows and those no reachable plant state produces (none
//! with `exact`) — the same formula [`rungs`](super::rungs) gives, without listing a state.

use crate::config::{Cube, ScanPolicy, Signals};
use crate::pack::PackSet;
use crate::plc::PlcOptions;
use crate::provenance::Provenance;
use crate::symbolic::Guards;

use super::minimise::Universe;
use super::{memory, program, program_files, EventRung, OnePerScan, StateError, Vector};

/// A state-based program written from guards.
#[derive(Clone, Debug)]
pub struct GuardProgram {
    /// `(file name, contents)`, as [`Output::files`](super::Output::files).
    pub files: Vec<(String, String)>,
    /// One rung per controllable event, in event id order.
    pub rungs: Vec<EventRung>,
    /// The state vectors bound to the set.
    pub vector: Vector,
}

/// Writes the state-based program of `set`'s plants under `signals`' state vectors from `guards` (as
/// [`generate`](super::generate) does from the explicit closed loop; `exact` keeps F_σ free of
/// don't-cares, and `choice`, else `[state] choice`, fires one command per scan chosen by that policy).
pub fn generate(
    set: &PackSet,
    signals: Signals,
    guards: &Guards,
    opts: &PlcOptions,
    (exact, choice): (bool, Option<ScanPolicy>),
    provenance: &Provenance,
) -> Result<GuardProgram, StateError> {
    let exact = exact || signals.exact;
    let policy = choice.or(signals.choice);
    let vector = Vector::bind(set, signals)?;
    let rungs = rungs(set, &vector, guards, exact)?;
    let events = rungs.iter().filter_map(|r| set.events().id(&r.event));
    let one = policy.map(|policy| OnePerScan::new(policy, opts.seed, &vector, events));
    let files = program_files(
        set,
        &vector,
        &rungs,
        &memory::Memory::default(),
        one.as_ref(),
        opts,
        exact,
        provenance,
    )?;
    Ok(GuardProgram { files, rungs, vector })
}

/// The rungs of `guards` (of the plants of `set`, bound to `vector`); memory deciding an event somewhere
/// is [`StateError::Memory`] (a state-based program from guards keeps no memory).
pub fn rungs(
    set: &PackSet,
    vector: &Vector,
    guards: &Guards,
    exact: bool,
) -> Result<Vec<EventRung>, StateError> {
    let names: Vec<String> = vector.signals.signals.iter().map(|s| s.name.clone()).collect();
    let n = names.len();
    let u = Universe::new(n);
    let reachable = guards.to_signals(&guards.reachable, &vector.cubes, n);
    let dc = if exact { u.union(&[]) } else { reachable.not() };
    let mut order: Vec<&crate::symbolic::Guard> = guards.guards.iter().collect();
    order.sort_by_key(|g| set.events().id(&g.event));
    order
        .into_iter()
        .map(|g| {
            if !g.memory.is_false() {
                return Err(StateError::Memory(format!(
                    "{}: the supervisor's memory decides it at {} plant states (the guard is no function of \
                     the plant state; --memory needs the explicit engine)",
                    g.event,
                    guards.count(&g.memory)
                )));
            }
            let on = guards.to_signals(&g.allowed, &vector.cubes, n);
            let cover = u.minimise(&on, &dc);
            let command = set
                .events()
                .id(&g.event)
                .and_then(|e| vector.commands.get(e.index()).copied().flatten())
                .map_or(Cube::default(), |(_, c)| c);
            Ok(program::rung(&names, &g.event, cover, command, Vec::new()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use num_bigint::BigUint;
    use proptest::prelude::*;

    use super::*;
    use crate::model::testing::{arb_automaton, with_kind};
    use crate::model::{Automaton, Kind};
    use crate::plc::state_based::Sfbc;
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
