//! The greedy control congruence of one state order: a partition of the supervisor's states whose
//! merges can be undone.

use crate::model::Dfa;

use super::super::condat::ControlData;

/// A partition of the supervisor states into cells, each named by one of its states.
pub(super) struct Partition {
    /// The cell of each state.
    pub(super) cell: Vec<u32>,
    /// The states of each cell (empty for a name no cell uses any more).
    pub(super) members: Vec<Vec<u32>>,
    /// The position (in the order being tried) of each cell's first state.
    first: Vec<u32>,
    /// (states moved, cell they came from, cell they went to, first position of the receiving cell
    /// before) for each merge since the last commit.
    log: Vec<(usize, u32, u32, u32)>,
}

impl Partition {
    /// Every state in a cell of its own; `position[x]` is state `x`'s place in the order tried.
    fn singletons(position: &[u32]) -> Self {
        let n = position.len() as u32;
        Partition {
            cell: (0..n).collect(),
            members: (0..n).map(|x| vec![x]).collect(),
            first: position.to_vec(),
            log: Vec::new(),
        }
    }

    /// The number of cells.
    pub(super) fn len(&self) -> usize {
        self.members.iter().filter(|m| !m.is_empty()).count()
    }

    /// Whether `x` comes first (in the order tried) in its cell.
    fn leads(&self, x: u32, position: &[u32]) -> bool {
        self.first[self.cell[x as usize] as usize] == position[x as usize]
    }

    fn merge(&mut self, a: u32, b: u32) {
        let (big, small) =
            if self.members[a as usize].len() >= self.members[b as usize].len() { (a, b) } else { (b, a) };
        let moved = std::mem::take(&mut self.members[small as usize]);
        for &x in &moved {
            self.cell[x as usize] = big;
        }
        let first = self.first[big as usize];
        self.first[big as usize] = first.min(self.first[small as usize]);
        self.log.push((moved.len(), small, big, first));
        self.members[big as usize].extend(moved);
    }

    fn undo(&mut self) {
        while let Some((count, small, big, first)) = self.log.pop() {
            let from = &mut self.members[big as usize];
            let moved = from.split_off(from.len() - count);
            for &x in &moved {
                self.cell[x as usize] = small;
            }
            self.members[small as usize] = moved;
            self.first[big as usize] = first;
        }
    }

    /// A state of cell `c` with a transition on `e`, and that transition's target.
    pub(super) fn successor(&self, sup: &Dfa, c: u32, e: u32) -> Option<u32> {
        self.members[c as usize].iter().find_map(|&x| sup.step(x, e))
    }

    /// Puts `i` and `j` in one cell with every merge that forces (cells with successors on one event
    /// must share the successors' cell); undoes everything when two states of a merged cell are not
    /// control consistent.
    fn try_merge(&mut self, sup: &Dfa, data: &ControlData, i: u32, j: u32) -> bool {
        let mut waiting = vec![(i, j)];
        while let Some((a, b)) = waiting.pop() {
            let (ca, cb) = (self.cell[a as usize], self.cell[b as usize]);
            if ca == cb {
                continue;
            }
            let ok = self.members[ca as usize]
                .iter()
                .all(|&x| self.members[cb as usize].iter().all(|&y| data.consistent(x, y)));
            if !ok {
                self.undo();
                return false;
            }
            for &e in &sup.alphabet {
                if let (Some(x), Some(y)) = (self.successor(sup, ca, e), self.successor(sup, cb, e)) {
                    waiting.push((x, y));
                }
            }
            self.merge(ca, cb);
        }
        self.log.clear();
        true
    }
}

/// The greedy control congruence for the state order `order` (a permutation of the states): each
/// state, in turn, first of its cell, is merged with each later state first of its own, keeping every
/// merge whose forced merges stay control consistent (Su and Wonham's procedure, TCT `supreduce`).
pub(super) fn greedy(sup: &Dfa, data: &ControlData, order: &[u32]) -> Partition {
    let mut position = vec![0u32; order.len()];
    for (k, &x) in order.iter().enumerate() {
        position[x as usize] = k as u32;
    }
    let mut p = Partition::singletons(&position);
    for (k, &i) in order.iter().enumerate() {
        if !p.leads(i, &position) {
            continue;
        }
        for &j in &order[k + 1..] {
            if p.cell[j as usize] != p.cell[i as usize] && p.leads(j, &position) {
                p.try_merge(sup, data, i, j);
            }
        }
    }
    p
}
