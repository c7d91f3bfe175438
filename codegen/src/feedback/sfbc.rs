//! The state feedback control f of a supervisor set (docs/design.md §10): on the reachable closed loop
//! plants ‖ supervisors, f_σ(x) = 1 iff σ is physically possible at plant state x and every reachable
//! closed-loop state (x, y) enables it. Where two such states disagree the supervisors' memory decides:
//! each such plant state is reported with a shortest trace to each side, and with memory allowed the
//! fewest supervisors whose states settle every disagreement are kept as further state components.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use crate::model::EventId;
use crate::pack::{PackSet, Role};
use crate::synth::Reachable;

use super::FeedbackError;

/// Most closed-loop states explored.
pub const STATE_LIMIT: usize = 2_000_000;

/// One reachable state of the feedback's domain: a plant state, with the kept supervisors' states when
/// memory is kept.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// Local state of each plant, then of each kept supervisor.
    pub state: Vec<u32>,
    /// Per controllable event (in [`Sfbc::controllable`] order): physically possible here.
    pub possible: Vec<bool>,
    /// Per controllable event: f_σ — possible and enabled by every closed-loop state over this one.
    pub allowed: Vec<bool>,
}

impl Entry {
    /// Whether f disables something here (the entry counts in |f|).
    pub fn inhibits(&self) -> bool {
        self.possible.iter().zip(&self.allowed).any(|(&p, &a)| p && !a)
    }
}

/// A plant state where the supervisors' memory decides an event.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Conflict {
    /// The plant state.
    pub state: Vec<u32>,
    /// The event decided by memory.
    pub event: EventId,
    /// A shortest trace to a closed-loop state over it that enables the event.
    pub enabled_after: Vec<EventId>,
    /// A shortest trace to one that disables it.
    pub disabled_after: Vec<EventId>,
}

/// The supervisors kept as memory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Memory {
    /// Member indices of the kept supervisors, in set order.
    pub kept: Vec<usize>,
    /// Bits their states take (⌈log2 states⌉ each).
    pub bits: u32,
}

/// The feedback of a set.
#[derive(Clone, Debug)]
pub struct Sfbc {
    /// The controllable events that some plant holds, in event id order: one rung each.
    pub controllable: Vec<EventId>,
    /// Number of plants (the first members of the set).
    pub plants: usize,
    /// Reachable closed-loop states (plants ‖ supervisors).
    pub closed_states: usize,
    /// Reachable plant states under supervision: the closed loop's states projected on the plants, each
    /// counted once.
    pub plant_states: usize,
    /// The domain's reachable states, in order of their state vectors: one per reachable plant state, or,
    /// with memory kept, one per reachable (plant state, kept supervisors' states) pair.
    pub entries: Vec<Entry>,
    /// Plant states where memory decides (empty when the feedback is a function of the plant state).
    pub conflicts: Vec<Conflict>,
    /// The supervisors kept, when memory was allowed and needed.
    pub memory: Option<Memory>,
}

/// The closed loop explored, with a parent per state for shortest traces.
struct Closed {
    reach: Reachable,
    parent: Vec<Option<(u32, u32)>>,
}

impl Closed {
    fn explore(set: &PackSet) -> Result<Closed, FeedbackError> {
        let dfas: Vec<_> = set.members().iter().map(|m| &m.dfa).collect();
        let reach = Reachable::explore(&dfas, STATE_LIMIT)?;
        let n = reach.dfa().state_count();
        let mut parent = vec![None; n];
        let mut seen = vec![false; n];
        let mut queue = VecDeque::from([0u32]);
        if n > 0 {
            seen[0] = true;
        }
        while let Some(s) = queue.pop_front() {
            for (e, t) in reach.dfa().edges(s) {
                if !seen[t as usize] {
                    seen[t as usize] = true;
                    parent[t as usize] = Some((s, e));
                    queue.push_back(t);
                }
            }
        }
        Ok(Closed { reach, parent })
    }

    fn trace(&self, mut s: u32) -> Vec<EventId> {
        let mut out = Vec::new();
        while let Some((p, e)) = self.parent[s as usize] {
            out.push(EventId::from_u32(e));
            s = p;
        }
        out.reverse();
        out
    }
}

/// Per closed-loop state: its domain key (plants and `kept` supervisors) and the controllable events it
/// enables, as a bit per [`Sfbc::controllable`] index.
fn enabled(closed: &Closed, controllable: &[EventId]) -> Vec<Vec<bool>> {
    let dfa = closed.reach.dfa();
    (0..dfa.state_count() as u32)
        .map(|s| controllable.iter().map(|e| dfa.step(s, e.as_u32()).is_some()).collect())
        .collect()
}

