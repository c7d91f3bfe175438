//! Guards over the variables of extended finite automata, for the PLC programs: the way Supremica's "add
//! guards" and ESCET's data-based synthesis give a supervisor back to a model with variables. The
//! analysis ([`extract`]) is one for both forms, and so is what they write of it ([`Guard::condition`],
//! [`Guards::assignments`], [`Variable::local`]); the event-based program tests the guard in the event's
//! rung ([`super::program`]), the state-based one keeps it in a `BOOL` its rung reads
//! ([`super::state_based::memory`]).
//!
//! The supervisors are synthesised from the unfolded automata ([`crate::formats::efa::unfold`]); this
//! module takes them back to the variables in two steps.
//!
//! 1. **Variables.** A variable is kept in the program as an integer when every event updates it the
//!    same way wherever the event is taken: in each component that assigns it and has the event, every
//!    edge carrying the event performs the same action on it (or none does), no two components assign
//!    it different actions on one event, the actions are arithmetic (`+`, `-`, `*`, negation, constants
//!    and other kept variables; `/` and `%`, whose rounding the PLC need not share, and comparisons are
//!    not), and its range fits an `INT`. Its update is then a statement `IF ev THEN x := …` per event.
//!    A variable that fails this stays inside the automata's states only.
//! 2. **Guards.** The closed loop of the set (plants and supervisors) is walked with the kept variables
//!    updated by those actions. For a controllable event that a supervisor holds, the care set is every
//!    reachable configuration where the plants allow it: `E` the valuations where the supervisors allow
//!    it too, `D` where one forbids it. Where `E` and `D` are disjoint, the supervisors' enablement is a
//!    function of the variables and the guard replaces their state tests in the event's rung (the
//!    plants' tests stay); where they meet it is not, and the event keeps the supervisors' state tests —
//!    a hybrid of state and guard, as Supremica leaves a guard over the automata's locations.
//!
//! The guard is simplified as follows. If one variable separates `E` from `D` (their projections on it
//! are disjoint), the guard is over that variable alone: the maximal runs of consecutive values of its
//! range that hold no value of `D`, those that hold a value of `E` kept, each written as an interval —
//! a bound at the range's end is left out, so `0..2` with `E = {0, 1}`, `D = {2}` gives `x <= 1`. Values
//! of no reachable configuration are don't-cares and fall in with the runs. Otherwise the guard is the
//! disjunction of `E`'s valuations over every kept variable, each a conjunction of equalities. With `D`
//! empty the guard is `TRUE`, with `E` empty `FALSE`. The guard equals the supervisors' enablement on
//! every reachable configuration where the plants allow the event, which is all the rung needs
//! (elsewhere the plants' tests are false); `tests` checks it against the explicit enablement.

use std::collections::{BTreeSet, HashMap, VecDeque};

use crate::formats::efa::expr::{Action, AssignOp, BinaryOp, Expr, UnaryOp};
use crate::formats::efa::{Efa, Variable as EfaVariable};
use crate::model::EventId;
use crate::pack::{PackSet, Role};
use crate::scan::ir::{self, Op, Stmt};

/// The most closed-loop configurations the walk visits: a larger closed loop keeps the state encoding.
pub const MAX_CONFIGURATIONS: usize = 1 << 18;

/// A variable kept in the program as an integer: its declaration in the module, and what the program
/// adds to it (its updates, where it comes from).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variable {
    /// Its declaration: name, range and initial value.
    pub declared: EfaVariable,
    /// Per event of the set that assigns it, the action (its expression's variables are indices into
    /// the module's variables: [`Guards::module_index`] maps them to kept variables).
    pub updates: Vec<(EventId, Action)>,
    /// Which module it comes from (index into the options' modules).
    pub module: usize,
    /// Its index among its module's variables.
    pub index: usize,
}

