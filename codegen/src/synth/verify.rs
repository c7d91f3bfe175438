//! Verifying a supervisor: the controllability and nonblocking checks, each with a shortest
//! counterexample trace.

use crate::model::{Automaton, EventId, EventTable};

use super::product::{tuple_name, Exploration, Options};
use super::reverse::Reverse;
use super::trim::coaccessible_mask;
use super::{Config, Inputs, SynthError};
use crate::model::Dfa;

/// The supervisor disables an uncontrollable event the plant can generate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Uncontrollable {
    /// Shortest string of the closed loop leading to the offending state.
    pub trace: Vec<String>,
    /// The closed-loop state: the tuple of plant states and the supervisor state.
    pub state: String,
    /// The uncontrollable event the plant enables and the supervisor refuses.
    pub event: String,
}

/// What a specification forbids at the end of a [`NoSupervisor`] trace.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Forbidden {
    /// The plant can generate this uncontrollable event there, and the specification refuses it.
    Refused {
        /// The event.
        event: String,
    },
    /// No marked state can be reached from there within what the specification allows.
    Blocking,
    /// The set has no initial state (an automaton of it has no state).
    NoInitialState,
}

/// No supervisor exists for a specification: the plant alone, by uncontrollable events no controller
/// can stop, goes from its initial state into what the specification forbids. The verdict of
/// synthesis when supC is empty.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "no supervisor exists for specification {} (plant {}): uncontrollable events, which no controller \
     can prevent, lead from the initial state into what it forbids\n{}",
    specs.join(" + "),
    plants.join(", "),
    self.explain()
)]
pub struct NoSupervisor {
    /// The specification (several when conflicting ones were merged).
    pub specs: Vec<String>,
    /// The plant components it was synthesised against.
    pub plants: Vec<String>,
    /// A shortest string of uncontrollable events from the initial state to [`NoSupervisor::state`].
    pub trace: Vec<String>,
    /// The state it reaches: the tuple of plant and specification states, in the order of
    /// [`NoSupervisor::plants`] then [`NoSupervisor::specs`].
    pub state: String,
    /// What is forbidden there.
    pub forbidden: Forbidden,
}

impl NoSupervisor {
    /// The trace and what it runs into, in words: indented lines.
    fn explain(&self) -> String {
        let tuple = self.plants.iter().chain(&self.specs).cloned().collect::<Vec<_>>().join(", ");
        let trace = |events: Vec<&String>| {
            if events.is_empty() {
                "ε (the initial state)".to_owned()
            } else {
                events.iter().map(|e| e.as_str()).collect::<Vec<_>>().join(" ")
            }
        };
        match &self.forbidden {
            Forbidden::Refused { event } => format!(
                "  shortest trace: {}\n  at state {} of ({tuple}) the plant can generate '{event}' \
                 (uncontrollable) and the specification forbids it",
                trace(self.trace.iter().chain(std::iter::once(event)).collect()),
                self.state
            ),
            Forbidden::Blocking => format!(
                "  shortest trace: {}\n  from state {} of ({tuple}) no marked state can be reached within what \
                 the specification allows",
                trace(self.trace.iter().collect()),
                self.state
            ),
            Forbidden::NoInitialState => "  an automaton of the set has no state".to_owned(),
        }
    }
}

/// The shortest string of uncontrollable events (breadth-first, events in ascending order) leading in
/// `d` from its initial state to a state with `target` set, and that state; `None` when there is no
/// initial state or no such string.
pub(crate) fn uncontrollable_path(
    d: &Dfa,
    controllable: &[bool],
    target: &[bool],
) -> Option<(Vec<u32>, u32)> {
    let initial = d.initial()?;
    let mut parent: Vec<Option<(u32, u32)>> = vec![None; d.state_count()];
    let mut seen = vec![false; d.state_count()];
    seen[initial as usize] = true;
    let mut queue = std::collections::VecDeque::from([initial]);
    while let Some(s) = queue.pop_front() {
        if target[s as usize] {
            let (mut path, mut at) = (Vec::new(), s);
            while let Some((p, e)) = parent[at as usize] {
                path.push(e);
                at = p;
            }
            path.reverse();
            return Some((path, s));
        }
        for (e, t) in d.edges(s) {
            if !controllable[e as usize] && !seen[t as usize] {
                seen[t as usize] = true;
                parent[t as usize] = Some((s, e));
                queue.push_back(t);
            }
        }
    }
    None
}

