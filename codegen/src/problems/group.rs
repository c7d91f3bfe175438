//! Findings grouped for a reader: by kind and shape, then by event pair, with counts, witnesses, and the
//! order in which a user acts on them.
//!
//! A concurrent closed loop has thousands of findings (the cell: 5 121), nearly all of a few kinds and a
//! few event pairs. Grouping keeps every fact (each group holds its findings' indices) while a report
//! prints one line per group, the groups that can change where the loop goes first.

use std::collections::{BTreeMap, BTreeSet};

use super::{Finding, Problem, Shape};

/// What a group of findings asks of the user: the order reports list them in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Concern {
    /// Can change the closed loop's behaviour and nothing at run time answers it: an avalanche (a scan
    /// cycle takes two steps on one occurrence), or two inputs whose order matters, which a scan that
    /// reads both cannot recover (simultaneity, `diverging` or `one-order`).
    Act,
    /// Changes behaviour only through a decision the runtime makes on purpose: which of two commands
    /// (choice: the choice policy) and a command racing an input (inexact synchronisation: the guard).
    Runtime,
    /// Provably harmless while the plant model holds: two inputs of which the loop allows neither after
    /// the other (simultaneity, `exclusive`), so per the model they never both happen.
    Harmless,
}

impl Concern {
    /// Every concern, in report order.
    pub const ALL: [Concern; 3] = [Concern::Act, Concern::Runtime, Concern::Harmless];

    /// The concern of a finding of `problem` in `shape`.
    pub fn of(problem: Problem, shape: Shape) -> Concern {
        match (problem, shape) {
            (Problem::Avalanche, _) => Concern::Act,
            (Problem::Simultaneity, Shape::Exclusive) => Concern::Harmless,
            (Problem::Simultaneity, _) => Concern::Act,
            (Problem::Choice | Problem::InexactSynchronisation, _) => Concern::Runtime,
        }
    }

    /// The name JSON carries.
    pub fn name(self) -> &'static str {
        match self {
            Concern::Act => "act",
            Concern::Runtime => "runtime",
            Concern::Harmless => "harmless",
        }
    }

    /// The heading a text report gives the groups of this concern.
    pub fn heading(self) -> &'static str {
        match self {
            Concern::Act => "act on first (can change where the loop goes; nothing at run time answers it)",
            Concern::Runtime => "answered at run time",
            Concern::Harmless => "harmless while the plant model holds",
        }
    }
}

/// The findings of one kind and one shape.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    /// The kind.
    pub problem: Problem,
    /// The shape.
    pub shape: Shape,
    /// What the group asks of the user.
    pub concern: Concern,
    /// Indices of the group's findings in the slice grouped, nearest state first.
    pub findings: Vec<usize>,
    /// How many distinct states the findings are at.
    pub states: usize,
    /// The event sets (one event for avalanche, a pair otherwise) with their number of findings, most
    /// findings first, then by name.
    pub events: Vec<(Vec<String>, usize)>,
}

impl Group {
    /// Up to two findings at different states that show the group, nearest first (indices as in
    /// [`Group::findings`]).
    pub fn witnesses(&self, found: &[Finding]) -> Vec<usize> {
        let mut out: Vec<usize> = Vec::new();
        for &i in &self.findings {
            if out.iter().all(|&w| found[w].state != found[i].state) {
                out.push(i);
            }
            if out.len() == 2 {
                break;
            }
        }
        out
    }
}

/// A group's place in a report, [`rank`]'s: concern, kind, shape.
type Rank = (Concern, u8, u8);

/// Where a group stands in a report: by concern, then the kind's own order of urgency (an avalanche
/// before a simultaneity; an inexact synchronisation, which desynchronises controller and plant, before
/// a choice), then the shape that changes most first (`diverging`, `one-order`, `exclusive`).
fn rank(problem: Problem, shape: Shape) -> Rank {
    let kind = match problem {
        Problem::Avalanche => 0,
        Problem::Simultaneity => 1,
        Problem::InexactSynchronisation => 2,
        Problem::Choice => 3,
    };
    let change = match shape {
        Shape::Chain | Shape::Diverging => 0,
        Shape::OneOrder => 1,
        Shape::Exclusive => 2,
    };
    (Concern::of(problem, shape), kind, change)
}

