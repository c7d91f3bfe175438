//! The information-theoretic floor a table of one automaton can be compared with.
//!
//! An automaton with `s` states over an alphabet of `a` events with `t` transitions is one of
//! `C(s·a, t) · s^t` automata of that size: which `t` of the `s·a` (state, event) pairs have a
//! transition, and the target of each. Telling them apart takes `log₂ C(s·a, t) + t·log₂ s` bits, so no
//! layout that can hold every automaton of the size does with fewer for all of them; it is the yardstick
//! the report puts every layout next to. (A layout sized by `s`, `a` and `t` alone, as `compact`'s block
//! of an `a`-bit mask per state and a `⌈log₂ s⌉`-bit target per transition is, is never below it.)

use super::Member;

/// `log₂ C(n, k)`, the bits that choose `k` of `n` things.
fn log2_binomial(n: f64, k: f64) -> f64 {
    let k = k.min(n - k);
    (1..=k as u64).map(|i| ((n - k + i as f64) / i as f64).log2()).sum()
}

/// The floor of one automaton in bits.
pub fn bits(m: &Member) -> f64 {
    let (s, a, t) = (m.state_count() as f64, m.dfa.alphabet().len() as f64, m.transition_count() as f64);
    log2_binomial(s * a, t) + t * s.log2()
}

/// The floor of one automaton in whole bytes.
pub fn bytes(m: &Member) -> usize {
    (bits(m) / 8.0).ceil() as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::PackSet;

    #[test]
    fn toggle_floor() {
        // 2 states × 2 events, 2 transitions: C(4, 2) = 6 choices of the pairs, 2² targets: log₂ 24 bits.
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let m = &set.members()[0];
        assert!((bits(m) - 24f64.log2()).abs() < 1e-9);
        assert_eq!(bytes(m), 1);
    }

    proptest::proptest! {
        /// `compact`'s block (an alphabet-size mask per state, a target per transition) is never below
        /// the floor: a floor no layout beats is what the report compares with.
        #[test]
        fn compact_is_never_below_the_floor(a in crate::model::testing::arb_automaton("A".into(), 5, 9)) {
            let set = PackSet::new(vec![a], vec![]).unwrap();
            let packed = crate::pack::tables::encode(&set, crate::config::Layout::Compact).unwrap();
            let block_bits = 8 * packed.automata[0].block.len();
            proptest::prop_assert!(block_bits as f64 >= bits(&set.members()[0]) - 1e-9);
        }
    }

    /// The floor counts the automata of a size by brute force on small sizes: every choice of defined
    /// (state, event) pairs and of their targets.
    #[test]
    fn the_floor_is_the_log_of_the_number_of_automata_of_the_size() {
        for (s, a) in [(1u32, 1u32), (2, 2), (3, 2), (2, 3), (4, 2)] {
            let pairs = s * a;
            for t in 0..=pairs {
                let count: u64 =
                    (0u32..1 << pairs).filter(|m| m.count_ones() == t).map(|_| u64::from(s).pow(t)).sum();
                let floor =
                    log2_binomial(f64::from(pairs), f64::from(t)) + f64::from(t) * f64::from(s).log2();
                assert!((floor - (count as f64).log2()).abs() < 1e-9, "s={s} a={a} t={t}");
            }
        }
    }
}
