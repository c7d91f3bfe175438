//! Accessible, coaccessible and trim parts of an automaton.
//!
//! A state is accessible when a string leads to it from the initial state and coaccessible when a string
//! leads from it to a marked state; the trim part keeps the states that are both, and so generates exactly
//! the prefixes of the marked language.

use crate::model::Automaton;

use super::reverse::Reverse;
use super::{Inputs, SynthError};
use crate::model::{Dfa, NONE};

/// Which states of `d` are reachable from the initial state through states with `keep` set.
pub(crate) fn accessible_mask(d: &Dfa, keep: &[bool]) -> Vec<bool> {
    let mut seen = vec![false; d.state_count()];
    let mut stack = Vec::new();
    if let Some(i) = d.initial.filter(|&i| keep[i as usize]) {
        seen[i as usize] = true;
        stack.push(i);
    }
    while let Some(s) = stack.pop() {
        for (_, t) in d.edges(s) {
            if keep[t as usize] && !seen[t as usize] {
                seen[t as usize] = true;
                stack.push(t);
            }
        }
    }
    seen
}

/// Which states with `keep` set reach a marked state with `keep` set through states with `keep` set.
pub(crate) fn coaccessible_mask(d: &Dfa, rev: &Reverse, keep: &[bool]) -> Vec<bool> {
    let mut seen = vec![false; d.state_count()];
    let mut stack: Vec<u32> = Vec::new();
    for s in 0..d.state_count() {
        if keep[s] && d.marked[s] {
            seen[s] = true;
            stack.push(s as u32);
        }
    }
    while let Some(s) = stack.pop() {
        for (p, _) in rev.preds(s) {
            if keep[p as usize] && !seen[p as usize] {
                seen[p as usize] = true;
                stack.push(p);
            }
        }
    }
    seen
}

/// The part of `d` reachable from the initial state through states with `keep` set, renumbered in
/// breadth-first order; also returns the old id of each new state.
pub(crate) fn restrict(d: &Dfa, keep: &[bool]) -> (Dfa, Vec<u32>) {
    let mut new_id = vec![NONE; d.state_count()];
    let mut order = Vec::new();
    if let Some(i) = d.initial.filter(|&i| keep[i as usize]) {
        new_id[i as usize] = 0;
        order.push(i);
    }
    let mut next = 0;
    while next < order.len() {
        let s = order[next];
        next += 1;
        for (_, t) in d.edges(s) {
            if keep[t as usize] && new_id[t as usize] == NONE {
                new_id[t as usize] = order.len() as u32;
                order.push(t);
            }
        }
    }
    (renumber(d, &order, &new_id), order)
}

/// The states of `d` listed in `order` (with `new_id` their inverse), transitions between them only.
fn renumber(d: &Dfa, order: &[u32], new_id: &[u32]) -> Dfa {
    let mut b = crate::model::DfaBuilder::new(d.alphabet.clone());
    for &s in order {
        b.start_state(d.marked[s as usize]);
        for (e, t) in d.edges(s) {
            if new_id[t as usize] != NONE {
                b.push(e, new_id[t as usize]);
            }
        }
    }
    let initial = d.initial.map(|i| new_id[i as usize]).filter(|&i| i != NONE);
    b.finish(initial)
}

/// Keeps the states of `a` selected by `mask(dfa)`, in their original order, or nothing when the initial
/// state is not selected.
fn keep_states(a: &Automaton, mask: impl Fn(&Dfa) -> Vec<bool>) -> Result<Automaton, SynthError> {
    let inputs = Inputs::new(std::iter::once(a))?;
    let d = &inputs.dfas[0];
    let keep = mask(d);
    let mut order: Vec<u32> = Vec::new();
    let mut new_id = vec![NONE; d.state_count()];
    if d.initial.is_some_and(|i| keep[i as usize]) {
        for s in 0..d.state_count() {
            if keep[s] {
                new_id[s] = order.len() as u32;
                order.push(s as u32);
            }
        }
    }
    let r = renumber(d, &order, &new_id);
    Ok(r.to_automaton(&a.name, a.kind, &inputs.table, |s| a.states[order[s as usize] as usize].name.clone()))
}

/// The accessible part of `a` (states keep their names and relative order).
pub fn accessible(a: &Automaton) -> Result<Automaton, SynthError> {
    keep_states(a, |d| accessible_mask(d, &vec![true; d.state_count()]))
}

/// The coaccessible part of `a`; empty when the initial state cannot reach a marked state.
pub fn coaccessible(a: &Automaton) -> Result<Automaton, SynthError> {
    keep_states(a, |d| coaccessible_mask(d, &Reverse::new(d), &vec![true; d.state_count()]))
}

/// The trim part of `a`: accessible and coaccessible states only.
pub fn trim(a: &Automaton) -> Result<Automaton, SynthError> {
    keep_states(a, |d| {
        let co = coaccessible_mask(d, &Reverse::new(d), &vec![true; d.state_count()]);
        accessible_mask(d, &co)
    })
}
