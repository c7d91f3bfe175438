//! Choice, inexact synchronisation and simultaneity: the same diamond, on different pairs of events.
//!
//! At a state where events x and y are both enabled, x·y and y·x must both be defined and reach the same
//! state; otherwise the order the runtime takes them in changes where the loop goes. The pair decides the
//! problem: two controllable events are a *choice* (confluence), a controllable and an uncontrollable
//! one an *inexact synchronisation* (delay insensitivity), two uncontrollable ones a *simultaneity*
//! (interleave insensitivity).

use super::{paths::Paths, Finding, Problem, Shape};
use crate::model::{EventId, StateId};

/// Every state and pair of the kinds in `problems` where the diamond does not close, nearest state first,
/// pairs in event order.
pub fn find(paths: &Paths, problems: &[Problem]) -> Vec<Finding> {
    let a = paths.automaton();
    let mut found = Vec::new();
    for &s in paths.order() {
        let out = paths.out(s);
        for (i, &(x, _)) in out.iter().enumerate() {
            for &(y, _) in &out[i + 1..] {
                let problem = match (a.events[x.index()].controllable, a.events[y.index()].controllable) {
                    (true, true) => Problem::Choice,
                    (false, false) => Problem::Simultaneity,
                    _ => Problem::InexactSynchronisation,
                };
                if !problems.contains(&problem) {
                    continue;
                }
                if let Some((shape, detail)) = open(paths, s, x, y) {
                    found.push(Finding {
                        problem,
                        state: a.states[s.index()].name.clone(),
                        events: vec![a.events[x.index()].name.clone(), a.events[y.index()].name.clone()],
                        trace: paths.trace(s),
                        shape,
                        detail,
                    });
                }
            }
        }
    }
    found
}

/// How and why the diamond x·y / y·x at `s` does not close, or `None` when it does.
fn open(paths: &Paths, s: StateId, x: EventId, y: EventId) -> Option<(Shape, String)> {
    let a = paths.automaton();
    let both = |first, second| paths.step(s, first).and_then(|m| paths.step(m, second));
    let name = |e: EventId| &a.events[e.index()].name;
    let state = |r: Option<StateId>| match r {
        Some(r) => format!("reaches {}", a.states[r.index()].name),
        None => "is undefined".to_owned(),
    };
    let (xy, yx) = (both(x, y), both(y, x));
    let shape = match (xy, yx) {
        (Some(p), Some(q)) if p == q => return None,
        (Some(_), Some(_)) => Shape::Diverging,
        (None, None) => Shape::Exclusive,
        _ => Shape::OneOrder,
    };
    Some((shape, format!("{}·{} {}, {}·{} {}", name(x), name(y), state(xy), name(y), name(x), state(yx))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::{build, livelock};

    #[test]
    fn livelock_has_choice_problems_at_1_and_3() {
        let a = livelock();
        let found = find(&Paths::new(&a), &Problem::ALL);
        let at: Vec<_> = found.iter().map(|f| (f.problem, f.state.as_str())).collect();
        assert_eq!(at, [(Problem::Choice, "1"), (Problem::Choice, "3")]);
        assert_eq!(found[0].detail, "a·b reaches 1, b·a is undefined");
        assert_eq!(found[1].detail, "a·b is undefined, b·a reaches 3");
        assert_eq!(found[1].trace, ["a"]);
        assert!(found.iter().all(|f| f.shape == Shape::OneOrder));
    }

    #[test]
    fn commuting_pairs_are_silent_and_kinds_follow_controllability() {
        // A 2×2 grid of c (controllable) and u: the diamond closes.
        let grid = build(
            "grid",
            &["00", "10", "01", "11"],
            &["c"],
            &[("00", "c", "10"), ("00", "u", "01"), ("10", "u", "11"), ("01", "c", "11")],
        );
        assert!(find(&Paths::new(&grid), &Problem::ALL).is_empty());
        // Break one side: u·c goes elsewhere.
        let broken = build(
            "broken",
            &["00", "10", "01", "11", "x"],
            &["c"],
            &[("00", "c", "10"), ("00", "u", "01"), ("10", "u", "11"), ("01", "c", "x")],
        );
        let found = find(&Paths::new(&broken), &Problem::ALL);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].problem, Problem::InexactSynchronisation);
        assert_eq!(found[0].shape, Shape::Diverging);
        assert!(find(&Paths::new(&broken), &[Problem::Choice]).is_empty());
    }
}
