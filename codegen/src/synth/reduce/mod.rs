//! Supervisor reduction after Su and Wonham (the control congruence behind TCT `supreduce`).
//!
//! Only the supervisor's *control action* matters: which controllable events it disables where the plant
//! would allow them, and which closed-loop states it marks. For each supervisor state `x`, with the plant
//! `G`, let `E(x)` be the events `x` enables, `D(x)` the events it disables while the plant (in some state
//! reached together with `x`) enables them or lacks them altogether, `M(x)` whether `x` is marked and `T(x)`
//! whether `x` is reached together with a marked plant state. States `x`, `y` are *control consistent*
//! when `E(x) ∩ D(y) = E(y) ∩ D(x) = ∅` and `T(x) = T(y) ⇒ M(x) = M(y)`. A partition into cells of
//! pairwise consistent states, whose cells each map under every event into one cell, is a control
//! congruence; the quotient automaton gives the same closed loop with the plant.
//!
//! Finding the smallest congruence is NP-hard. The greedy procedure ([`partition::greedy`]) merges each
//! state with every later one in a state order, following each merge through the successors it forces
//! and undoing it when a forced pair is inconsistent; its result depends on the order. So the reduction
//! here runs it in several orders — the supervisor's own (breadth-first), depth-first, reversed, the
//! states of the lower bound's clique first, and [`SHUFFLES`] fixed pseudo-random ones — keeps the
//! smallest quotient, and reduces that quotient again (its control data are narrower) until a round
//! gains nothing or the size meets the lower bound ([`bound`]). The result is never larger than the
//! greedy procedure's in the supervisor's own order (TCT's on the same supervisor), and is
//! deterministic.

mod bound;
mod partition;

use crate::model::{Automaton, Dfa, DfaBuilder, NONE};

use super::condat::ControlData;
use super::{Config, Inputs, SynthError};
use partition::Partition;

/// Pseudo-random state orders tried besides the fixed ones.
const SHUFFLES: u64 = 8;

/// A reduced supervisor and what bounds it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reduction {
    /// The reduced supervisor; each state named after the first supervisor state it merges.
    pub automaton: Automaton,
    /// No supervisor with the same closed loop built from the original's control data has fewer
    /// states: the size of a set of pairwise control-inconsistent states (TCT's `slb`).
    pub lower_bound: usize,
}

/// The quotient of `sup` by `p`, cells numbered by their first state, and that state of each cell.
fn quotient(sup: &Dfa, data: &ControlData, p: &Partition) -> (Dfa, Vec<u32>) {
    let n = sup.state_count();
    let mut number = vec![NONE; n];
    let mut firsts = Vec::new();
    for x in 0..n {
        let c = p.cell[x] as usize;
        if number[c] == NONE {
            number[c] = firsts.len() as u32;
            firsts.push(x as u32);
        }
    }
    let mut b = DfaBuilder::new(sup.alphabet.clone());
    for &f in &firsts {
        let c = p.cell[f as usize];
        let members = &p.members[c as usize];
        let marked = members.iter().any(|&x| data.marked[x as usize] && data.plant_marked[x as usize])
            || members.iter().all(|&x| !data.plant_marked[x as usize])
                && members.iter().any(|&x| data.marked[x as usize]);
        b.start_state(marked);
        for &e in &sup.alphabet {
            if let Some(t) = p.successor(sup, c, e) {
                b.push(e, number[p.cell[t as usize] as usize]);
            }
        }
    }
    let initial = sup.initial.map(|i| number[p.cell[i as usize] as usize]);
    (b.finish(initial), firsts)
}

/// The state orders the greedy procedure is run in (each a permutation of the states).
fn orders(sup: &Dfa, clique: &[u32]) -> Vec<Vec<u32>> {
    let n = sup.state_count() as u32;
    let own: Vec<u32> = (0..n).collect();
    let mut clique_first = clique.to_vec();
    let mut in_clique = vec![false; n as usize];
    clique.iter().for_each(|&x| in_clique[x as usize] = true);
    clique_first.extend(own.iter().copied().filter(|&x| !in_clique[x as usize]));
    let mut orders = vec![own.clone(), depth_first(sup), own.iter().rev().copied().collect(), clique_first];
    for seed in 1..=SHUFFLES {
        let mut o = own.clone();
        o.sort_by_key(|&x| mix(seed << 32 | u64::from(x)));
        orders.push(o);
    }
    orders
}

/// The states in depth-first preorder from the initial state (events ascending), then the rest.
fn depth_first(sup: &Dfa) -> Vec<u32> {
    let n = sup.state_count();
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut stack: Vec<u32> = sup.initial.into_iter().collect();
    while let Some(s) = stack.pop() {
        if std::mem::replace(&mut seen[s as usize], true) {
            continue;
        }
        order.push(s);
        let next: Vec<u32> = sup.edges(s).map(|(_, t)| t).filter(|&t| !seen[t as usize]).collect();
        stack.extend(next.into_iter().rev());
    }
    order.extend((0..n as u32).filter(|&x| !seen[x as usize]));
    order
}

/// A well-mixed 64-bit hash (splitmix64's finaliser), for the fixed pseudo-random orders.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The reduced supervisor, for each of its states the supervisor state it is named after, and the
/// lower bound.
fn reduce_dfa(
    plants: &[&Dfa],
    sup: &Dfa,
    inputs: &Inputs,
    cfg: &Config,
) -> Result<(Dfa, Vec<u32>, usize), SynthError> {
    let mut current = sup.clone();
    let mut names: Vec<u32> = (0..sup.state_count() as u32).collect();
    let mut data = ControlData::new(plants, &current, inputs, cfg)?;
    let bound = bound::inconsistent_clique(&data, current.state_count()).len();
    loop {
        let clique = bound::inconsistent_clique(&data, current.state_count());
        let mut best: Option<Partition> = None;
        for order in orders(&current, &clique) {
            let p = partition::greedy(&current, &data, &order);
            if best.as_ref().is_none_or(|b| p.len() < b.len()) {
                let done = p.len() <= bound;
                best = Some(p);
                if done {
                    break;
                }
            }
        }
        let Some(best) = best.filter(|b| b.len() < current.state_count()) else { break };
        let (q, firsts) = quotient(&current, &data, &best);
        names = firsts.iter().map(|&f| names[f as usize]).collect();
        current = q;
        if current.state_count() <= bound {
            break;
        }
        data = ControlData::new(plants, &current, inputs, cfg)?;
    }
    Ok((current, names, bound))
}

/// Reduces `supervisor` with respect to the plant `‖ plants`: a supervisor with (usually far) fewer
/// states whose closed loop with the plant generates and marks the same languages, and the lower bound
/// on any such reduction.
pub fn reduction(
    plants: &[Automaton],
    supervisor: &Automaton,
    cfg: &Config,
) -> Result<Reduction, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(std::iter::once(supervisor)))?;
    let (p, s) = inputs.dfas.split_at(plants.len());
    let (r, names, lower_bound) = reduce_dfa(&p.iter().collect::<Vec<_>>(), &s[0], &inputs, cfg)?;
    let automaton = r.to_automaton(&supervisor.name, supervisor.kind, &inputs.table, |q| {
        supervisor.states[names[q as usize] as usize].name.clone()
    });
    Ok(Reduction { automaton, lower_bound })
}

/// [`reduction`]'s supervisor alone.
pub fn reduce(plants: &[Automaton], supervisor: &Automaton, cfg: &Config) -> Result<Automaton, SynthError> {
    reduction(plants, supervisor, cfg).map(|r| r.automaton)
}
