//! F_σ as a two-level formula: the union of its states' cubes, minimised on binary decision diagrams
//! (`biodivine-lib-bdd`).
//!
//! The function must be TRUE on ON (the valuations of the states where f_σ = 1), FALSE on OFF (those
//! of the other reachable states) and is free elsewhere — valuations no reachable state produces, the
//! only don't-cares (none with `exact`). The crate's optimised DNF of ON gives a cover; each cube is then
//! expanded to a prime within ON ∪ don't-cares (a literal dropped while the cube stays inside) and the
//! cover made irredundant (a cube dropped while the others still cover ON), every test a BDD
//! implication. The result is a prime and irredundant sum of products between ON and ON ∪ DC.

use biodivine_lib_bdd::{Bdd, BddPartialValuation, BddVariable, BddVariableSet};

use crate::config::Cube;

/// A BDD universe over `n` signals.
pub struct Universe {
    vars: BddVariableSet,
    n: usize,
}

impl Universe {
    /// Signals `0..n` (n ≤ 64).
    pub fn new(n: usize) -> Universe {
        Universe { vars: BddVariableSet::new_anonymous(n as u16), n }
    }

    fn cube(&self, c: Cube) -> Bdd {
        let values: Vec<(BddVariable, bool)> =
            c.literals().filter(|&(i, _)| i < self.n).map(|(i, v)| (BddVariable::from_index(i), v)).collect();
        self.vars.mk_conjunctive_clause(&BddPartialValuation::from_values(&values))
    }

    /// The union of `cubes`.
    pub fn union(&self, cubes: &[Cube]) -> Bdd {
        cubes.iter().fold(self.vars.mk_false(), |acc, &c| acc.or(&self.cube(c)))
    }

    /// A prime, irredundant cover `F` with `on ⊆ F ⊆ on ∪ dc`.
    pub fn minimise(&self, on: &Bdd, dc: &Bdd) -> Vec<Cube> {
        let upper = on.or(dc);
        let mut cover: Vec<Cube> = on
            .to_optimized_dnf()
            .iter()
            .map(|p| {
                p.to_values().into_iter().fold(Cube::default(), |c, (v, b)| Cube {
                    mask: c.mask | 1 << v.to_index(),
                    value: c.value | u64::from(b) << v.to_index(),
                })
            })
            .collect();
        // Expand: drop every literal the cube can lose and stay inside the upper bound.
        for c in &mut cover {
            for (i, _) in c.literals().collect::<Vec<_>>() {
                let wider = Cube { mask: c.mask & !(1 << i), value: c.value & !(1 << i) };
                if self.cube(wider).and_not(&upper).is_false() {
                    *c = wider;
                }
            }
        }
        cover.sort_by_key(|c| (c.len(), c.mask, c.value));
        cover.dedup();
        // Irredundant: drop a cube (largest first) whose part of ON the others cover.
        let mut i = cover.len();
        while i > 0 {
            i -= 1;
            let others: Vec<Cube> =
                cover.iter().enumerate().filter(|&(j, _)| j != i).map(|(_, &c)| c).collect();
            if on.and(&self.cube(cover[i])).and_not(&self.union(&others)).is_false() {
                cover.remove(i);
            }
        }
        cover
    }

    /// Whether `f` (a sum of `cubes`) is TRUE exactly on ON and FALSE on OFF: ON ⊆ F and F ∧ OFF = ∅.
    pub fn separates(&self, cubes: &[Cube], on: &Bdd, off: &Bdd) -> bool {
        let f = self.union(cubes);
        on.and_not(&f).is_false() && f.and(off).is_false()
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn holds(cover: &[Cube], v: u64) -> bool {
        cover.iter().any(|c| c.holds(v))
    }

    proptest! {
        /// Against brute force over 5 signals: every minterm of ON is covered, none of OFF is, every
        /// cube is prime (no literal can go) and none is redundant.
        #[test]
        fn covers_are_exact_prime_and_irredundant(on_bits in any::<u32>(), dc_bits in any::<u32>()) {
            let u = Universe::new(5);
            let dc_bits = dc_bits & !on_bits;
            let minterms = |bits: u32| -> Vec<Cube> {
                (0..32).filter(|m| bits >> m & 1 == 1).map(|m| Cube { mask: 0b11111, value: m }).collect()
            };
            let (on, dc) = (u.union(&minterms(on_bits)), u.union(&minterms(dc_bits)));
            let cover = u.minimise(&on, &dc);
            for m in 0..32u64 {
                let want = if on_bits >> m & 1 == 1 { Some(true) } else if dc_bits >> m & 1 == 1 { None } else { Some(false) };
                if let Some(w) = want {
                    prop_assert_eq!(holds(&cover, m), w, "minterm {:05b} of {:?}", m, cover);
                }
            }
            let allowed = |v: u64| (on_bits | dc_bits) >> v & 1 == 1;
            for (k, c) in cover.iter().enumerate() {
                for (i, _) in c.literals() {
                    let wider = Cube { mask: c.mask & !(1 << i), value: c.value & !(1 << i) };
                    prop_assert!((0..32).any(|v| wider.holds(v) && !allowed(v)), "{:?} not prime", c);
                }
                let rest: Vec<Cube> = cover.iter().enumerate().filter(|&(j, _)| j != k).map(|(_, &c)| c).collect();
                prop_assert!((0..32).any(|v| on_bits >> v & 1 == 1 && c.holds(v) && !holds(&rest, v)), "{:?} redundant", c);
            }
        }
    }
}