/// A reachable state of a product from which no marked state can be reached.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Blocking {
    /// Shortest string leading to the blocking state.
    pub trace: Vec<String>,
    /// The product state: the tuple of component states.
    pub state: String,
}

fn names(table: &EventTable, events: &[u32]) -> Vec<String> {
    events.iter().map(|&e| table.name(EventId::from_u32(e)).to_owned()).collect()
}

/// Checks that `supervisor` is controllable with respect to the plant `‖ plants`: in every reachable
/// state of plant ‖ supervisor, each uncontrollable event the plant enables is enabled by the supervisor
/// too (or is outside its alphabet). Returns the first violation in breadth-first order.
pub fn controllability(
    plants: &[Automaton],
    supervisor: &Automaton,
    cfg: &Config,
) -> Result<Option<Uncontrollable>, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(std::iter::once(supervisor)))?;
    let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
    let x = Exploration::run(
        &dfas,
        &inputs.controllable,
        Options { plants: plants.len(), parents: true },
        cfg,
        "closed loop",
    )?;
    let sources: Vec<&Automaton> = plants.iter().chain(std::iter::once(supervisor)).collect();
    Ok(x.bad.first().map(|&(s, e)| Uncontrollable {
        trace: names(&inputs.table, &x.trace(s)),
        state: tuple_name(&x, &sources, s),
        event: inputs.table.name(EventId::from_u32(e)).to_owned(),
    }))
}

/// The first (breadth-first) reachable state of the product of `dfas` that cannot reach a marked state.
pub(crate) fn first_blocking(
    dfas: &[&Dfa],
    inputs: &Inputs,
    cfg: &Config,
    what: &str,
) -> Result<(Exploration, Option<u32>), SynthError> {
    let x = Exploration::run(
        dfas,
        &inputs.controllable,
        Options { plants: dfas.len(), parents: true },
        cfg,
        what,
    )?;
    let d = &x.dfa;
    super::memory::admit(cfg, what, d.state_count(), Reverse::bytes(d))?;
    let co = coaccessible_mask(d, &Reverse::new(d), &vec![true; d.state_count()]);
    let first = co.iter().position(|&c| !c).map(|s| s as u32);
    Ok((x, first))
}

