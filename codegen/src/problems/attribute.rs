//! Which supervisors a finding involves: the closed loop's findings attributed to the supervisors whose
//! disablement or state makes the two orders differ, so that a user reading the closed loop knows
//! which supervisor to look at (docs/checks.md, "Which supervisor a finding involves").
//!
//! The rule, on the members of the product checked (plants and supervisors), at the finding's state:
//!
//! * a diamond on x and y (choice, inexact synchronisation, simultaneity): supervisor S is involved
//!   when it *disables* an event of x·y or y·x where every plant holding it allows it (the order is cut
//!   by control, not by the plant's physics), or when both orders are defined and S ends them in two
//!   different states (what S enables next depends on the order);
//! * an avalanche p –σ→ q –σ→ r: S holds σ and its state changes on one of the two steps (it is S's
//!   state, moved by σ, that enables σ again).
//!
//! A finding that involves no supervisor is the plants' alone: an order their physics refuses, or
//! states only plants tell apart.

use std::collections::HashMap;

use super::{Finding, Problem};
use crate::model::Automaton;

/// One member of the product: its transitions by (state, event name), and whether it is a supervisor.
struct Member<'a> {
    automaton: &'a Automaton,
    supervisor: bool,
    next: HashMap<(usize, &'a str), usize>,
}

/// What one member does on one event.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Step {
    /// The event is not in its alphabet: it stays.
    Stays,
    /// It moves to this state.
    To(usize),
    /// It holds the event and has no transition for it here.
    Refuses,
}

impl Member<'_> {
    fn step(&self, state: usize, event: &str) -> Step {
        match self.next.get(&(state, event)) {
            Some(&t) => Step::To(t),
            None if self.automaton.event_id(event).is_some() => Step::Refuses,
            None => Step::Stays,
        }
    }
}

/// Attributes the findings of one product to its supervisors.
pub struct Attributor<'a> {
    members: Vec<Member<'a>>,
}

