//! The state-based program: its rungs ([`super::rungs`]) as the ST `PROGRAM` (one `IF` per rung, on the
//! current image: a command written by one rung is seen by the rungs below) and the Ladder Diagram body. With a choice policy ([`OnePerScan`],
//! `[state] choice`) the rungs' conditions fill the choice section's `enabled` array instead, the policy
//! picks one ([`crate::plc::choice`], as in the event-based program) and only its command is written:
//! where several commands are allowed in one plant state, each may be the one that fires there, and the
//! plant may move before the next.

use crate::config::{Direction, ScanPolicy, Signals};
use crate::feedback::{FeedbackError, Vector};
use crate::model::EventId;
use crate::plc::choice::{self, PlantChoice};
use crate::scan::ir::{Expr, Pou, Section, Stmt, Type, Var, VarClass};
use crate::scan::ld::{CoilKind, Element, Rung};
use crate::scan::names::is_identifier;

use super::memory::{Tracking, HOLD};
use super::rungs::EventRung;

/// One command per scan, chosen among the rungs that conduct.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OnePerScan {
    /// The choice policy.
    pub policy: ScanPolicy,
    /// The random policy's seed.
    pub seed: u64,
    /// Per rung, the plant component its command belongs to (the local queue's plants).
    pub owners: Vec<usize>,
}

impl OnePerScan {
    /// The choice by `policy` (seeded with `seed`) among the rungs of `events`, in rung order, each
    /// owned by the plant component its command writes (component 0 for an event without a command).
    pub fn new(
        policy: ScanPolicy,
        seed: u64,
        vector: &Vector,
        events: impl IntoIterator<Item = EventId>,
    ) -> Self {
        let owners = events.into_iter().map(|e| vector.commands[e.index()].map_or(0, |(p, _)| p)).collect();
        OnePerScan { policy, seed, owners }
    }

    /// `enabled[k] := F_k` for every rung, the policy's choice of `c`, then `CASE c OF k: command k`.
    fn statements(&self, conditions: Vec<Expr>, bodies: Vec<Vec<Stmt>>) -> Vec<Stmt> {
        let n = conditions.len() as i64;
        let components = self.owners.iter().max().map_or(0, |&m| m + 1);
        let plants: Vec<PlantChoice> = (0..components)
            .map(|p| PlantChoice {
                events: (0..n).filter(|&k| self.owners.get(k as usize) == Some(&p)).collect(),
                sites: Vec::new(),
            })
            .collect();
        let mut out: Vec<Stmt> = conditions
            .into_iter()
            .enumerate()
            .map(|(k, cond)| Stmt::Assign(Expr::at(choice::ENABLED, Expr::Int(k as i64)), cond))
            .collect();
        out.push(Stmt::set("c", Expr::Int(-1)));
        out.extend(choice::statements(self.policy, n, &plants));
        let arms = bodies.into_iter().enumerate().map(|(k, body)| (vec![k as i64], body)).collect();
        out.push(Stmt::Case(Expr::var("c"), arms, Vec::new()));
        out
    }
}

/// `rung` behind a normally closed `hold` contact ([`HOLD`]): the rung of a program keeping memory, in
/// its ST condition and its ladder alike.
pub fn held(rung: &Rung) -> Rung {
    let hold = Element::Contact { variable: HOLD.into(), negated: true };
    Rung { condition: Element::Series(vec![hold, rung.condition.clone()]), ..rung.clone() }
}

/// The `PROGRAM <base>_main`: every signal a `BOOL` (located where it has an address), the memory's
/// variables, its event detection, then one `IF` per rung — or, with `one`, the rungs' conditions
/// into the choice section and the chosen rung's command. With memory kept, every rung's condition
/// is preceded by `NOT hold` ([`HOLD`]): held, the program still tracks every sensor change scan by
/// scan but fires no command, as the event-based program's `hold` does, so that a closed loop in
/// lock-step rounds can show it a round's sensor changes one per scan and let it decide on all of
/// them (the rungs' formulas and figures are those of f; `hold` is FALSE unless something sets it).
pub fn pou(
    signals: &Signals,
    base: &str,
    rungs: &[EventRung],
    memory: &Tracking,
    one: Option<&OnePerScan>,
) -> Result<Pou, FeedbackError> {
    let mut vars = Vec::new();
    for s in &signals.signals {
        if !is_identifier(&s.name) {
            return Err(FeedbackError::Vector {
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
    let holds = !memory.vars.is_empty();
    if holds {
        if let Some(v) = vars.iter().find(|v| v.name.eq_ignore_ascii_case(HOLD)) {
            return Err(FeedbackError::Vector {
                key: "state.components".into(),
                message: format!("signal '{}' has the name of the program's hold input", v.name),
            });
        }
        vars.push(
            Var::new(HOLD, Type::Bool, "held: the memory reads the sensors, no rung fires")
                .init(Expr::Bool(false)),
        );
    }
    let condition = |r: &EventRung| -> Expr {
        if holds {
            held(&r.rung).condition.st()
        } else {
            r.rung.condition.st()
        }
    };
    if let Some(one) = one {
        let taken = vars.iter().find(|v| choice::VARIABLES.iter().any(|c| c.eq_ignore_ascii_case(&v.name)));
        if let Some(v) = taken {
            return Err(FeedbackError::Vector {
                key: "state.choice".into(),
                message: format!("signal '{}' has a name the choice section uses", v.name),
            });
        }
        vars.extend(choice::locals(one.policy, rungs.len(), 0, one.seed, "rung"));
    }
    let body = |r: &EventRung| -> Vec<Stmt> {
        r.rung
            .coils
            .iter()
            .map(|c| Stmt::set(c.variable.clone(), Expr::Bool(c.kind == CoilKind::Set)))
            .chain(r.extra.iter().cloned())
            .collect()
    };
    let stmts = match one {
        None => rungs.iter().map(|r| Stmt::when(condition(r), body(r))).collect(),
        Some(one) => one.statements(rungs.iter().map(condition).collect(), rungs.iter().map(body).collect()),
    };
    let events: Vec<&str> = rungs.iter().map(|r| r.event.as_str()).collect();
    Ok(Pou {
        program: true,
        name: format!("{base}_main"),
        vars: vec![(VarClass::Local, vars)],
        sections: vec![
            Section::new(
                "events",
                "supervisor memory: sensor events read from the tracked components' state changes",
                memory.detect.clone(),
            ),
            Section::new(
                "rungs",
                format!(
                    "one rung per controllable event{}: {}",
                    one.map_or(String::new(), |o| format!(", one per scan chosen by {}", o.policy.name())),
                    events.join(", ")
                ),
                stmts,
            ),
        ],
    })
}
