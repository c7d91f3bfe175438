//! Language-preserving state minimisation by partition refinement.
//!
//! Two states are equivalent when they agree on marking and, for every event, either both lack the
//! transition or both have it into equivalent states; the quotient by that equivalence generates and marks
//! the same languages with the fewest states (an undefined transition is its own class, so a transition into
//! a blocking state is kept: the generated language needs it). Refinement starts from the marked/unmarked
//! split and re-partitions by (class, [(event, class of target)]) signatures until the count of classes
//! stops growing.

use std::collections::HashMap;

use crate::model::Automaton;

use super::trim::restrict;
use super::{Inputs, SynthError};
use crate::model::{Dfa, DfaBuilder, NONE};

/// The minimal automaton of `d` (accessible part, classes numbered breadth-first) and, for each of its
/// states, one state of `d` it stands for.
pub(crate) fn minimize_dfa(d: &Dfa) -> (Dfa, Vec<u32>) {
    let (acc, old) = restrict(d, &vec![true; d.state_count()]);
    let n = acc.state_count();
    let mut class: Vec<u32> = acc.marked.iter().map(|&m| u32::from(m)).collect();
    let mut count = class.iter().copied().collect::<std::collections::BTreeSet<_>>().len();
    let mut sig = Vec::new();
    let mut starts = Vec::with_capacity(n + 1);
    loop {
        sig.clear();
        starts.clear();
        for s in 0..n as u32 {
            starts.push(sig.len());
            sig.push(class[s as usize]);
            for (e, t) in acc.edges(s) {
                sig.push(e);
                sig.push(class[t as usize]);
            }
        }
        starts.push(sig.len());
        let mut ids: HashMap<&[u32], u32> = HashMap::with_capacity(count * 2);
        let mut next = Vec::with_capacity(n);
        for s in 0..n {
            let key = &sig[starts[s]..starts[s + 1]];
            let fresh = ids.len() as u32;
            next.push(*ids.entry(key).or_insert(fresh));
        }
        let new_count = ids.len();
        drop(ids);
        class = next;
        if new_count == count {
            break;
        }
        count = new_count;
    }
    quotient(&acc, &class, count, &old)
}

/// The automaton of classes, numbered breadth-first from the initial class.
fn quotient(acc: &Dfa, class: &[u32], count: usize, old: &[u32]) -> (Dfa, Vec<u32>) {
    let mut rep = vec![NONE; count];
    for (s, &c) in class.iter().enumerate().rev() {
        rep[c as usize] = s as u32;
    }
    let mut new_id = vec![NONE; count];
    let mut order = Vec::with_capacity(count);
    if let Some(i) = acc.initial {
        new_id[class[i as usize] as usize] = 0;
        order.push(class[i as usize]);
    }
    let mut b = DfaBuilder::new(acc.alphabet.clone());
    let mut k = 0;
    while k < order.len() {
        let c = order[k];
        k += 1;
        let r = rep[c as usize];
        b.start_state(acc.marked[r as usize]);
        for (e, t) in acc.edges(r) {
            let tc = class[t as usize] as usize;
            if new_id[tc] == NONE {
                new_id[tc] = order.len() as u32;
                order.push(tc as u32);
            }
            b.push(e, new_id[tc]);
        }
    }
    let reps = order.iter().map(|&c| old[rep[c as usize] as usize]).collect();
    (b.finish(acc.initial.map(|_| 0)), reps)
}

/// The minimal automaton generating and marking the same languages as `a`.
///
/// Each state is named after one state of `a` it merges (the first in breadth-first order).
pub fn minimize(a: &Automaton) -> Result<Automaton, SynthError> {
    let inputs = Inputs::new(std::iter::once(a))?;
    let (m, reps) = minimize_dfa(&inputs.dfas[0]);
    Ok(m.to_automaton(&a.name, a.kind, &inputs.table, |s| a.states[reps[s as usize] as usize].name.clone()))
}