/// Groups `found` by kind and shape, most urgent group first; every finding is in exactly one group.
pub fn group(found: &[Finding]) -> Vec<Group> {
    let mut by: BTreeMap<Rank, Vec<usize>> = BTreeMap::new();
    for (i, f) in found.iter().enumerate() {
        by.entry(rank(f.problem, f.shape)).or_default().push(i);
    }
    by.into_iter()
        .map(|((concern, _, _), findings)| {
            // Every group has a first finding; its kind and shape are the group's.
            let (problem, shape) = (found[findings[0]].problem, found[findings[0]].shape);
            let states: BTreeSet<&str> = findings.iter().map(|&i| found[i].state.as_str()).collect();
            let mut count: BTreeMap<&[String], usize> = BTreeMap::new();
            for &i in &findings {
                *count.entry(found[i].events.as_slice()).or_default() += 1;
            }
            let mut events: Vec<(Vec<String>, usize)> =
                count.into_iter().map(|(e, n)| (e.to_vec(), n)).collect();
            events.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
            Group { problem, shape, concern, findings, states: states.len(), events }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finding(problem: Problem, shape: Shape, state: &str, events: &[&str]) -> Finding {
        Finding {
            problem,
            state: state.to_owned(),
            events: events.iter().map(|e| (*e).to_owned()).collect(),
            trace: Vec::new(),
            shape,
            detail: String::new(),
        }
    }

    #[test]
    fn groups_keep_every_finding_and_put_what_changes_the_loop_first() {
        let found = vec![
            finding(Problem::Choice, Shape::Exclusive, "0", &["a", "b"]),
            finding(Problem::Simultaneity, Shape::Exclusive, "0", &["u", "v"]),
            finding(Problem::Simultaneity, Shape::Exclusive, "1", &["u", "v"]),
            finding(Problem::Simultaneity, Shape::Exclusive, "1", &["u", "w"]),
            finding(Problem::InexactSynchronisation, Shape::OneOrder, "2", &["a", "u"]),
            finding(Problem::Simultaneity, Shape::Diverging, "3", &["v", "w"]),
            finding(Problem::Avalanche, Shape::Chain, "1", &["a"]),
        ];
        let groups = group(&found);
        let order: Vec<_> = groups.iter().map(|g| (g.concern, g.problem, g.shape)).collect();
        assert_eq!(
            order,
            [
                (Concern::Act, Problem::Avalanche, Shape::Chain),
                (Concern::Act, Problem::Simultaneity, Shape::Diverging),
                (Concern::Runtime, Problem::InexactSynchronisation, Shape::OneOrder),
                (Concern::Runtime, Problem::Choice, Shape::Exclusive),
                (Concern::Harmless, Problem::Simultaneity, Shape::Exclusive),
            ]
        );
        let mut all: Vec<usize> = groups.iter().flat_map(|g| g.findings.clone()).collect();
        all.sort_unstable();
        assert_eq!(all, (0..found.len()).collect::<Vec<_>>());
        let exclusive = &groups[4];
        assert_eq!((exclusive.findings.len(), exclusive.states), (3, 2));
        assert_eq!(
            exclusive.events,
            [(vec!["u".to_owned(), "v".to_owned()], 2), (vec!["u".into(), "w".into()], 1)]
        );
        // Two witnesses at different states, nearest first.
        assert_eq!(exclusive.witnesses(&found), [1, 2]);
    }

    #[test]
    fn one_order_simultaneity_is_acted_on_and_exclusive_choice_is_answered_at_run_time() {
        assert_eq!(Concern::of(Problem::Simultaneity, Shape::OneOrder), Concern::Act);
        assert_eq!(Concern::of(Problem::Choice, Shape::Exclusive), Concern::Runtime);
        assert_eq!(Concern::of(Problem::InexactSynchronisation, Shape::Exclusive), Concern::Runtime);
    }
}
