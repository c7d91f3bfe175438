//! Equality and inclusion of generated and marked languages, with a shortest counterexample.
//!
//! Both automata are walked together over pairs of states (a side without the transition drops out),
//! breadth-first, so the first disagreement found is a shortest string on which the languages differ.

use std::collections::HashMap;

use crate::model::{Automaton, EventId};

use super::{Inputs, SynthError};
use crate::model::{Dfa, NONE};

/// How two languages differ on [`Difference::trace`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DifferenceKind {
    /// The first automaton generates the string, the second does not.
    GeneratedOnlyByFirst,
    /// The second automaton generates the string, the first does not.
    GeneratedOnlyBySecond,
    /// Both generate the string; only the first marks it.
    MarkedOnlyByFirst,
    /// Both generate the string; only the second marks it.
    MarkedOnlyBySecond,
}

/// A shortest string on which two automata disagree.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Difference {
    /// The string, as event names.
    pub trace: Vec<String>,
    /// Which side generates or marks it.
    pub kind: DifferenceKind,
}

/// Whether only the inclusion of the first language in the second is asked.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Relation {
    Equal,
    Included,
}

fn walk(a: &Dfa, b: &Dfa, relation: Relation) -> Option<(Vec<u32>, DifferenceKind)> {
    let start = (a.initial.unwrap_or(NONE), b.initial.unwrap_or(NONE));
    let mut pairs = vec![start];
    let mut parent: Vec<(u32, u32)> = vec![(NONE, NONE)];
    let mut index: HashMap<(u32, u32), u32> = HashMap::from([(start, 0)]);
    let mut k = 0;
    while k < pairs.len() {
        let (x, y) = pairs[k];
        let verdict = match (x == NONE, y == NONE) {
            (false, true) => Some(DifferenceKind::GeneratedOnlyByFirst),
            (true, false) if relation == Relation::Equal => Some(DifferenceKind::GeneratedOnlyBySecond),
            (false, false) => match (a.marked[x as usize], b.marked[y as usize]) {
                (true, false) => Some(DifferenceKind::MarkedOnlyByFirst),
                (false, true) if relation == Relation::Equal => Some(DifferenceKind::MarkedOnlyBySecond),
                _ => None,
            },
            _ => None,
        };
        if let Some(kind) = verdict {
            let mut trace = Vec::new();
            let mut i = k;
            while parent[i].0 != NONE {
                trace.push(parent[i].1);
                i = parent[i].0 as usize;
            }
            trace.reverse();
            return Some((trace, kind));
        }
        if x != NONE && y != NONE {
            let mut ea = a.edges(x).peekable();
            let mut eb = b.edges(y).peekable();
            loop {
                let (e, tx, ty) = match (ea.peek().copied(), eb.peek().copied()) {
                    (None, None) => break,
                    (Some((e, t)), None) => {
                        ea.next();
                        (e, t, NONE)
                    }
                    (None, Some((e, t))) => {
                        eb.next();
                        (e, NONE, t)
                    }
                    (Some((e1, t1)), Some((e2, t2))) => {
                        if e1 < e2 {
                            ea.next();
                            (e1, t1, NONE)
                        } else if e2 < e1 {
                            eb.next();
                            (e2, NONE, t2)
                        } else {
                            ea.next();
                            eb.next();
                            (e1, t1, t2)
                        }
                    }
                };
                let fresh = pairs.len() as u32;
                if *index.entry((tx, ty)).or_insert(fresh) == fresh {
                    pairs.push((tx, ty));
                    parent.push((k as u32, e));
                }
            }
        }
        k += 1;
    }
    None
}

fn compare(a: &Automaton, b: &Automaton, relation: Relation) -> Result<Option<Difference>, SynthError> {
    let inputs = Inputs::new([a, b].into_iter())?;
    Ok(walk(&inputs.dfas[0], &inputs.dfas[1], relation).map(|(trace, kind)| Difference {
        trace: trace.iter().map(|&e| inputs.table.name(EventId::from_u32(e)).to_owned()).collect(),
        kind,
    }))
}

/// `None` when `a` and `b` generate the same language and mark the same language; otherwise a shortest
/// string on which they differ.
pub fn equal(a: &Automaton, b: &Automaton) -> Result<Option<Difference>, SynthError> {
    compare(a, b, Relation::Equal)
}

/// `None` when the generated and marked languages of `a` are included in those of `b`; otherwise a
/// shortest string of `a` that `b` does not generate or mark.
pub fn included(a: &Automaton, b: &Automaton) -> Result<Option<Difference>, SynthError> {
    compare(a, b, Relation::Included)
}
