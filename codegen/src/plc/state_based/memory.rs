//! Supervisor memory in a state-based program: where the plant state does not decide the feedback, the
//! kept supervisors' states become further literals ([`crate::feedback::memory::Layout`]) — each kept
//! supervisor's state as an `INT`, and its binary code as `BOOL`s (⌈log2 states⌉ of them, least
//! significant first) the rungs read — tracked from events as an event-based program tracks them. A command is known when
//! its rung fires; an uncontrollable event is read as its component's state change between two scans
//! (the previous state kept in an `INT`), so memory, unlike the rest of the program, depends on seeing
//! every sensor change: a component that moves two steps between scans desynchronises it.

use std::collections::BTreeMap;

use crate::feedback::memory::Layout;
use crate::feedback::{FeedbackError, Vector};
use crate::model::EventId;
use crate::pack::PackSet;
use crate::scan::ir::{Expr, Op, Stmt, Type, Var};
use crate::scan::names::Names;

use super::rungs;

/// The memory literals' names and the code that keeps them.
#[derive(Clone, Debug, Default)]
pub struct Tracking {
    /// Where the memory bits are among the variables.
    pub layout: Layout,
    /// Per kept supervisor, the `INT` holding its state.
    pub states: Vec<String>,
    /// Every memory bit's name, in index order.
    pub names: Vec<String>,
    /// Declarations: the kept supervisors' states and bits (initial states set), each tracked
    /// component's last state.
    pub vars: Vec<Var>,
    /// Before the rungs: each tracked component's state decoded, its uncontrollable events applied.
    pub detect: Vec<Stmt>,
    /// Per controllable event: what its rung does besides its coils.
    pub after: BTreeMap<u32, Vec<Stmt>>,
}

/// `CASE s OF q: s := q'; …` for event `e` in every kept supervisor holding it, then that supervisor's
/// bits set from its new state.
fn apply(set: &PackSet, m: &Tracking, e: EventId) -> Vec<Stmt> {
    let mut out = Vec::new();
    for (k, &s) in m.layout.kept.iter().enumerate() {
        let member = &set.members()[s];
        if !member.dfa.has_event(e.as_u32()) {
            continue;
        }
        let state = &m.states[k];
        let arms: Vec<(Vec<i64>, Vec<Stmt>)> = (0..member.state_count())
            .filter_map(|q| {
                let t = member.dfa.step(q as u32, e.as_u32())? as usize;
                (q != t).then(|| (vec![q as i64], vec![Stmt::set(state.clone(), Expr::Int(t as i64))]))
            })
            .collect();
        if arms.is_empty() {
            continue;
        }
        out.push(Stmt::Case(Expr::var(state.clone()), arms, Vec::new()));
        for (i, &bit) in m.layout.bits[k].iter().enumerate() {
            let digit = Expr::var(state.clone())
                .op(Op::Div, Expr::Int(1 << i))
                .op(Op::Mod, Expr::Int(2))
                .op(Op::Eq, Expr::Int(1));
            out.push(Stmt::set(m.names[bit - m.layout.base].clone(), digit));
        }
    }
    out
}

