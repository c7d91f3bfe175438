//! The order of the components' state bits in the BDD variable order.
//!
//! A BDD stays small when variables that constrain each other sit close together. Components that share
//! events constrain each other (they move together), so the event graph — a component per vertex, an
//! edge between two components sharing an event — gives the order: a Cuthill–McKee walk of it (breadth
//! first from a component of least degree, neighbours by ascending degree) places each component next
//! to the ones it synchronises with. On the transfer line it gives `M1 B1 M2 B2 …` where the input order
//! is `M1 … Mn B1 … Bn-1`; `docs/symbolic.md` has the node counts of both.

use crate::model::Dfa;

/// How the components' bits are ordered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Order {
    /// In the order given (plants, then specifications).
    Given,
    /// By a Cuthill–McKee walk of the event graph (the default).
    #[default]
    EventGraph,
}

/// The components of `dfas` in variable order (a permutation of `0..dfas.len()`).
pub(crate) fn component_order(dfas: &[&Dfa], how: Order) -> Vec<usize> {
    let n = dfas.len();
    if how == Order::Given {
        return (0..n).collect();
    }
    let shares = |a: usize, b: usize| dfas[a].alphabet().iter().any(|&e| dfas[b].has_event(e));
    let neighbours: Vec<Vec<usize>> =
        (0..n).map(|a| (0..n).filter(|&b| b != a && shares(a, b)).collect()).collect();
    let degree = |a: usize| neighbours[a].len();
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    while order.len() < n {
        // A new component of the graph: start from its unplaced vertex of least degree.
        let Some(start) = (0..n).filter(|&a| !placed[a]).min_by_key(|&a| (degree(a), a)) else { break };
        placed[start] = true;
        let mut head = order.len();
        order.push(start);
        while head < order.len() {
            let mut next: Vec<usize> =
                neighbours[order[head]].iter().copied().filter(|&b| !placed[b]).collect();
            next.sort_by_key(|&b| (degree(b), b));
            for b in next {
                placed[b] = true;
                order.push(b);
            }
            head += 1;
        }
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::families::generate;
    use crate::synth::Inputs;

    #[test]
    fn the_transfer_line_interleaves_machines_and_buffers() {
        let inst = generate("transfer-line", 4).unwrap();
        let inputs = Inputs::new(inst.plants.iter().chain(&inst.specs)).unwrap();
        let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
        // Components: M1..M4 are 0..3, B1..B3 are 4..6.
        assert_eq!(component_order(&dfas, Order::EventGraph), [0, 4, 1, 5, 2, 6, 3]);
        assert_eq!(component_order(&dfas, Order::Given), [0, 1, 2, 3, 4, 5, 6]);
    }
}
