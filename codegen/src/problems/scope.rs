//! Where the checks run: the closed loop, and each supervisor with its local plant.
//!
//! The closed loop is every plant and every supervisor together; a problem found there can happen in the
//! running system. A supervisor with its local plant (the plants that share an event with it) is smaller
//! and says which supervisor a problem belongs to.

use crate::model::Automaton;

/// A set of automata whose synchronous product is checked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Scope<'a> {
    /// What the scope is, e.g. `closed loop` or `S1 with local plant G1, G2`.
    pub name: String,
    /// The automata to compose, plants first.
    pub members: Vec<&'a Automaton>,
}

/// The closed loop first, then one scope per supervisor (skipped when it equals the closed loop).
pub fn scopes<'a>(plants: &'a [Automaton], supervisors: &'a [Automaton]) -> Vec<Scope<'a>> {
    let closed: Vec<&Automaton> = plants.iter().chain(supervisors).collect();
    let mut out = vec![Scope { name: "closed loop".to_owned(), members: closed.clone() }];
    for s in supervisors {
        let local: Vec<&Automaton> =
            plants.iter().filter(|p| p.events.iter().any(|e| s.event_id(&e.name).is_some())).collect();
        let names: Vec<&str> = local.iter().map(|p| p.name.as_str()).collect();
        let members: Vec<&Automaton> = local.into_iter().chain([s]).collect();
        if members != closed {
            let name = if names.is_empty() {
                format!("{} alone", s.name)
            } else {
                format!("{} with local plant {}", s.name, names.join(", "))
            };
            out.push(Scope { name, members });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::build;

    #[test]
    fn local_plants_share_an_event() {
        let g1 = build("G1", &["0"], &[], &[("0", "a", "0")]);
        let g2 = build("G2", &["0"], &[], &[("0", "b", "0")]);
        let s1 = build("S1", &["0"], &[], &[("0", "a", "0")]);
        let s2 = build("S2", &["0"], &[], &[("0", "a", "0"), ("0", "b", "0")]);
        let (plants, sups) = (vec![g1, g2], vec![s1, s2]);
        let names: Vec<_> = scopes(&plants, &sups).into_iter().map(|s| (s.name, s.members.len())).collect();
        assert_eq!(
            names,
            [
                ("closed loop".to_owned(), 4),
                ("S1 with local plant G1".to_owned(), 2),
                ("S2 with local plant G1, G2".to_owned(), 3)
            ]
        );
    }

    #[test]
    fn a_lone_automaton_is_only_the_closed_loop() {
        let g = build("G", &["0"], &[], &[("0", "a", "0")]);
        let plants = vec![g];
        assert_eq!(scopes(&plants, &[]).len(), 1);
    }
}