impl Variable {
    /// Its declaration in a program as the `INT` `name` (no initial value: each form sets it).
    pub fn local(&self, name: &str) -> ir::Var {
        let d = &self.declared;
        let what = format!(
            "variable '{}' ({}..{}, initial {}): its events' actions",
            d.name, d.min, d.max, d.initial
        );
        ir::Var::new(name, ir::Type::Int, what)
    }
}

/// A bound on one kept variable: `lo <= x <= hi`, either side absent when it is the range's end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bound {
    /// The kept variable (index into [`Guards::variables`]).
    pub var: usize,
    /// The least value allowed, `None` for the range's least.
    pub lo: Option<i64>,
    /// The greatest, `None` for the range's greatest.
    pub hi: Option<i64>,
}

/// A guard: a disjunction of conjunctions of bounds (no terms: `FALSE`; an empty term: `TRUE`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Guard {
    /// The conjunctions.
    pub terms: Vec<Vec<Bound>>,
}

impl Guard {
    /// Whether the guard holds at `values` (the kept variables' values).
    pub fn holds(&self, values: &[i64]) -> bool {
        self.terms.iter().any(|t| {
            t.iter().all(|b| {
                let x = values[b.var];
                b.lo.is_none_or(|lo| x >= lo) && b.hi.is_none_or(|hi| x <= hi)
            })
        })
    }

    /// Whether the guard always holds (`TRUE`: the supervisors never forbid the event where the
    /// plants allow it).
    pub fn always(&self) -> bool {
        self.terms.iter().any(Vec::is_empty)
    }

    /// The guard as text over the variables' names (`n <= 1`, `n = 2 OR n = 4`), for reports.
    pub fn text(&self, variables: &[Variable]) -> String {
        if self.terms.is_empty() {
            return "FALSE".into();
        }
        let term = |t: &Vec<Bound>| -> String {
            if t.is_empty() {
                return "TRUE".into();
            }
            let parts: Vec<String> = t
                .iter()
                .map(|b| {
                    let n = &variables[b.var].declared.name;
                    match (b.lo, b.hi) {
                        (Some(lo), Some(hi)) if lo == hi => format!("{n} = {lo}"),
                        (Some(lo), Some(hi)) => format!("{lo} <= {n} <= {hi}"),
                        (Some(lo), None) => format!("{n} >= {lo}"),
                        (None, Some(hi)) => format!("{n} <= {hi}"),
                        (None, None) => "TRUE".into(),
                    }
                })
                .collect();
            parts.join(" AND ")
        };
        let terms: Vec<String> = self.terms.iter().map(term).collect();
        match terms.as_slice() {
            [one] => one.clone(),
            _ => terms.iter().map(|t| format!("({t})")).collect::<Vec<_>>().join(" OR "),
        }
    }

    /// The guard as an ST condition over the kept variables' identifiers `names` (by kept index): what
    /// both program forms test, the event-based one in the event's rung, the state-based one in the
    /// guard's `BOOL`.
    pub fn condition(&self, names: &[String]) -> ir::Expr {
        let bound = |b: &Bound| {
            let x = || ir::Expr::var(&names[b.var]);
            match (b.lo, b.hi) {
                (Some(lo), Some(hi)) if lo == hi => vec![x().op(Op::Eq, ir::Expr::Int(lo))],
                (lo, hi) => lo
                    .map(|lo| x().op(Op::Ge, ir::Expr::Int(lo)))
                    .into_iter()
                    .chain(hi.map(|hi| x().op(Op::Le, ir::Expr::Int(hi))))
                    .collect(),
            }
        };
        let term = |t: &Vec<Bound>| ir::Expr::fold(t.iter().flat_map(bound), Op::And, ir::Expr::Bool(true));
        ir::Expr::fold(self.terms.iter().map(term), Op::Or, ir::Expr::Bool(false))
    }
}