/// Checks that the product of `automata` is nonblocking (every reachable state can reach a marked
/// state). For a set of supervisors this is the conflict check: they are nonconflicting exactly when it
/// passes. Returns the first blocking state in breadth-first order.
pub fn nonblocking(automata: &[Automaton], cfg: &Config) -> Result<Option<Blocking>, SynthError> {
    let inputs = Inputs::new(automata.iter())?;
    let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
    let (x, first) = first_blocking(&dfas, &inputs, cfg, "product")?;
    let sources: Vec<&Automaton> = automata.iter().collect();
    Ok(first
        .map(|s| Blocking { trace: names(&inputs.table, &x.trace(s)), state: tuple_name(&x, &sources, s) }))
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::model::testing::{arb_automaton, build};
    use crate::model::Kind;
    use crate::synth::{local_modular, monolithic};

    /// The length of the shortest string of uncontrollable events from the initial state to a target
    /// state, by trying every such string of each length in turn (a string longer than the state count
    /// repeats a state, so none is needed).
    fn brute_force(d: &Dfa, controllable: &[bool], target: &[bool]) -> Option<usize> {
        let uncontrollable: Vec<u32> =
            d.alphabet().iter().copied().filter(|&e| !controllable[e as usize]).collect();
        let mut frontier: Vec<u32> = d.initial().into_iter().collect();
        for length in 0..=d.state_count() {
            if frontier.iter().any(|&s| target[s as usize]) {
                return Some(length);
            }
            // Every string one longer: each state reached so far, each uncontrollable event.
            frontier = frontier
                .iter()
                .flat_map(|&s| uncontrollable.iter().filter_map(move |&e| d.step(s, e)))
                .collect();
        }
        None
    }

    proptest! {
        #[test]
        fn the_path_is_uncontrollable_reaches_the_target_and_is_shortest(
            a in arb_automaton("A".into(), 4, 6),
            target in proptest::collection::vec(any::<bool>(), 6),
        ) {
            let inputs = Inputs::new(std::iter::once(&a)).unwrap();
            let d = &inputs.dfas[0];
            let target = &target[..d.state_count()];
            let found = uncontrollable_path(d, &inputs.controllable, target);
            prop_assert_eq!(found.as_ref().map(|(p, _)| p.len()), brute_force(d, &inputs.controllable, target));
            if let Some((path, end)) = found {
                let mut s = d.initial().unwrap();
                for e in path {
                    prop_assert!(!inputs.controllable[e as usize]);
                    s = d.step(s, e).unwrap();
                }
                prop_assert_eq!(s, end);
                prop_assert!(target[end as usize]);
            }
        }
    }

    fn plant(a: Automaton) -> Automaton {
        Automaton { kind: Kind::Plant, ..a }
    }

    fn spec(a: Automaton) -> Automaton {
        Automaton { kind: Kind::Spec, ..a }
    }

    fn verdict(r: Result<impl std::fmt::Debug, SynthError>) -> NoSupervisor {
        match r {
            Err(SynthError::NoSupervisor(v)) => *v,
            other => panic!("expected no supervisor, got {other:?}"),
        }
    }

    #[test]
    fn a_forbidden_uncontrollable_event_two_steps_away_is_the_end_of_the_trace() {
        // The plant runs u then v by itself; the specification allows u but never v after it.
        let mut g =
            build("G", &["0", "1", "2"], &["c"], &[("0", "u", "1"), ("1", "v", "2"), ("2", "c", "0")]);
        g.states[0].marked = true;
        let mut e = build("E", &["0", "1"], &[], &[("0", "u", "1"), ("0", "v", "0")]);
        e.states[0].marked = true;
        let (g, e) = (plant(g), spec(e));
        let cfg = Config::default();
        let v = verdict(local_modular(std::slice::from_ref(&g), std::slice::from_ref(&e), &cfg));
        assert_eq!((v.trace.as_slice(), v.state.as_str()), (["u".to_owned()].as_slice(), "(1,1)"));
        assert_eq!(v.forbidden, Forbidden::Refused { event: "v".into() });
        let text = v.to_string();
        assert!(text.starts_with("no supervisor exists for specification E (plant G)"), "{text}");
        assert!(text.contains("shortest trace: u v\n"), "{text}");
        assert!(text.contains("at state (1,1) of (G, E) the plant can generate 'v'"), "{text}");
        // Monolithic synthesis gives the same verdict.
        assert_eq!(verdict(monolithic(&[g], &[e], &cfg)).trace, ["u"]);
    }

    #[test]
    fn a_dead_end_the_plant_runs_into_is_a_blocking_verdict() {
        // u leads by itself into a state from which nothing is marked.
        let mut g = build("G", &["0", "1"], &["c"], &[("0", "u", "1"), ("0", "c", "0")]);
        g.states[0].marked = true;
        let mut e = spec(build("E", &["0"], &["c"], &[("0", "c", "0")]));
        e.states[0].marked = true;
        let v = verdict(local_modular(&[plant(g)], &[e], &Config::default()));
        assert_eq!(
            (v.trace, v.state, v.forbidden),
            (vec!["u".to_owned()], "(1,0)".to_owned(), Forbidden::Blocking)
        );
    }
}