impl Sfbc {
    /// The feedback of `set`: with `memory`, the fewest supervisors whose states settle every
    /// disagreement are kept (and the conflicts stay reported); without, conflicts are left for the
    /// caller to refuse.
    pub fn compute(set: &PackSet, memory: bool) -> Result<Sfbc, FeedbackError> {
        Sfbc::compute_deciding(set, memory, &[])
    }

    /// The feedback of `set` as [`Sfbc::compute`] gives it, except for the events of `decided`, which
    /// something other than the plant state decides (guards over a module's variables): the supervisors
    /// are read as allowing them wherever the plants do, so f_σ is σ's physical possibility, no
    /// disagreement over them is a conflict and none keeps memory. The program writes f_σ ∧ guard.
    pub fn compute_deciding(set: &PackSet, memory: bool, decided: &[EventId]) -> Result<Sfbc, FeedbackError> {
        let members = set.members();
        let plants = members.iter().take_while(|m| m.role == Role::Plant).count();
        let table = set.events();
        let controllable: Vec<EventId> = table
            .ids()
            .filter(|&e| table.is_controllable(e))
            .filter(|e| members[..plants].iter().any(|m| m.dfa.has_event(e.as_u32())))
            .collect();
        let closed = Closed::explore(set)?;
        let mut en = enabled(&closed, &controllable);
        let n = closed.reach.dfa().state_count() as u32;
        let tuples: Vec<Vec<u32>> = (0..n).map(|s| closed.reach.tuple(s)).collect();
        let possible = |state: &[u32], e: EventId| {
            members[..plants]
                .iter()
                .zip(state)
                .all(|(m, &s)| !m.dfa.has_event(e.as_u32()) || m.dfa.step(s, e.as_u32()).is_some())
        };
        for (i, e) in controllable.iter().enumerate().filter(|(_, e)| decided.contains(e)) {
            for (t, row) in tuples.iter().zip(&mut en) {
                row[i] = possible(&t[..plants], *e);
            }
        }
        let plant_states = tuples.iter().map(|t| &t[..plants]).collect::<BTreeSet<_>>().len();
        let conflicts = conflicts(&closed, &tuples, &en, plants, &controllable);
        let kept = if memory && !conflicts.is_empty() {
            Some(keep(&tuples, &en, plants, members.len()))
        } else {
            None
        };
        let kept_list = kept.clone().unwrap_or_default();
        let key = |t: &[u32]| -> Vec<u32> {
            t[..plants].iter().copied().chain(kept_list.iter().map(|&k| t[k])).collect()
        };
        let mut domain: BTreeMap<Vec<u32>, Vec<bool>> = BTreeMap::new();
        for (t, e) in tuples.iter().zip(&en) {
            let slot = domain.entry(key(t)).or_insert_with(|| e.clone());
            for (a, b) in slot.iter_mut().zip(e) {
                *a &= *b;
            }
        }
        let entries = domain
            .into_iter()
            .map(|(state, allowed)| {
                let possible = controllable.iter().map(|&e| possible(&state[..plants], e)).collect();
                Entry { state, possible, allowed }
            })
            .collect();
        let memory = kept
            .map(|kept| Memory { bits: kept.iter().map(|&k| bits(members[k].state_count())).sum(), kept });
        Ok(Sfbc { controllable, plants, closed_states: n as usize, plant_states, entries, conflicts, memory })
    }

    /// |f|: the domain's states where f disables a physically possible controllable event.
    pub fn size(&self) -> usize {
        self.entries.iter().filter(|e| e.inhibits()).count()
    }
}

/// Bits to number `states` states.
pub(super) fn bits(states: usize) -> u32 {
    usize::BITS - states.saturating_sub(1).leading_zeros()
}

/// One event's two sides at one plant state: the first closed-loop state enabling it, the first disabling it.
type Sides = (Option<u32>, Option<u32>);

