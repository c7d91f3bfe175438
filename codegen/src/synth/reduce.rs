//! Supervisor reduction after Su and Wonham (the control congruence behind TCT `supreduce`).
//!
//! Only the supervisor's *control action* matters: which controllable events it disables where the plant
//! would allow them, and which closed-loop states it marks. For each supervisor state `x`, with the plant
//! `G`, let `E(x)` be the events `x` enables, `D(x)` the events it disables while the plant (in some state
//! reached together with `x`) enables them or lacks them altogether, `M(x)` whether `x` is marked and `T(x)` whether
//! `x` is reached together with a marked plant state. States `x`, `y` are *control consistent* when
//! `E(x) ∩ D(y) = E(y) ∩ D(x) = ∅` and `T(x) = T(y) ⇒ M(x) = M(y)`. A partition into cells of pairwise
//! consistent states, whose cells each map under every event into one cell, is a control congruence; the
//! quotient automaton gives the same closed loop with the plant. The greedy search tries to merge each state
//! with every later one (in state order), following the merge through the successors it forces and undoing
//! it when some forced pair is inconsistent. The result depends on that order, as TCT's does; it is
//! usually much smaller but not guaranteed minimal.

use crate::model::Automaton;

use super::condat::ControlData;
use super::{Config, Inputs, SynthError};
use crate::model::{Dfa, DfaBuilder, NONE};

/// A partition of the supervisor states with undoable merges.
struct Partition {
    cell: Vec<u32>,
    members: Vec<Vec<u32>>,
    /// (states moved, cell they came from, cell they went to) of the merges since the last commit.
    log: Vec<(usize, u32, u32)>,
}

impl Partition {
    fn merge(&mut self, a: u32, b: u32) {
        let (big, small) =
            if self.members[a as usize].len() >= self.members[b as usize].len() { (a, b) } else { (b, a) };
        let moved = std::mem::take(&mut self.members[small as usize]);
        for &x in &moved {
            self.cell[x as usize] = big;
        }
        self.log.push((moved.len(), small, big));
        self.members[big as usize].extend(moved);
    }

    fn undo(&mut self) {
        while let Some((count, small, big)) = self.log.pop() {
            let from = &mut self.members[big as usize];
            let moved = from.split_off(from.len() - count);
            for &x in &moved {
                self.cell[x as usize] = small;
            }
            self.members[small as usize] = moved;
        }
    }
}

/// A state of cell `c` with a transition on `e`, and that transition's target.
fn successor(sup: &Dfa, p: &Partition, c: u32, e: u32) -> Option<u32> {
    p.members[c as usize].iter().find_map(|&x| sup.step(x, e))
}

/// Tries to put `i` and `j` in one cell, with every merge that forces; undoes everything on a clash.
fn try_merge(sup: &Dfa, data: &ControlData, p: &mut Partition, i: u32, j: u32) -> bool {
    let mut waiting = vec![(i, j)];
    while let Some((a, b)) = waiting.pop() {
        let (ca, cb) = (p.cell[a as usize], p.cell[b as usize]);
        if ca == cb {
            continue;
        }
        let ok = p.members[ca as usize]
            .iter()
            .all(|&x| p.members[cb as usize].iter().all(|&y| data.consistent(x, y)));
        if !ok {
            p.undo();
            return false;
        }
        let forced: Vec<(u32, u32)> = sup
            .alphabet
            .iter()
            .filter_map(|&e| Some((successor(sup, p, ca, e)?, successor(sup, p, cb, e)?)))
            .collect();
        p.merge(ca, cb);
        waiting.extend(forced);
    }
    p.log.clear();
    true
}

/// The reduced supervisor (quotient of `sup` by the greedy control congruence) and, for each of its
/// states, the smallest supervisor state it holds.
pub(crate) fn reduce_dfa(
    plants: &[&Dfa],
    sup: &Dfa,
    inputs: &Inputs,
    cfg: &Config,
) -> Result<(Dfa, Vec<u32>), SynthError> {
    let data = ControlData::new(plants, sup, inputs, cfg)?;
    let n = sup.state_count();
    let mut p = Partition {
        cell: (0..n as u32).collect(),
        members: (0..n as u32).map(|x| vec![x]).collect(),
        log: Vec::new(),
    };
    for i in 0..n as u32 {
        if p.members[p.cell[i as usize] as usize].iter().any(|&x| x < i) {
            continue;
        }
        for j in i + 1..n as u32 {
            let cj = p.cell[j as usize];
            if cj == p.cell[i as usize] || p.members[cj as usize].iter().any(|&x| x < j) {
                continue;
            }
            try_merge(sup, &data, &mut p, i, j);
        }
    }
    // Cells numbered by their smallest state.
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
        let members = &p.members[p.cell[f as usize] as usize];
        let marked = members.iter().any(|&x| data.marked[x as usize] && data.plant_marked[x as usize])
            || members.iter().all(|&x| !data.plant_marked[x as usize])
                && members.iter().any(|&x| data.marked[x as usize]);
        b.start_state(marked);
        for &e in &sup.alphabet {
            if let Some(t) = successor(sup, &p, p.cell[f as usize], e) {
                b.push(e, number[p.cell[t as usize] as usize]);
            }
        }
    }
    let initial = sup.initial.map(|i| number[p.cell[i as usize] as usize]);
    Ok((b.finish(initial), firsts))
}

/// Reduces `supervisor` with respect to the plant `‖ plants`: a supervisor with (usually far) fewer
/// states whose closed loop with the plant generates and marks the same languages.
///
/// Each state of the result is named after the first supervisor state it merges.
pub fn reduce(plants: &[Automaton], supervisor: &Automaton, cfg: &Config) -> Result<Automaton, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(std::iter::once(supervisor)))?;
    let (p, s) = inputs.dfas.split_at(plants.len());
    let (r, firsts) = reduce_dfa(&p.iter().collect::<Vec<_>>(), &s[0], &inputs, cfg)?;
    Ok(r.to_automaton(&supervisor.name, supervisor.kind, &inputs.table, |q| {
        supervisor.states[firsts[q as usize] as usize].name.clone()
    }))
}
