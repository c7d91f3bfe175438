//! The state-based program's rungs: per controllable event σ its F_σ ([`crate::feedback::Rule`])
//! factored into a rung — the literals every product shares in series (the precondition side), the
//! rest of each product on a parallel branch — whose coils are the outputs σ's command writes (SET for
//! TRUE, RESET for FALSE).

use crate::config::Cube;
use crate::feedback::Rule;
use crate::pack::PackSet;
use crate::scan::ir::Stmt;
use crate::scan::ld::{Coil, CoilKind, Element, Rung};

/// One controllable event's rung, with the formula it came from.
#[derive(Clone, Debug)]
pub struct EventRung {
    /// The event.
    pub event: String,
    /// F_σ as a sum of cubes over the variables.
    pub cubes: Vec<Cube>,
    /// The rung.
    pub rung: Rung,
    /// What the ST rung does besides its coils when it fires (the kept supervisors' memory).
    pub extra: Vec<Stmt>,
}

/// The literal of variable `i` (`names[i]`) with value `v` as a contact.
fn contact(names: &[String], i: usize, v: bool) -> Element {
    Element::contact(names.get(i).cloned().unwrap_or_default(), !v)
}

/// `cubes` over the variables `names` as a rung condition: shared literals in series, then the
/// products' remainders in parallel.
pub fn condition(names: &[String], cubes: &[Cube]) -> Element {
    let Some(first) = cubes.first() else { return Element::Parallel(Vec::new()) };
    let shared = cubes.iter().fold(first.mask, |m, c| m & c.mask & !(c.value ^ first.value));
    let common = Cube { mask: shared, value: first.value & shared };
    let mut series: Vec<Element> = common.literals().map(|(i, v)| contact(names, i, v)).collect();
    let rest: Vec<Element> = cubes
        .iter()
        .map(|c| {
            let r = Cube { mask: c.mask & !shared, value: c.value & !shared };
            Element::Series(r.literals().map(|(i, v)| contact(names, i, v)).collect())
        })
        .collect();
    if rest.len() > 1 {
        series.push(Element::Parallel(rest));
    }
    Element::Series(series)
}

/// The rung of `rule` of `set` over the variables `names`, behind the contact of the `BOOL` `guard`
/// holding its guard over a module's variables when it has one; `extra` runs in ST when it fires.
pub fn rung(
    set: &PackSet,
    names: &[String],
    rule: &Rule,
    guard: Option<&str>,
    extra: Vec<Stmt>,
) -> EventRung {
    let event = set.events().name(rule.event);
    let coils = rule
        .command
        .literals()
        .map(|(i, v)| Coil {
            variable: names.get(i).cloned().unwrap_or_default(),
            kind: if v { CoilKind::Set } else { CoilKind::Reset },
        })
        .collect();
    let (comment, condition) = match (guard, condition(names, &rule.cubes)) {
        (None, c) => (format!("{event}: F_{event}"), c),
        (Some(g), c) => {
            let mut series = match c {
                Element::Series(series) => series,
                other => vec![other],
            };
            series.push(Element::contact(g, false));
            (format!("{event}: F_{event} and its guard over the variables"), Element::Series(series))
        }
    };
    let rung = Rung { comment, condition, coils };
    EventRung { event: event.to_owned(), cubes: rule.cubes.clone(), rung, extra }
}