/// What the program keeps of the modules' variables, and the guards over them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Guards {
    /// The variables kept as integers, by module then declaration.
    pub variables: Vec<Variable>,
    /// Per controllable event that a supervisor holds and whose enablement is a function of the kept
    /// variables: its guard, which replaces the supervisors' state tests.
    pub guards: Vec<(EventId, Guard)>,
    /// Controllable events a supervisor holds whose enablement is not a function of the kept variables:
    /// they keep the supervisors' state tests.
    pub kept: Vec<EventId>,
}

impl Guards {
    /// The guard of `e`, if it has one.
    pub fn of(&self, e: EventId) -> Option<&Guard> {
        self.guards.iter().find(|(x, _)| *x == e).map(|(_, g)| g)
    }

    /// The kept variable for `var` of module `module`, if it is kept.
    pub fn module_index(&self, module: usize, var: usize) -> Option<usize> {
        self.variables.iter().position(|v| v.module == module && v.index == var)
    }

    /// The assignments event `e` makes to the kept variables, over their identifiers `names` (by kept
    /// index): `x := x + 1`. No action reads a variable the same event assigns ([`extract`]), so their
    /// order does not matter. Both program forms run them where the event happens.
    pub fn assignments(&self, e: EventId, names: &[String]) -> Vec<Stmt> {
        let mut out = Vec::new();
        for (v, name) in self.variables.iter().zip(names) {
            let Some((_, a)) = v.updates.iter().find(|(x, _)| *x == e) else { continue };
            let rhs = self.value(v.module, &a.value, names);
            let value = match a.op {
                AssignOp::Set => rhs,
                AssignOp::Add => ir::Expr::var(name).op(Op::Add, rhs),
                AssignOp::Sub => ir::Expr::var(name).op(Op::Sub, rhs),
            };
            out.push(Stmt::set(name, value));
        }
        out
    }

    /// An expression of module `module` over its variables, in the identifiers `names` (only kept
    /// variables' arithmetic reaches here, [`extract`]).
    fn value(&self, module: usize, e: &Expr, names: &[String]) -> ir::Expr {
        let operand = |x: &Expr| self.value(module, x, names);
        match e {
            Expr::Int(n) => ir::Expr::Int(*n),
            Expr::Var(i) => match self.module_index(module, *i) {
                Some(k) => ir::Expr::var(&names[k]),
                None => ir::Expr::Int(0),
            },
            Expr::Unary(UnaryOp::Neg, x) => ir::Expr::Int(0).op(Op::Sub, operand(x)),
            Expr::Binary(BinaryOp::Add, l, r) => operand(l).op(Op::Add, operand(r)),
            Expr::Binary(BinaryOp::Sub, l, r) => operand(l).op(Op::Sub, operand(r)),
            Expr::Binary(BinaryOp::Mul, l, r) => operand(l).op(Op::Mul, operand(r)),
            // Not kept by `extract`: never reached.
            Expr::Unary(..) | Expr::Binary(..) => ir::Expr::Int(0),
        }
    }
}

/// The variables of `modules` the program can keep, and the guards of the controllable events of `set`
/// (its supervisors synthesised from the modules' unfolding), as the module's documentation says.
pub fn extract(set: &PackSet, modules: &[Efa]) -> Guards {
    let variables = kept_variables(set, modules);
    if variables.is_empty() {
        return Guards::default();
    }
    let mut out = Guards { variables, ..Guards::default() };
    let Some(care) = care_sets(set, modules, &out) else {
        // The walk left a range or passed its bound: every event keeps the state tests.
        out.kept = care_events(set);
        out.variables.clear();
        return out;
    };
    for (e, (enabled, disabled)) in care {
        match separate(&out.variables, &enabled, &disabled) {
            Some(g) => out.guards.push((e, g)),
            None => out.kept.push(e),
        }
    }
    out
}

/// The controllable events some supervisor holds, by id.
fn care_events(set: &PackSet) -> Vec<EventId> {
    let events = set.events();
    events
        .ids()
        .filter(|&e| events.is_controllable(e))
        .filter(|&e| {
            set.members().iter().any(|m| m.role == Role::Supervisor && m.alphabet().binary_search(&e).is_ok())
        })
        .collect()
}