impl<'a> Attributor<'a> {
    /// For the product of `members`, of which those named in `supervisors` are supervisors.
    pub fn new(members: &[&'a Automaton], supervisors: &[String]) -> Attributor<'a> {
        let members = members
            .iter()
            .map(|&a| Member {
                automaton: a,
                supervisor: supervisors.contains(&a.name),
                next: a
                    .transitions
                    .iter()
                    .map(|t| ((t.source.index(), a.events[t.event.index()].name.as_str()), t.target.index()))
                    .collect(),
            })
            .collect();
        Attributor { members }
    }

    /// Every member's state after `trace` from the initial states; `None` if the trace leaves the
    /// product (a finding of another product).
    fn replay(&self, trace: &[String]) -> Option<Vec<usize>> {
        let mut state: Vec<usize> =
            self.members.iter().map(|m| m.automaton.initial.map(|s| s.index())).collect::<Option<_>>()?;
        for e in trace {
            state = self.step(&state, e).ok()?;
        }
        Some(state)
    }

    /// The product's step on `event`, or the members that refuse it.
    fn step(&self, state: &[usize], event: &str) -> Result<Vec<usize>, Vec<usize>> {
        let steps: Vec<Step> = self.members.iter().zip(state).map(|(m, &s)| m.step(s, event)).collect();
        let refusing: Vec<usize> = (0..steps.len()).filter(|&k| steps[k] == Step::Refuses).collect();
        if !refusing.is_empty() {
            return Err(refusing);
        }
        Ok(steps.iter().zip(state).map(|(step, &s)| if let Step::To(t) = *step { t } else { s }).collect())
    }

    /// The supervisors `f` involves (see the module documentation), in member order; empty when the
    /// finding is the plants' alone or its trace does not replay here.
    pub fn supervisors(&self, f: &Finding) -> Vec<String> {
        let Some(at) = self.replay(&f.trace) else { return Vec::new() };
        let mut involved = vec![false; self.members.len()];
        match (f.problem, f.events.as_slice()) {
            (Problem::Avalanche, [sigma]) => {
                let mut state = at;
                for _ in 0..2 {
                    let Ok(next) = self.step(&state, sigma) else { break };
                    for (k, m) in self.members.iter().enumerate() {
                        involved[k] |= m.supervisor && next[k] != state[k];
                    }
                    state = next;
                }
            }
            (_, [x, y]) => {
                let mut ends = Vec::new();
                for order in [[x, y], [y, x]] {
                    let mut state = at.clone();
                    for e in order {
                        match self.step(&state, e) {
                            Ok(next) => state = next,
                            Err(refusing) => {
                                // Cut by control only where no plant refuses it too.
                                if refusing.iter().all(|&k| self.members[k].supervisor) {
                                    for k in refusing {
                                        involved[k] = true;
                                    }
                                }
                                break;
                            }
                        }
                    }
                    ends.push(state);
                }
                if self.reaches(&at, [x, y]) && self.reaches(&at, [y, x]) {
                    for (k, m) in self.members.iter().enumerate() {
                        involved[k] |= m.supervisor && ends[0][k] != ends[1][k];
                    }
                }
            }
            _ => {}
        }
        self.members.iter().zip(involved).filter(|(_, i)| *i).map(|(m, _)| m.automaton.name.clone()).collect()
    }

    /// Whether the product takes `order` from `state`.
    fn reaches(&self, state: &[usize], order: [&String; 2]) -> bool {
        self.step(state, order[0]).and_then(|s| self.step(&s, order[1])).is_ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::build;
    use crate::problems::run;

    /// The findings of the product of `plants` and `sups`, each with the supervisors it involves.
    fn attributed(plants: &[Automaton], sups: &[Automaton]) -> Vec<(Problem, Vec<String>, Vec<String>)> {
        let members: Vec<Automaton> = plants.iter().chain(sups).cloned().collect();
        let product = crate::synth::product(&members, &crate::synth::Config::default()).unwrap();
        let refs: Vec<&Automaton> = members.iter().collect();
        let names: Vec<String> = sups.iter().map(|s| s.name.clone()).collect();
        let who = Attributor::new(&refs, &names);
        run(&product, &Problem::ALL)
            .iter()
            .map(|f| (f.problem, f.events.clone(), who.supervisors(f)))
            .collect()
    }

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| (*s).to_owned()).collect()
    }

    #[test]
    fn a_supervisor_disabling_a_command_after_an_input_is_named() {
        // The plant lets `go` (controllable) and `u` happen in either order; S disables go after u.
        let mut g = build("G", &["0"], &[], &[("0", "go", "0"), ("0", "u", "0")]);
        g.events.iter_mut().for_each(|e| e.controllable = e.name == "go");
        let mut s = build("S", &["0", "1"], &[], &[("0", "go", "0"), ("0", "u", "1"), ("1", "u", "1")]);
        s.events.iter_mut().for_each(|e| e.controllable = e.name == "go");
        let found = attributed(&[g], &[s]);
        assert_eq!(found, [(Problem::InexactSynchronisation, names(&["go", "u"]), names(&["S"]))]);
    }

    #[test]
    fn orders_the_plant_refuses_are_the_plants_alone() {
        // Exclusive sensors: after a, b is physically impossible, and S mirrors the plant.
        let g = build("G", &["0", "a", "b"], &[], &[("0", "a", "a"), ("0", "b", "b")]);
        let s = build("S", &["0", "a", "b"], &[], &[("0", "a", "a"), ("0", "b", "b")]);
        let found = attributed(&[g], &[s]);
        assert_eq!(found, [(Problem::Simultaneity, names(&["a", "b"]), Vec::new())]);
    }

    #[test]
    fn a_supervisor_whose_state_depends_on_the_order_is_named_and_one_that_ignores_it_is_not() {
        // Two independent plants; S1 counts a then b (its state tells the orders apart), S2 holds a
        // only and ends both orders in one state.
        let g1 = build("G1", &["0"], &[], &[("0", "a", "0")]);
        let g2 = build("G2", &["0"], &[], &[("0", "b", "0")]);
        let s1 = build(
            "S1",
            &["0", "1", "2", "3"],
            &[],
            &[
                ("0", "a", "1"),
                ("0", "b", "2"),
                ("1", "b", "3"),
                ("2", "a", "0"),
                ("3", "a", "3"),
                ("3", "b", "3"),
            ],
        );
        let s2 = build("S2", &["0", "1"], &[], &[("0", "a", "1"), ("1", "a", "1")]);
        let found = attributed(&[g1, g2], &[s1, s2]);
        let first = found.iter().find(|f| f.1 == names(&["a", "b"])).unwrap();
        assert_eq!(first.2, names(&["S1"]));
    }

    #[test]
    fn an_avalanche_names_the_supervisor_that_steps_twice() {
        let g = build("G", &["0"], &[], &[("0", "a", "0")]);
        let s = build("S", &["0", "1", "2"], &[], &[("0", "a", "1"), ("1", "a", "2"), ("2", "a", "2")]);
        let t = build("T", &["0"], &[], &[("0", "a", "0")]);
        let found = attributed(&[g], &[s, t]);
        assert_eq!(found, [(Problem::Avalanche, names(&["a"]), names(&["S"]))]);
    }
}
