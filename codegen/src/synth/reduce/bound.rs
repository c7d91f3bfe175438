//! A lower bound on the size of every reduced supervisor: states that are pairwise not control
//! consistent lie in different cells of every control cover, so a set of them — a clique of the
//! inconsistency graph — bounds the reduction from below (Su and Wonham's estimate, which TCT's
//! `supreduce` prints as `slb`).

use super::super::condat::ControlData;

/// Starts of the greedy clique search (the states with the most inconsistent partners first).
const STARTS: usize = 32;

/// A large set of pairwise inconsistent states of the `n` supervisor states (greedy: from each of the
/// [`STARTS`] states with the most inconsistent partners, add every state inconsistent with all chosen
/// so far, most partners first); the largest found.
pub(super) fn inconsistent_clique(data: &ControlData, n: usize) -> Vec<u32> {
    let mut degree = vec![0u32; n];
    for x in 0..n as u32 {
        for y in x + 1..n as u32 {
            if !data.consistent(x, y) {
                degree[x as usize] += 1;
                degree[y as usize] += 1;
            }
        }
    }
    let mut by_degree: Vec<u32> = (0..n as u32).filter(|&x| degree[x as usize] > 0).collect();
    by_degree.sort_by_key(|&x| (std::cmp::Reverse(degree[x as usize]), x));
    let mut best: Vec<u32> = (0..n.min(1) as u32).collect();
    for &start in by_degree.iter().take(STARTS) {
        let mut clique = vec![start];
        for &y in &by_degree {
            if clique.iter().all(|&x| !data.consistent(x, y)) {
                clique.push(y);
            }
        }
        if clique.len() > best.len() {
            best = clique;
        }
    }
    best
}
