//! Alphabets where files meet: the events of specifications and supervisors that no plant has.
//!
//! Synthesis treats an event no plant has as one the plant always allows: a typo in a specification
//! (`s11` for `sl1`) silently becomes a new, free event, the supervisor grows, and a simulation of the
//! plants can never produce it. libFAUDES' `SupCon` refuses such a pair outright. So a set refuses every
//! such event unless it is declared plant-less on purpose, and names the plant events closest in
//! spelling ([`super::suggest`]).

use std::collections::BTreeSet;

use super::{suggest, Automaton, Kind};

/// An event of a specification or supervisor that no plant of its set has.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlantlessEvent {
    /// The event.
    pub event: String,
    /// The automaton holding it.
    pub automaton: String,
    /// Its role (specification or supervisor).
    pub kind: Kind,
    /// The plant events closest in spelling, best first (possibly none).
    pub suggestions: Vec<String>,
}

impl PlantlessEvent {
    /// `event 's11' of specification 'S' is in no plant (did you mean 'sl1'?)`.
    pub fn describe(&self) -> String {
        let role = match self.kind {
            Kind::Spec => "specification",
            Kind::Supervisor => "supervisor",
            Kind::Plant | Kind::Unknown => "automaton",
        };
        let hint = suggest::did_you_mean(&self.event, self.suggestions.iter().map(String::as_str));
        format!("event '{}' of {role} '{}' is in no plant{hint}", self.event, self.automaton)
    }
}

/// Every event of `specs` and `supervisors` (in order, each event once per automaton) that no automaton
/// of `plants` has and that `declared` does not name. A set without plants has nothing to check against
/// and gives none.
pub fn plantless_events(
    plants: &[Automaton],
    specs: &[Automaton],
    supervisors: &[Automaton],
    declared: &BTreeSet<String>,
) -> Vec<PlantlessEvent> {
    if plants.is_empty() {
        return Vec::new();
    }
    let plant_events: BTreeSet<&str> =
        plants.iter().flat_map(|p| &p.events).map(|e| e.name.as_str()).collect();
    let roles =
        specs.iter().map(|a| (a, Kind::Spec)).chain(supervisors.iter().map(|a| (a, Kind::Supervisor)));
    let mut out = Vec::new();
    for (a, kind) in roles {
        for e in &a.events {
            if plant_events.contains(e.name.as_str()) || declared.contains(&e.name) {
                continue;
            }
            out.push(PlantlessEvent {
                event: e.name.clone(),
                automaton: a.name.clone(),
                kind,
                suggestions: suggest::closest(&e.name, plant_events.iter().copied())
                    .into_iter()
                    .map(str::to_owned)
                    .collect(),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::build;

    fn arm() -> Automaton {
        build("G_arm", &["0", "1"], &["al", "ar"], &[("0", "al", "1"), ("1", "sl1", "0"), ("1", "ar", "0")])
    }

    fn spec(events: &[&str]) -> Automaton {
        let mut a = build("S", &["0"], &[], &events.iter().map(|e| ("0", *e, "0")).collect::<Vec<_>>());
        a.kind = Kind::Spec;
        a
    }

    #[test]
    fn a_typo_is_named_with_the_plant_event_it_resembles() {
        let found = plantless_events(&[arm()], &[spec(&["al", "s11"])], &[], &BTreeSet::new());
        assert_eq!(found.len(), 1);
        assert_eq!(
            found[0].describe(),
            "event 's11' of specification 'S' is in no plant (did you mean 'sl1'?)"
        );
    }

    #[test]
    fn every_problem_of_every_automaton_is_listed_and_declared_events_pass() {
        let mut sup = spec(&["zz", "ar"]);
        sup.name = "K".into();
        let (s, plants) = (spec(&["s11", "tick"]), [arm()]);
        let found = plantless_events(&plants, std::slice::from_ref(&s), &[sup], &BTreeSet::new());
        let names: Vec<(&str, &str)> =
            found.iter().map(|p| (p.automaton.as_str(), p.event.as_str())).collect();
        assert_eq!(names, [("S", "s11"), ("S", "tick"), ("K", "zz")]);
        assert!(found[2].describe().starts_with("event 'zz' of supervisor 'K' is in no plant"));
        let declared: BTreeSet<String> = ["tick".to_owned()].into();
        assert_eq!(plantless_events(&plants, &[s], &[], &declared).len(), 1);
    }

    #[test]
    fn a_set_without_plants_has_nothing_to_check() {
        assert!(plantless_events(&[], &[spec(&["a"])], &[], &BTreeSet::new()).is_empty());
    }
}
