//! Controllability as the files of a set say it. Formats that name it for every event (IDES3, TCT's odd
//! and even labels, a Supremica module's event kinds, a libFAUDES generator with `+C+`) say it; a
//! libFAUDES generator without `+C+` anywhere says nothing — libFAUDES takes controllability from the
//! plant — and its events take what the rest of the set says.

use std::collections::BTreeMap;

use super::{Automaton, ModelError};

/// Gives every event of the automata whose files left controllability unsaid
/// ([`Automaton::controllability_unsaid`]) the controllability the others say, and marks them said.
/// Refuses an event two files say differently ([`ModelError::InconsistentControllability`], as
/// [`super::EventTable::build`] does) and an event no file says ([`ModelError::UnsaidControllability`]).
pub fn resolve_controllability<'a>(
    automata: impl IntoIterator<Item = &'a mut Automaton>,
) -> Result<(), ModelError> {
    resolve_controllability_or(automata, None)
}

/// [`resolve_controllability`], with `otherwise` the controllability of the events no file says
/// (`codegen convert --assume`); `None` refuses them as [`resolve_controllability`] does.
pub fn resolve_controllability_or<'a>(
    automata: impl IntoIterator<Item = &'a mut Automaton>,
    otherwise: Option<bool>,
) -> Result<(), ModelError> {
    let mut automata: Vec<&mut Automaton> = automata.into_iter().collect();
    let mut said: BTreeMap<String, (bool, String)> = BTreeMap::new();
    for a in automata.iter().filter(|a| !a.controllability_unsaid) {
        for e in &a.events {
            match said.get(&e.name) {
                Some((c, first)) if *c != e.controllable => {
                    return Err(ModelError::InconsistentControllability {
                        event: e.name.clone(),
                        first: first.clone(),
                        first_controllable: *c,
                        second: a.name.clone(),
                    })
                }
                Some(_) => {}
                None => {
                    said.insert(e.name.clone(), (e.controllable, a.name.clone()));
                }
            }
        }
    }
    let mut unsaid: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for a in automata.iter().filter(|a| a.controllability_unsaid) {
        for e in a.events.iter().filter(|e| !said.contains_key(&e.name)) {
            unsaid.entry(e.name.clone()).or_default().push(a.name.clone());
        }
    }
    match (unsaid.into_iter().next(), otherwise) {
        (Some((event, automata)), None) => return Err(ModelError::UnsaidControllability { event, automata }),
        (Some(_), Some(c)) => {
            for a in automata.iter().filter(|a| a.controllability_unsaid) {
                for e in &a.events {
                    said.entry(e.name.clone()).or_insert((c, String::new()));
                }
            }
        }
        (None, _) => {}
    }
    for a in automata.iter_mut().filter(|a| a.controllability_unsaid) {
        for e in &mut a.events {
            e.controllable = said[&e.name].0;
        }
        a.controllability_unsaid = false;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::build;

    fn unsaid(mut a: Automaton) -> Automaton {
        a.events.iter_mut().for_each(|e| e.controllable = false);
        a.controllability_unsaid = true;
        a
    }

    #[test]
    fn an_unsaid_automaton_takes_what_the_others_say() {
        let mut plant = build("G", &["0", "1"], &["a"], &[("0", "a", "1"), ("1", "b", "0")]);
        let mut spec = unsaid(build("E", &["0"], &[], &[("0", "a", "0"), ("0", "b", "0")]));
        resolve_controllability([&mut plant, &mut spec]).unwrap();
        let c: Vec<(String, bool)> = spec.events.iter().map(|e| (e.name.clone(), e.controllable)).collect();
        assert_eq!(c, [("a".to_owned(), true), ("b".to_owned(), false)]);
        assert!(!spec.controllability_unsaid);
    }

    #[test]
    fn an_event_no_file_says_is_named_with_the_automata_that_hold_it() {
        let mut plant = build("G", &["0"], &["a"], &[("0", "a", "0")]);
        let mut e1 = unsaid(build("E1", &["0"], &[], &[("0", "a", "0"), ("0", "z", "0")]));
        let mut e2 = unsaid(build("E2", &["0"], &[], &[("0", "z", "0")]));
        let err = resolve_controllability([&mut plant, &mut e1, &mut e2]).unwrap_err();
        assert!(matches!(&err, ModelError::UnsaidControllability { event, automata }
            if event == "z" && automata == &["E1", "E2"]));
        assert!(err.to_string().contains("E1, E2 all leave it unsaid"), "{err}");
    }

    #[test]
    fn what_no_file_says_takes_what_is_assumed() {
        let mut plant = build("G", &["0"], &["a"], &[("0", "a", "0")]);
        let mut spec = unsaid(build("E", &["0"], &[], &[("0", "a", "0"), ("0", "z", "0")]));
        resolve_controllability_or([&mut plant, &mut spec], Some(false)).unwrap();
        let c: Vec<bool> = spec.events.iter().map(|e| e.controllable).collect();
        assert_eq!(c, [true, false], "the plant says a; z is assumed");
    }

    #[test]
    fn two_files_saying_it_differently_are_refused_as_before() {
        let mut g = build("G", &["0"], &["a"], &[("0", "a", "0")]);
        let mut h = build("H", &["0"], &[], &[("0", "a", "0")]);
        assert!(matches!(
            resolve_controllability([&mut g, &mut h]),
            Err(ModelError::InconsistentControllability { .. })
        ));
    }
}