/// Whether `e` can be written as an `INT` statement: arithmetic over constants and the variables
/// `ok` accepts.
fn arithmetic(e: &Expr, ok: &dyn Fn(usize) -> bool) -> bool {
    match e {
        Expr::Int(n) => i16::try_from(*n).is_ok(),
        Expr::Var(v) => ok(*v),
        Expr::Unary(UnaryOp::Neg, x) => arithmetic(x, ok),
        Expr::Binary(BinaryOp::Add | BinaryOp::Sub | BinaryOp::Mul, l, r) => {
            arithmetic(l, ok) && arithmetic(r, ok)
        }
        _ => false,
    }
}

/// Per variable of each module, its update per event when it has one the same wherever the event is
/// taken (`None`: not kept), before checking that the expressions read kept variables only.
fn uniform_updates(set: &PackSet, efa: &Efa) -> Vec<Option<Vec<(EventId, Action)>>> {
    let mut out = Vec::new();
    for (v, var) in efa.variables.iter().enumerate() {
        let fits = i16::try_from(var.min).is_ok() && i16::try_from(var.max).is_ok();
        let writers: Vec<_> = efa
            .components
            .iter()
            .filter(|c| c.edges.iter().any(|e| e.actions.iter().any(|a| a.var == v)))
            .collect();
        let mut updates = Vec::new();
        let mut uniform = fits;
        for (e, (name, _)) in efa.events.iter().enumerate() {
            let mut action: Option<&Action> = None;
            for c in writers.iter().filter(|c| c.alphabet.contains(&e)) {
                let mut carrying = c
                    .edges
                    .iter()
                    .filter(|edge| edge.events.contains(&e))
                    .map(|edge| edge.actions.iter().filter(|a| a.var == v).collect::<Vec<&Action>>());
                let Some(first) = carrying.next() else { continue };
                if carrying.any(|other| other != first) || first.len() > 1 {
                    uniform = false;
                }
                match (action, first.first()) {
                    (Some(a), Some(b)) if a != *b => uniform = false,
                    (None, Some(b)) => action = Some(b),
                    _ => {}
                }
            }
            if let Some(a) = action {
                // An event the set does not have never happens in it.
                if let Some(id) = set.events().id(name) {
                    updates.push((id, a.clone()));
                }
            }
        }
        out.push(uniform.then_some(updates));
    }
    out
}

