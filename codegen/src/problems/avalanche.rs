//! The avalanche effect: an event σ with p –σ→ q –σ→ r, p ≠ q and q ≠ r.
//!
//! A controller that runs every enabled transition of one scan in rung order would take both steps on one
//! occurrence of σ. Self-loops never count: taking one twice changes nothing.

use super::{paths::Paths, Finding, Problem, Shape};

/// One finding per avalanche event, at the nearest state where its double step starts.
pub fn find(paths: &Paths) -> Vec<Finding> {
    let a = paths.automaton();
    let mut found: Vec<Option<Finding>> = vec![None; a.events.len()];
    for &p in paths.order() {
        for &(e, q) in paths.out(p) {
            if q == p || found[e.index()].is_some() {
                continue;
            }
            if let Some(r) = paths.step(q, e).filter(|&r| r != q) {
                let name = &a.events[e.index()].name;
                found[e.index()] = Some(Finding {
                    problem: Problem::Avalanche,
                    state: a.states[p.index()].name.clone(),
                    events: vec![name.clone()],
                    trace: paths.trace(p),
                    shape: Shape::Chain,
                    detail: format!(
                        "{name} leads to {} and again to {}",
                        a.states[q.index()].name,
                        a.states[r.index()].name
                    ),
                });
            }
        }
    }
    found.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::{build, livelock};

    /// `seed/TEST.ADS`, transitions as in the file (odd labels controllable).
    fn seed() -> crate::model::Automaton {
        build(
            "TEST",
            &["0", "1", "2", "3", "4"],
            &["1", "3", "5"],
            &[
                ("0", "1", "1"),
                ("0", "2", "4"),
                ("1", "3", "3"),
                ("1", "2", "0"),
                ("1", "1", "2"),
                ("1", "5", "4"),
                ("2", "3", "1"),
                ("2", "1", "3"),
                ("3", "1", "2"),
                ("3", "6", "2"),
                ("4", "2", "2"),
                ("4", "6", "0"),
                ("3", "4", "0"),
            ],
        )
    }

    #[test]
    fn seed_has_avalanche_events_1_2_3() {
        let a = seed();
        let found = find(&Paths::new(&a));
        let events: Vec<_> = found.iter().map(|f| f.events[0].as_str()).collect();
        assert_eq!(events, ["1", "2", "3"]);
        assert_eq!(found[0].state, "0");
        assert_eq!(found[0].detail, "1 leads to 1 and again to 2");
        // Event 3: nearest start is state 1 (0 –1→ 1 –3→ 3 –… no 3), 2 –3→ 1 –3→ 3 from state 2.
        assert_eq!(found[2].state, "2");
        assert_eq!(found[2].trace, ["1", "1"]);
    }

    #[test]
    fn self_loops_never_count() {
        let a = build("L", &["0", "1"], &[], &[("0", "x", "0"), ("0", "y", "1"), ("1", "x", "1")]);
        assert!(find(&Paths::new(&a)).is_empty());
        // In the livelock example 1 –a→ 3 –a→ 4 and 3 –b→ 1 –b→ 2; u and v never repeat.
        let events: Vec<_> =
            find(&Paths::new(&livelock())).into_iter().map(|f| f.events[0].clone()).collect();
        assert_eq!(events, ["a", "b"]);
    }
}
