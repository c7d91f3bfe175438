//! The state-based program: per controllable event σ (in event id order) its F_σ factored into a rung —
//! the literals every product shares in series (the precondition side), the rest of each product on a
//! parallel branch — whose coils are the outputs σ's command writes (SET for TRUE, RESET for FALSE). The
//! same rungs become the ST `PROGRAM` (one `IF` per rung, on the current image: a command written by one
//! rung is seen by the rungs below) and the Ladder Diagram body.

use crate::config::{Cube, Direction, Signals};
use crate::plc::ld::{Coil, CoilKind, Element, Rung};
use crate::plc::names::is_identifier;
use crate::plc::st::{Expr, Pou, Section, SectionKind, Stmt, Type, Var, VarClass};
use crate::plc::state_based::memory::Memory;

use super::StateError;

/// One controllable event's rung, with the formula it came from.
#[derive(Clone, Debug)]
pub struct EventRung {
    /// The event.
    pub event: String,
    /// F_σ as a sum of cubes over the signals.
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

/// The rung of `event` with formula `cubes` over the variables `names` and command `command`; `extra`
/// runs in ST when it fires.
pub fn rung(names: &[String], event: &str, cubes: Vec<Cube>, command: Cube, extra: Vec<Stmt>) -> EventRung {
    let coils = command
        .literals()
        .map(|(i, v)| Coil {
            variable: names.get(i).cloned().unwrap_or_default(),
            kind: if v { CoilKind::Set } else { CoilKind::Reset },
        })
        .collect();
    let rung = Rung { comment: format!("{event}: F_{event}"), condition: condition(names, &cubes), coils };
    EventRung { event: event.to_owned(), cubes, rung, extra }
}

/// The `PROGRAM <base>_main`: every signal a `BOOL` (located where it has an address), the memory's
/// variables, its event detection, then one `IF` per rung.
pub fn pou(signals: &Signals, base: &str, rungs: &[EventRung], memory: &Memory) -> Result<Pou, StateError> {
    let mut vars = Vec::new();
    for s in &signals.signals {
        if !is_identifier(&s.name) {
            return Err(StateError::Vector {
                key: "state.components".into(),
                message: format!("signal '{}' is not an IEC 61131-3 identifier", s.name),
            });
        }
        let what = match s.direction {
            Direction::Input => "input",
            Direction::Output => "output",
        };
        let mut v =
            Var::new(s.name.clone(), Type::Bool, format!("{} {what}", signals.components[s.component].name));
        v.address.clone_from(&s.address);
        vars.push(v);
    }
    vars.extend(memory.vars.iter().cloned());
    let stmts = rungs
        .iter()
        .map(|r| {
            let body = r
                .rung
                .coils
                .iter()
                .map(|c| Stmt::set(c.variable.clone(), Expr::Bool(c.kind == CoilKind::Set)))
                .chain(r.extra.iter().cloned())
                .collect();
            Stmt::when(r.rung.condition.st(), body)
        })
        .collect();
    let events: Vec<&str> = rungs.iter().map(|r| r.event.as_str()).collect();
    Ok(Pou {
        program: true,
        name: format!("{base}_main"),
        vars: vec![(VarClass::Local, vars)],
        sections: vec![
            Section {
                kind: SectionKind::Events,
                title: "supervisor memory: sensor events read from the tracked components' state changes"
                    .into(),
                stmts: memory.detect.clone(),
            },
            Section {
                kind: SectionKind::Rungs,
                title: format!("one rung per controllable event: {}", events.join(", ")),
                stmts,
            },
        ],
    })
}