/// The variables of `modules` kept: uniform updates whose expressions read kept variables only (a
/// fixpoint: dropping one may drop those that read it).
fn kept_variables(set: &PackSet, modules: &[Efa]) -> Vec<Variable> {
    let mut out = Vec::new();
    for (m, efa) in modules.iter().enumerate() {
        let mut updates = uniform_updates(set, efa);
        loop {
            let keep: Vec<bool> = updates.iter().map(Option::is_some).collect();
            let mut changed = false;
            // An action reading a variable the same event assigns would see the new value in a PLC,
            // which assigns one after the other: such a variable is not kept.
            let assigned =
                |e: EventId, x: usize| updates[x].as_ref().is_some_and(|u| u.iter().any(|(y, _)| *y == e));
            let drop: Vec<bool> = (0..updates.len())
                .map(|v| {
                    updates[v].as_ref().is_some_and(|u| {
                        u.iter().any(|(e, a)| {
                            let ok = |x: usize| keep[x] && (x == v || !assigned(*e, x));
                            !arithmetic(&a.value, &ok)
                        })
                    })
                })
                .collect();
            for (u, drop) in updates.iter_mut().zip(drop) {
                if drop {
                    *u = None;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        for (v, u) in updates.into_iter().enumerate() {
            let Some(updates) = u else { continue };
            out.push(Variable { declared: efa.variables[v].clone(), updates, module: m, index: v });
        }
    }
    out
}

/// The kept variables' values after `e` from `values`, each action computed from the values before
/// (`None`: an action has no value or leaves its range).
pub fn step(guards: &Guards, modules: &[Efa], values: &[i64], e: EventId) -> Option<Vec<i64>> {
    let mut next = values.to_vec();
    for (k, var) in guards.variables.iter().enumerate() {
        let Some((_, action)) = var.updates.iter().find(|(x, _)| *x == e) else { continue };
        // The module's values, its unkept variables at their initial values (no kept action reads them).
        let env: Vec<i64> = modules[var.module]
            .variables
            .iter()
            .enumerate()
            .map(|(i, v)| guards.module_index(var.module, i).map_or(v.initial, |j| values[j]))
            .collect();
        let x = action.apply(&env)?;
        if x < var.declared.min || x > var.declared.max {
            return None;
        }
        next[k] = x;
    }
    Some(next)
}

/// The valuations of the kept variables where an event is allowed, and where it is forbidden.
type CareSet = (BTreeSet<Vec<i64>>, BTreeSet<Vec<i64>>);

/// Per controllable event a supervisor holds, the valuations of the kept variables where the plants
/// allow it and the supervisors allow it (first) or one forbids it (second), over the reachable closed
/// loop; `None` when the walk leaves a range or passes [`MAX_CONFIGURATIONS`].
fn care_sets(set: &PackSet, modules: &[Efa], guards: &Guards) -> Option<Vec<(EventId, CareSet)>> {
    let members = set.members();
    let events = set.events();
    let alphabets: Vec<Vec<EventId>> = members.iter().map(|m| m.alphabet()).collect();
    let holders: Vec<Vec<usize>> = events
        .ids()
        .map(|e| (0..members.len()).filter(|&a| alphabets[a].binary_search(&e).is_ok()).collect())
        .collect();
    let holders = |e: EventId| holders[e.index()].iter().copied();
    let mut care: Vec<(EventId, CareSet)> =
        care_events(set).into_iter().map(|e| (e, Default::default())).collect();
    let first: (Vec<usize>, Vec<i64>) = (
        members.iter().map(|m| m.initial().index()).collect(),
        guards.variables.iter().map(|v| v.declared.initial).collect(),
    );
    let mut seen = HashMap::from([(first.clone(), ())]);
    let mut queue = VecDeque::from([first]);
    while let Some((states, values)) = queue.pop_front() {
        let next_state =
            |a: usize, e: EventId| members[a].out(states[a]).find(|(x, _)| *x == e).map(|(_, t)| t);
        for (e, (enabled, disabled)) in &mut care {
            let plants =
                holders(*e).filter(|&a| members[a].role == Role::Plant).all(|a| next_state(a, *e).is_some());
            if plants {
                let sups = holders(*e).all(|a| next_state(a, *e).is_some());
                if sups { enabled } else { disabled }.insert(values.clone());
            }
        }
        for e in events.ids() {
            let Some(next) = holders(e)
                .map(|a| next_state(a, e).map(|t| (a, t.index())))
                .collect::<Option<Vec<(usize, usize)>>>()
            else {
                continue;
            };
            let mut s = states.clone();
            for (a, t) in next {
                s[a] = t;
            }
            let key = (s, step(guards, modules, &values, e)?);
            if !seen.contains_key(&key) {
                if seen.len() >= MAX_CONFIGURATIONS {
                    return None;
                }
                seen.insert(key.clone(), ());
                queue.push_back(key);
            }
        }
    }
    Some(care)
}

/// The guard that holds on `enabled` and fails on `disabled`, simplified as the module's documentation
/// says; `None` when the two meet.
fn separate(
    variables: &[Variable],
    enabled: &BTreeSet<Vec<i64>>,
    disabled: &BTreeSet<Vec<i64>>,
) -> Option<Guard> {
    if disabled.is_empty() {
        return Some(Guard { terms: vec![Vec::new()] });
    }
    if enabled.is_empty() {
        return Some(Guard { terms: Vec::new() });
    }
    if !enabled.is_disjoint(disabled) {
        return None;
    }
    for (k, var) in variables.iter().enumerate() {
        let on: BTreeSet<i64> = enabled.iter().map(|v| v[k]).collect();
        let off: BTreeSet<i64> = disabled.iter().map(|v| v[k]).collect();
        if !on.is_disjoint(&off) {
            continue;
        }
        // Runs of the range free of `off`, kept when they hold a value of `on`.
        let mut terms = Vec::new();
        let mut lo = var.declared.min;
        let mut cuts: Vec<i64> = off.iter().copied().collect();
        cuts.push(var.declared.max + 1);
        for cut in cuts {
            if lo < cut && on.range(lo..cut).next().is_some() {
                let bound = Bound {
                    var: k,
                    lo: (lo > var.declared.min).then_some(lo),
                    hi: (cut - 1 < var.declared.max).then_some(cut - 1),
                };
                terms.push(vec![bound]);
            }
            lo = cut + 1;
        }
        return Some(Guard { terms });
    }
    let terms = enabled
        .iter()
        .map(|v| v.iter().enumerate().map(|(k, &x)| Bound { var: k, lo: Some(x), hi: Some(x) }).collect())
        .collect();
    Some(Guard { terms })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use proptest::prelude::*;

    use super::*;
    use crate::formats::efa::{unfold, Component, Edge, Variable as EfaVariable};
    use crate::model::{Automaton, Kind};
    use crate::synth::{monolithic, Config};

    /// The value of `var` in a state of an unfolded automaton, read off its name (`…var=value…`, the
    /// unfolding's documented naming); `None` if the automaton does not hold the variable.
    fn value_in(a: &Automaton, s: usize, var: &str) -> Option<i64> {
        a.states[s].name.split('.').find_map(|part| part.strip_prefix(&format!("{var}="))?.parse().ok())
    }

    /// The brute-force check: walks the closed loop of `set` in step with the unfolded automata
    /// `unfolded` (which accept every string the supervisors allow), takes each kept variable's value
    /// from the unfolded state that holds it, and asserts at every reachable configuration that the
    /// program's variables (updated by [`step`]) have those values and that each guard is the explicit
    /// enablement by the supervisors wherever the plants allow the event. Returns the configurations seen.
    fn check(set: &PackSet, modules: &[Efa], unfolded: &[Automaton], g: &Guards) -> usize {
        let members = set.members();
        let events = set.events();
        let holds = |alphabet: &[EventId], e| alphabet.binary_search(&e).is_ok();
        let alphabets: Vec<Vec<EventId>> = members.iter().map(|m| m.alphabet()).collect();
        type Config = (Vec<usize>, Vec<usize>, Vec<i64>);
        let first: Config = (
            members.iter().map(|m| m.initial().index()).collect(),
            unfolded.iter().map(|a| a.initial.map_or(0, |s| s.index())).collect(),
            g.variables.iter().map(|v| v.declared.initial).collect(),
        );
        let mut seen = std::collections::HashSet::from([first.clone()]);
        let mut queue = vec![first];
        while let Some((states, ustates, values)) = queue.pop() {
            for (k, v) in g.variables.iter().enumerate() {
                let reference =
                    unfolded.iter().zip(&ustates).find_map(|(a, &s)| value_in(a, s, &v.declared.name));
                assert_eq!(reference, Some(values[k]), "variable {} at {states:?}", v.declared.name);
            }
            let next = |a: usize, e: EventId| {
                members[a].out(states[a]).find(|(x, _)| *x == e).map(|(_, t)| t.index())
            };
            for (e, guard) in &g.guards {
                let holders = || (0..members.len()).filter(|&a| holds(&alphabets[a], *e));
                let plants =
                    holders().filter(|&a| members[a].role == Role::Plant).all(|a| next(a, *e).is_some());
                if plants {
                    let sups = holders().all(|a| next(a, *e).is_some());
                    assert_eq!(guard.holds(&values), sups, "{} at {states:?} {values:?}", events.name(*e));
                }
            }
            for e in events.ids() {
                let Some(moves) = (0..members.len())
                    .filter(|&a| holds(&alphabets[a], e))
                    .map(|a| next(a, e).map(|t| (a, t)))
                    .collect::<Option<Vec<_>>>()
                else {
                    continue;
                };
                let mut s = states.clone();
                moves.into_iter().for_each(|(a, t)| s[a] = t);
                let mut u = ustates.clone();
                for (i, a) in unfolded.iter().enumerate() {
                    let Some(id) = a.event_id(events.name(e)) else { continue };
                    let t = a.transitions.iter().find(|t| t.source.index() == u[i] && t.event == id);
                    u[i] = t.expect("the unfolded automata accept the closed loop").target.index();
                }
                let key = (s, u, step(g, modules, &values, e).expect("values stay in range"));
                if seen.insert(key.clone()) {
                    queue.push(key);
                }
            }
        }
        seen.len()
    }

    /// Synthesises the monolithic supervisor of `efa`'s unfolding; `None` when the unfolding is refused
    /// or the supervisor is empty.
    fn closed_loop(efa: &Efa) -> Option<(PackSet, Vec<Automaton>)> {
        let unfolded = unfold(Path::new("m.wmod"), efa).ok()?;
        let plants: Vec<Automaton> = unfolded.iter().filter(|a| a.kind == Kind::Plant).cloned().collect();
        let specs: Vec<Automaton> = unfolded.iter().filter(|a| a.kind == Kind::Spec).cloned().collect();
        let sup = monolithic(&plants, &specs, &Config::default()).ok()?;
        if sup.automaton.states.is_empty() {
            return None;
        }
        Some((PackSet::new(plants, vec![sup.automaton]).ok()?, unfolded))
    }

    #[test]
    fn the_buffer_comes_back_as_bounds_on_its_count() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/efa/buffer.wmod");
        let efa = crate::formats::read_efa_path(&file).unwrap().unwrap();
        let (set, unfolded) = closed_loop(&efa).unwrap();
        let g = extract(&set, std::slice::from_ref(&efa));
        let texts: Vec<(&str, String)> =
            g.guards.iter().map(|(e, x)| (set.events().name(*e), x.text(&g.variables))).collect();
        assert_eq!(texts, [("start1", "n <= 1".to_owned()), ("start2", "n >= 1".to_owned())]);
        assert!(g.kept.is_empty());
        assert_eq!(check(&set, std::slice::from_ref(&efa), &unfolded, &g), 10);
    }

    #[test]
    fn a_variable_two_edges_update_differently_is_not_kept() {
        // `a` adds one from q0 and sets zero from q1: its update depends on the state.
        let x = EfaVariable { name: "x".into(), min: 0, max: 2, initial: 0, marked: None, line: 1 };
        let edge = |source, target, op, k| Edge {
            source,
            target,
            events: vec![0],
            guards: vec![],
            actions: vec![Action { var: 0, op, value: Expr::Int(k) }],
            line: 1,
        };
        let efa = Efa {
            events: vec![("a".into(), true)],
            variables: vec![x],
            components: vec![Component {
                name: "P".into(),
                kind: Kind::Plant,
                alphabet: vec![0],
                states: vec![("q0".into(), true), ("q1".into(), true)],
                initial: Some(0),
                edges: vec![edge(0, 1, AssignOp::Add, 1), edge(1, 0, AssignOp::Set, 0)],
                line: 1,
            }],
        };
        let (set, _) = closed_loop(&efa).unwrap();
        assert_eq!(extract(&set, &[efa]), Guards::default());
    }

    fn guard_strategy() -> impl Strategy<Value = Expr> {
        let op = prop_oneof![Just(BinaryOp::Eq), Just(BinaryOp::Ne), Just(BinaryOp::Lt), Just(BinaryOp::Gt)];
        (0..2usize, op, 0..3i64)
            .prop_map(|(v, op, k)| Expr::Binary(op, Box::new(Expr::Var(v)), Box::new(Expr::Int(k))))
    }

    /// A plant over `a` (controllable), `b` (uncontrollable), `c` (controllable) whose edges update
    /// `x` (0..3) and `y` (0..1) by one uniform action per event, and a specification guarding its
    /// edges with conditions on them, in states of its own.
    fn efa_strategy() -> impl Strategy<Value = Efa> {
        let op = prop_oneof![Just(AssignOp::Set), Just(AssignOp::Add), Just(AssignOp::Sub)];
        let action = prop::option::of((0..2usize, op, 0..3i64))
            .prop_map(|a| a.map(|(var, op, k)| Action { var, op, value: Expr::Int(k) }));
        let plant_edges = prop::collection::vec((0..2usize, 0..2usize, 0..3usize), 1..6);
        let spec_edges = prop::collection::vec((0..2usize, 0..2usize, 0..3usize, guard_strategy()), 1..6);
        (prop::collection::vec(action, 3), plant_edges, spec_edges, any::<[bool; 2]>()).prop_map(
            |(per_event, plant, spec, marks)| {
                let plant_edges = plant
                    .into_iter()
                    .map(|(source, target, e)| Edge {
                        source,
                        target,
                        events: vec![e],
                        guards: vec![],
                        actions: per_event[e].clone().into_iter().collect(),
                        line: 1,
                    })
                    .collect();
                let spec_edges = spec
                    .into_iter()
                    .map(|(source, target, e, g)| Edge {
                        source,
                        target,
                        events: vec![e],
                        guards: vec![g],
                        actions: vec![],
                        line: 1,
                    })
                    .collect();
                let comp = |name: &str, kind, edges| Component {
                    name: name.into(),
                    kind,
                    alphabet: vec![0, 1, 2],
                    states: vec![("p".into(), marks[0]), ("q".into(), true)],
                    initial: Some(0),
                    edges,
                    line: 1,
                };
                let var = |name: &str, max| EfaVariable {
                    name: name.into(),
                    min: 0,
                    max,
                    initial: 0,
                    marked: None,
                    line: 1,
                };
                Efa {
                    events: vec![("a".into(), true), ("b".into(), false), ("c".into(), true)],
                    variables: vec![var("x", 3), var("y", 1)],
                    components: vec![
                        comp("P", Kind::Plant, plant_edges),
                        Component {
                            states: vec![("s".into(), true), ("t".into(), marks[1])],
                            ..comp("S", Kind::Spec, spec_edges)
                        },
                    ],
                }
            },
        )
    }

    #[test]
    fn guards_are_the_supervisors_enablement_on_every_reachable_configuration() {
        let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig {
            failure_persistence: None,
            ..ProptestConfig::with_cases(128)
        });
        // How many cases had a supervisor, and how many a guard: the property is not vacuous.
        let (supervised, guarded) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
        runner
            .run(&efa_strategy(), |efa| {
                let Some((set, unfolded)) = closed_loop(&efa) else { return Ok(()) };
                let g = extract(&set, std::slice::from_ref(&efa));
                // Every variable the plant updates by one action per event is kept, and every
                // controllable event the supervisor holds is either guarded or kept on its states.
                prop_assert_eq!(g.variables.len(), 2);
                let mut decided: Vec<EventId> =
                    g.guards.iter().map(|(e, _)| *e).chain(g.kept.iter().copied()).collect();
                decided.sort_unstable();
                prop_assert_eq!(decided, care_events(&set));
                check(&set, std::slice::from_ref(&efa), &unfolded, &g);
                supervised.set(supervised.get() + 1);
                guarded.set(guarded.get() + usize::from(!g.guards.is_empty()));
                Ok(())
            })
            .unwrap();
        let (supervised, guarded) = (supervised.get(), guarded.get());
        assert!(supervised >= 32 && guarded >= 16, "{supervised} supervised, {guarded} guarded of 128");
    }
}
