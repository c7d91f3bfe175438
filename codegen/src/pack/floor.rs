//! The information-theoretic floor a table of one automaton can be compared with.
//!
//! An automaton with `s` states, an alphabet of `a` events and `t` transitions is, as a table, `t` pairs
//! (event, target) plus how many pairs each state has: `t·(log₂ a + log₂ s) + s·log₂(a + 1)` bits. No
//! layout that stores transitions one by one can do with less without exploiting structure; it is the
//! yardstick the report puts every layout next to.

use super::Member;

/// The floor of one automaton in bits.
pub fn bits(m: &Member) -> f64 {
    let (s, a, t) = (m.state_count() as f64, m.dfa.alphabet().len() as f64, m.transition_count() as f64);
    let per_transition = if t > 0.0 { t * (a.log2() + s.log2()) } else { 0.0 };
    per_transition + s * (a + 1.0).log2()
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
        // 2 transitions × (1 + 1) bits + 2 states × log₂ 3 bits = 7.17 bits: one byte.
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let m = &set.members()[0];
        assert!((bits(m) - (4.0 + 2.0 * 3f64.log2())).abs() < 1e-9);
        assert_eq!(bytes(m), 1);
    }
}