impl Tracking {
    /// The tracking of the memory bits of `layout` over `vector`'s signals, named `signal_names`:
    /// variables numbered from the signals' count, names unique against them.
    pub fn new(
        set: &PackSet,
        vector: &Vector,
        layout: &Layout,
        signal_names: &[String],
    ) -> Result<Tracking, FeedbackError> {
        let members = set.members();
        let mut names = Names::default();
        for n in signal_names {
            names.reserve(n);
        }
        let mut m = Tracking { layout: layout.clone(), ..Tracking::default() };
        let kept = &layout.kept;
        for (k, &s) in kept.iter().enumerate() {
            let sup = members[s].name();
            let initial = members[s].initial().index();
            let state = names.fresh("s", sup);
            m.vars.push(
                Var::new(state.clone(), Type::Int, format!("memory: {sup}'s state"))
                    .init(Expr::Int(initial as i64)),
            );
            m.states.push(state);
            for i in 0..layout.bits[k].len() {
                let name = names.fresh(&format!("m_{sup}"), &format!("b{i}"));
                m.vars.push(
                    Var::new(name.clone(), Type::Bool, format!("memory: bit {i} of {sup}'s state"))
                        .init(Expr::Bool(initial >> i & 1 == 1)),
                );
                m.names.push(name);
            }
        }
        let all_names: Vec<String> = signal_names.iter().chain(&m.names).cloned().collect();
        let table = set.events();
        let plants = vector.component.len();
        for p in 0..plants {
            let plant = &members[p];
            let kept_has = |e: EventId| kept.iter().any(|&s| members[s].dfa.has_event(e.as_u32()));
            // The uncontrollable transitions of the plant the kept supervisors see, by (from, to).
            let mut seen: BTreeMap<(usize, usize), EventId> = BTreeMap::new();
            for q in 0..plant.state_count() {
                for (e, t) in plant.out(q) {
                    if table.is_controllable(e) || !kept_has(e) {
                        continue;
                    }
                    if let Some(other) = seen.insert((q, t.index()), e) {
                        return Err(FeedbackError::Vector {
                            key: format!("state.components.{}", plant.name()),
                            message: format!(
                                "{} and {} both lead from {} to {}: memory cannot tell them apart",
                                table.name(other),
                                table.name(e),
                                plant.automaton.states[q].name,
                                plant.automaton.states[t.index()].name
                            ),
                        });
                    }
                }
            }
            if seen.is_empty() {
                continue;
            }
            let prev = names.fresh("p", plant.name());
            let now = names.fresh("n", plant.name());
            m.vars.push(
                Var::new(prev.clone(), Type::Int, format!("{}'s state at the last scan", plant.name()))
                    .init(Expr::Int(plant.initial().index() as i64)),
            );
            m.vars.push(Var::new(now.clone(), Type::Int, format!("{}'s state read this scan", plant.name())));
            let decode: Vec<(Expr, Vec<Stmt>)> = vector.cubes[p]
                .iter()
                .enumerate()
                .map(|(q, &c)| {
                    (
                        rungs::condition(&all_names, &[c]).st(),
                        vec![Stmt::set(now.clone(), Expr::Int(q as i64))],
                    )
                })
                .collect();
            m.detect.push(Stmt::If(decode, Vec::new()));
            for (&(a, b), &e) in &seen {
                let cond = Expr::var(prev.clone())
                    .op(Op::Eq, Expr::Int(a as i64))
                    .op(Op::And, Expr::var(now.clone()).op(Op::Eq, Expr::Int(b as i64)));
                let body = apply(set, &m, e);
                if !body.is_empty() {
                    m.detect.push(Stmt::when(cond, body));
                }
            }
            m.detect.push(Stmt::set(prev.clone(), Expr::var(now.clone())));
            // A command moves the component too: its rung records where to, so the next scan reads no
            // sensor event in it.
            let mut moves: BTreeMap<u32, Vec<(Expr, Vec<Stmt>)>> = BTreeMap::new();
            for q in 0..plant.state_count() {
                for (e, t) in plant.out(q).filter(|&(e, _)| table.is_controllable(e)) {
                    moves.entry(e.as_u32()).or_default().push((
                        Expr::var(prev.clone()).op(Op::Eq, Expr::Int(q as i64)),
                        vec![Stmt::set(prev.clone(), Expr::Int(t.index() as i64))],
                    ));
                }
            }
            for (e, arms) in moves {
                m.after.entry(e).or_default().push(Stmt::If(arms, Vec::new()));
            }
        }
        for e in table.ids().filter(|&e| table.is_controllable(e)) {
            let mut body = apply(set, &m, e);
            body.extend(m.after.remove(&e.as_u32()).unwrap_or_default());
            if !body.is_empty() {
                m.after.insert(e.as_u32(), body);
            }
        }
        Ok(m)
    }
}
