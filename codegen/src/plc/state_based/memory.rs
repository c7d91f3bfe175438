//! Supervisor memory in a state-based program: where the plant state does not decide the feedback, the
//! kept supervisors' states become further literals ([`crate::feedback::memory::Layout`]) — each kept
//! supervisor's state as an `INT`, and its binary code as `BOOL`s (⌈log2 states⌉ of them, least
//! significant first) the rungs read — tracked from events as an event-based program tracks them. A command is known when
//! its rung fires; an uncontrollable event is read as its component's state change between two scans
//! (the previous state kept in an `INT`), so memory, unlike the rest of the program, depends on seeing
//! every sensor change: a component that moves two steps between scans desynchronises it.
//!
//! A project of Supremica modules with variables keeps its variables the same way
//! ([`crate::plc::guards`]): each an `INT` updated by its events' actions where they are seen (a
//! sensor event in the detection, a command after its rung's coils), and per controllable event the
//! guards decide a `BOOL` holding its guard, refreshed after every update, which the event's rung
//! reads as a contact beside F_σ.

use std::collections::BTreeMap;

use crate::feedback::memory::Layout;
use crate::feedback::{FeedbackError, Vector};
use crate::model::EventId;
use crate::pack::PackSet;
use crate::plc::choice;
use crate::plc::guards::Guards;
use crate::scan::ir::{Expr, Op, Stmt, Type, Var};
use crate::scan::names::Names;

use super::rungs;

/// The input that, with memory kept, stops the rungs while the memory goes on reading the sensors.
pub const HOLD: &str = "hold";

/// The memory literals' names and the code that keeps them.
#[derive(Clone, Debug, Default)]
pub struct Tracking {
    /// Where the memory bits are among the variables.
    pub layout: Layout,
    /// Per kept supervisor, the `INT` holding its state.
    pub states: Vec<String>,
    /// Every memory bit's name, in index order.
    pub names: Vec<String>,
    /// Declarations: the kept supervisors' states and bits (initial states set), the kept variables
    /// and the guards' `BOOL`s (initial values set), each tracked component's last state.
    pub vars: Vec<Var>,
    /// Before the rungs: each tracked component's state decoded, its uncontrollable events applied.
    pub detect: Vec<Stmt>,
    /// Per controllable event: what its rung does besides its coils.
    pub after: BTreeMap<u32, Vec<Stmt>>,
    /// The modules' variables kept as `INT`s ([`Guards::variables`] order).
    pub variables: Vec<String>,
    /// Per controllable event with a guard: the `BOOL` holding it, its rung's further contact.
    pub guards: Vec<(EventId, String)>,
}

impl Tracking {
    /// The `BOOL` holding `e`'s guard, if it has one.
    pub fn guard(&self, e: EventId) -> Option<&str> {
        self.guards.iter().find(|(x, _)| *x == e).map(|(_, g)| g.as_str())
    }

    /// Each guard's `BOOL` set from the variables.
    fn refresh(&self, guards: &Guards) -> Vec<Stmt> {
        let guard = |e: EventId| guards.guards.iter().find(|(x, _)| *x == e).map(|(_, g)| g);
        self.guards
            .iter()
            .filter_map(|(e, b)| Some(Stmt::set(b, guard(*e)?.condition(&self.variables))))
            .collect()
    }

    /// What event `e` does to the memory: the kept supervisors' states, then the variables and the
    /// guards read from them.
    fn on_event(&self, set: &PackSet, guards: &Guards, e: EventId) -> Vec<Stmt> {
        let mut out = apply(set, self, e);
        let assigned = guards.assignments(e, &self.variables);
        if !assigned.is_empty() {
            out.extend(assigned);
            out.extend(self.refresh(guards));
        }
        out
    }
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
    /// variables numbered from the signals' count, names unique against them; with `guards`' variables
    /// and guards beside them.
    pub fn new(
        set: &PackSet,
        vector: &Vector,
        layout: &Layout,
        signal_names: &[String],
        guards: &Guards,
    ) -> Result<Tracking, FeedbackError> {
        let members = set.members();
        let mut names = Names::default();
        // The program's own names too: its hold input and its choice section's variables.
        for n in signal_names.iter().map(String::as_str).chain([HOLD]).chain(choice::VARIABLES) {
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
        let initial: Vec<i64> = guards.variables.iter().map(|v| v.declared.initial).collect();
        for (v, &x) in guards.variables.iter().zip(&initial) {
            let name = names.plain(&v.declared.name);
            m.vars.push(v.local(&name).init(Expr::Int(x)));
            m.variables.push(name);
        }
        // A guard that always holds needs no contact.
        for (e, g) in guards.guards.iter().filter(|(_, g)| !g.always()) {
            let event = set.events().name(*e);
            let name = names.fresh("g", event);
            let what = format!("guard of '{event}': {}", g.text(&guards.variables));
            m.vars.push(Var::new(name.clone(), Type::Bool, what).init(Expr::Bool(g.holds(&initial))));
            m.guards.push((*e, name));
        }
        let updates = |e: EventId| guards.variables.iter().any(|v| v.updates.iter().any(|(x, _)| *x == e));
        let all_names: Vec<String> = signal_names.iter().chain(&m.names).cloned().collect();
        let table = set.events();
        let plants = vector.component.len();
        for p in 0..plants {
            let plant = &members[p];
            let kept_has =
                |e: EventId| kept.iter().any(|&s| members[s].dfa.has_event(e.as_u32())) || updates(e);
            // The uncontrollable transitions of the plant the kept supervisors see or that update a kept
            // variable, by (from, to).
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
                let body = m.on_event(set, guards, e);
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
            let mut body = m.on_event(set, guards, e);
            body.extend(m.after.remove(&e.as_u32()).unwrap_or_default());
            if !body.is_empty() {
                m.after.insert(e.as_u32(), body);
            }
        }
        Ok(m)
    }
}