/// Per plant state and controllable event on which its closed-loop states disagree: one conflict with
/// shortest traces to each side (the first in breadth-first order).
fn conflicts(
    closed: &Closed,
    tuples: &[Vec<u32>],
    en: &[Vec<bool>],
    plants: usize,
    controllable: &[EventId],
) -> Vec<Conflict> {
    // Per plant state: per event, the first closed-loop state enabling it and the first disabling it.
    let mut sides: BTreeMap<&[u32], Vec<Sides>> = BTreeMap::new();
    for (s, (t, e)) in tuples.iter().zip(en).enumerate() {
        let slot = sides.entry(&t[..plants]).or_insert_with(|| vec![(None, None); controllable.len()]);
        for (side, &on) in slot.iter_mut().zip(e) {
            let which = if on { &mut side.0 } else { &mut side.1 };
            which.get_or_insert(s as u32);
        }
    }
    let mut out = Vec::new();
    for (x, slot) in sides {
        for (i, side) in slot.iter().enumerate() {
            if let (Some(on), Some(off)) = *side {
                out.push(Conflict {
                    state: x.to_vec(),
                    event: controllable[i],
                    enabled_after: closed.trace(on),
                    disabled_after: closed.trace(off),
                });
            }
        }
    }
    out
}

/// The fewest supervisors (then the first in set order) whose states, with the plant state, determine
/// the enabled controllable events of every reachable closed-loop state.
fn keep(tuples: &[Vec<u32>], en: &[Vec<bool>], plants: usize, members: usize) -> Vec<usize> {
    let sups: Vec<usize> = (plants..members).collect();
    let decides = |kept: &[usize]| {
        let mut seen: BTreeMap<Vec<u32>, &Vec<bool>> = BTreeMap::new();
        tuples.iter().zip(en).all(|(t, e)| {
            let k: Vec<u32> = t[..plants].iter().copied().chain(kept.iter().map(|&s| t[s])).collect();
            *seen.entry(k).or_insert(e) == e
        })
    };
    // Subsets by size, each size in lexicographic order, while there are few supervisors; else greedy.
    if sups.len() <= 12 {
        for size in 1..=sups.len() {
            let mut pick: Vec<usize> = (0..size).collect();
            loop {
                let kept: Vec<usize> = pick.iter().map(|&i| sups[i]).collect();
                if decides(&kept) {
                    return kept;
                }
                // Next combination.
                let Some(i) = (0..size).rev().find(|&i| pick[i] < sups.len() - size + i) else { break };
                pick[i] += 1;
                let first = pick[i];
                for (off, p) in pick[i + 1..].iter_mut().enumerate() {
                    *p = first + off + 1;
                }
            }
        }
    }
    sups
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use proptest::prelude::*;

    use super::*;
    use crate::model::testing::{arb_automaton, build};
    use crate::model::Composition;

    /// f by brute force: every closed-loop state reached by stepping the composition from the initial
    /// state; per plant state, the controllable events some plant holds that every closed-loop state
    /// over it allows.
    fn brute(set: &PackSet, plants: usize) -> BTreeMap<Vec<u32>, BTreeSet<u32>> {
        let all: Vec<&crate::model::Automaton> = set.members().iter().map(|m| &m.automaton).collect();
        let c = Composition::new(&all, set.events()).unwrap();
        let table = set.events();
        let ctrl: Vec<EventId> = table
            .ids()
            .filter(|&e| table.is_controllable(e) && (0..plants).any(|p| c.has_event(p, e)))
            .collect();
        let (mut seen, mut todo) = (BTreeSet::new(), vec![c.initial()]);
        let mut f: BTreeMap<Vec<u32>, BTreeSet<u32>> = BTreeMap::new();
        while let Some(s) = todo.pop() {
            if !seen.insert(s.clone()) {
                continue;
            }
            let here: BTreeSet<u32> = ctrl.iter().filter(|&&e| c.allows(&s, e)).map(|e| e.as_u32()).collect();
            f.entry(s[..plants].to_vec())
                .and_modify(|a| *a = a.intersection(&here).copied().collect())
                .or_insert(here);
            for e in c.enabled(&s) {
                let mut t = s.clone();
                c.step(&mut t, e);
                todo.push(t);
            }
        }
        f
    }

    /// The closed loop by brute force: every state reached by stepping the composition from the initial
    /// state.
    fn closed_loop(set: &PackSet) -> BTreeSet<Vec<u32>> {
        let all: Vec<&crate::model::Automaton> = set.members().iter().map(|m| &m.automaton).collect();
        let c = Composition::new(&all, set.events()).unwrap();
        let (mut seen, mut todo) = (BTreeSet::new(), vec![c.initial()]);
        while let Some(s) = todo.pop() {
            if !seen.insert(s.clone()) {
                continue;
            }
            for e in c.enabled(&s) {
                let mut t = s.clone();
                c.step(&mut t, e);
                todo.push(t);
            }
        }
        seen
    }

    proptest! {
        /// The report's counts against brute force: closed-loop states, plant states (the closed loop
        /// projected on the plants) and, with memory kept, the domain of (plant state, kept supervisors'
        /// states) pairs — three different numbers as soon as a supervisor has memory.
        #[test]
        fn closed_loop_plant_states_and_the_domain_are_counted_apart(
            g1 in arb_automaton("G1".into(), 4, 3),
            g2 in arb_automaton("G2".into(), 3, 3),
            s1 in arb_automaton("S1".into(), 4, 4),
            s2 in arb_automaton("S2".into(), 3, 4),
        ) {
            let Ok(set) = PackSet::new(vec![g1, g2], vec![s1, s2]) else { return Ok(()) };
            let all = closed_loop(&set);
            let project = |keep: &[usize]| -> usize {
                all.iter().map(|t| keep.iter().map(|&k| t[k]).collect::<Vec<_>>()).collect::<BTreeSet<_>>().len()
            };
            for memory in [false, true] {
                let f = Sfbc::compute(&set, memory).unwrap();
                prop_assert_eq!(f.closed_states, all.len());
                prop_assert_eq!(f.plant_states, project(&[0, 1]));
                let kept = f.memory.as_ref().map_or(Vec::new(), |m| m.kept.clone());
                let domain: Vec<usize> = [0, 1].into_iter().chain(kept).collect();
                prop_assert_eq!(f.entries.len(), project(&domain));
            }
        }

        /// f and its conflicts against brute force on random plants and supervisors.
        #[test]
        fn f_is_the_intersection_over_each_plant_state(
            g1 in arb_automaton("G1".into(), 4, 3),
            g2 in arb_automaton("G2".into(), 4, 3),
            s in arb_automaton("S".into(), 4, 4),
        ) {
            let Ok(set) = PackSet::new(vec![g1, g2], vec![s]) else { return Ok(()) };
            let f = Sfbc::compute(&set, false).unwrap();
            let want = brute(&set, 2);
            let got: BTreeMap<Vec<u32>, BTreeSet<u32>> = f
                .entries
                .iter()
                .map(|e| (e.state.clone(), f.controllable.iter().zip(&e.allowed).filter(|(_, &a)| a).map(|(c, _)| c.as_u32()).collect()))
                .collect();
            prop_assert_eq!(&got, &want);
            // A conflict exactly where some closed-loop state over x allows an event f does not.
            for c in &f.conflicts {
                prop_assert!(!want[&c.state].contains(&c.event.as_u32()));
            }
        }
    }

    #[test]
    fn bits_number_states() {
        assert_eq!([1, 2, 3, 4, 5, 8, 9].map(bits), [0, 1, 2, 2, 3, 3, 4]);
    }

    /// A machine that starts by `start` or `alt` (both controllable) and ends by `done`, under a
    /// supervisor allowing `alt` only every other cycle: the plant state idle is reached with the
    /// supervisor in two states that disagree on `alt`.
    fn alternating() -> PackSet {
        let plant = build(
            "M",
            &["I", "W"],
            &["start", "alt"],
            &[("I", "start", "W"), ("I", "alt", "W"), ("W", "done", "I")],
        );
        let sup = build(
            "S",
            &["a", "b", "c", "d"],
            &["start", "alt"],
            &[
                ("a", "start", "b"),
                ("a", "alt", "b"),
                ("b", "done", "c"),
                ("c", "start", "d"),
                ("d", "done", "a"),
            ],
        );
        PackSet::new(vec![plant], vec![sup]).unwrap()
    }

    #[test]
    fn memory_decides_where_closed_loop_states_disagree() {
        let set = alternating();
        let f = Sfbc::compute(&set, false).unwrap();
        assert_eq!(f.conflicts.len(), 1, "{:?}", f.conflicts);
        let c = &f.conflicts[0];
        let names = |t: &[EventId]| t.iter().map(|&e| set.events().name(e).to_owned()).collect::<Vec<_>>();
        assert_eq!(names(&c.enabled_after), Vec::<String>::new());
        assert_eq!(names(&c.disabled_after), ["start", "done"]);
        assert!(f.memory.is_none());
        let m = Sfbc::compute(&set, true).unwrap();
        assert_eq!(m.memory, Some(Memory { kept: vec![1], bits: 2 }));
        // With S's state as memory, idle splits in two: alt allowed in (I, a), not in (I, c).
        let idle: Vec<_> =
            m.entries.iter().filter(|e| e.state[0] == 0).map(|e| (e.state[1], e.allowed.clone())).collect();
        assert_eq!(idle, [(0, vec![true, true]), (2, vec![true, false])]);
        assert!(m.entries.iter().all(|e| e.state.len() == 2));
    }
}
