//! Unfolds the variables of an [`Efa`] into plain automata, exactly (the semantics is in
//! [`super`]'s documentation).

use std::collections::{HashMap, VecDeque};
use std::path::Path;

use super::{Component, Edge, Efa};
use crate::formats::builder::Builder;
use crate::formats::ParseError;
use crate::model::{Automaton, Kind};

/// A state of an unfolded automaton: its components' states and its variables' values.
type Key = (Vec<usize>, Vec<i64>);

/// The most states one unfolded automaton may have: a larger product is refused, not built.
pub const MAX_STATES: usize = 1 << 20;

/// The plain automata of `efa` (read from `file`, for messages): one per set of components of one
/// kind linked by shared variables, in the order of each set's first component, named after its
/// components joined by `||`, with states named `state.state.var=value…`; a component that touches no
/// variable is kept as it is (all its states), and a variable no component touches becomes a one-state
/// automaton (its initial value may be unmarked).
///
/// Variables are the plant's (as in Waters, which compiles a variable into a plant automaton): a
/// specification may read in its guards a variable that plants read or write, and is then unfolded
/// together with those plants, so that it knows the values; its language is then the plants' language
/// cut by its guards, and the synchronous product with the plants is the module's. A specification
/// that assigns a variable a plant also reads or writes is refused (its action would change the
/// plant's behaviour, not restrict it).
///
/// Fails as just said, when components of two kinds other than plant share a variable, when an event
/// is nondeterministic in the product (two edges whose guards both hold lead to different states), or
/// when a product passes [`MAX_STATES`].
pub fn unfold(file: &Path, efa: &Efa) -> Result<Vec<Automaton>, ParseError> {
    let n = efa.components.len();
    let comps = &efa.components;
    let vars: Vec<Vec<usize>> = comps.iter().map(Component::variables).collect();
    let mut parent: Vec<usize> = (0..n).collect();
    // Per variable: the first component of each kind touching it.
    let mut owners: Vec<Vec<usize>> = vec![Vec::new(); efa.variables.len()];
    for (c, vs) in vars.iter().enumerate() {
        for &v in vs {
            match owners[v].iter().copied().find(|&o| comps[o].kind == comps[c].kind) {
                Some(o) => {
                    let (a, b) = (find(&mut parent, o), find(&mut parent, c));
                    parent[a.max(b)] = a.min(b);
                }
                None => owners[v].push(c),
            }
        }
    }
    for os in &owners {
        if let [a, .., b] =
            os.iter().copied().filter(|&o| comps[o].kind != Kind::Plant).collect::<Vec<_>>()[..]
        {
            return Err(mixed(file, &comps[a], &comps[b]));
        }
    }
    let mut out = Vec::new();
    let mut done = vec![false; n];
    for c in 0..n {
        let root = find(&mut parent, c);
        if done[root] {
            continue;
        }
        done[root] = true;
        let own: Vec<usize> = (c..n).filter(|&m| find(&mut parent, m) == root).collect();
        let mut members = own.clone();
        if comps[c].kind != Kind::Plant {
            for (&m, edge) in own.iter().flat_map(|m| comps[*m].edges.iter().map(move |e| (m, e))) {
                for v in edge.actions.iter().map(|a| a.var) {
                    if let Some(&p) = owners[v].iter().find(|&&o| comps[o].kind == Kind::Plant) {
                        return Err(ParseError::unsupported(
                            file,
                            edge.line,
                            format!(
                                "{} '{}' assigns '{}', a variable of plant '{}': a specification may \
                                 read the plant's variables in its guards, not assign them",
                                comps[m].kind.as_str(),
                                comps[m].name,
                                efa.variables[v].name,
                                comps[p].name
                            ),
                        ));
                    }
                }
            }
            // The plant groups whose variables it reads.
            let read: Vec<usize> = own.iter().flat_map(|&m| vars[m].iter().copied()).collect();
            let roots: Vec<usize> = read
                .iter()
                .flat_map(|&v| owners[v].iter().copied().filter(|&o| comps[o].kind == Kind::Plant))
                .map(|o| find(&mut parent, o))
                .collect();
            members.extend(
                (0..n).filter(|&m| comps[m].kind == Kind::Plant && roots.contains(&find(&mut parent, m))),
            );
            members.sort_unstable();
            members.dedup();
        }
        let mut group_vars: Vec<usize> = members.iter().flat_map(|&m| vars[m].iter().copied()).collect();
        group_vars.sort_unstable();
        group_vars.dedup();
        let comp = &comps[c];
        let plain =
            members.len() == 1 && comp.edges.iter().all(|e| e.guards.is_empty() && e.actions.is_empty());
        out.push(if plain {
            copy(file, efa, comp)?
        } else {
            product(file, efa, &members, &own, &group_vars)?
        });
    }
    for (v, _) in owners.iter().enumerate().filter(|(_, o)| o.is_empty()) {
        out.push(product(file, efa, &[], &[], &[v])?);
    }
    Ok(out)
}

/// The refusal of two components of different kinds, neither a plant, sharing a variable.
fn mixed(file: &Path, first: &Component, other: &Component) -> ParseError {
    ParseError::unsupported(
        file,
        other.line,
        format!(
            "'{}' ({}) and '{}' ({}) share variables; only a plant's variables may be read by \
             components of another kind",
            first.name,
            first.kind.as_str(),
            other.name,
            other.kind.as_str()
        ),
    )
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// A component without guards and actions, as the plain reader would give it.
fn copy(file: &Path, efa: &Efa, c: &Component) -> Result<Automaton, ParseError> {
    let mut b = Builder::new(file, c.name.clone(), c.kind);
    let mut ids = HashMap::new();
    for &e in &c.alphabet {
        let (name, controllable) = &efa.events[e];
        ids.insert(e, b.event(name, *controllable, c.line)?);
    }
    let states = c
        .states
        .iter()
        .map(|(name, marked)| b.state(name.clone(), *marked, c.line))
        .collect::<Result<Vec<_>, _>>()?;
    if let Some(i) = c.initial {
        b.initial(states[i], c.line)?;
    }
    for edge in &c.edges {
        for e in &edge.events {
            b.transition(states[edge.source], ids[e], states[edge.target], edge.line);
        }
    }
    b.finish()
}

/// The reachable product of `members` (indices into the components) and `vars` (indices into the
/// variables), of the kind of `own` (the members it is named after; the others are the plants whose
/// variables they read), or a plant named after its lone variable when there are no members.
fn product(
    file: &Path,
    efa: &Efa,
    members: &[usize],
    own: &[usize],
    vars: &[usize],
) -> Result<Automaton, ParseError> {
    let comps: Vec<&Component> = members.iter().map(|&m| &efa.components[m]).collect();
    let line = own.first().map_or_else(|| efa.variables[vars[0]].line, |&c| efa.components[c].line);
    let kind = own.first().map_or(Kind::Plant, |&c| efa.components[c].kind);
    let name = if own.is_empty() {
        efa.variables[vars[0]].name.clone()
    } else {
        own.iter().map(|&c| efa.components[c].name.as_str()).collect::<Vec<_>>().join("||")
    };
    let mut b = Builder::new(file, name.clone(), kind);
    let mut alphabet: Vec<usize> = comps.iter().flat_map(|c| c.alphabet.iter().copied()).collect();
    alphabet.sort_unstable();
    alphabet.dedup();
    // Per event of the alphabet: its id, and the members that hold it.
    let mut events = Vec::with_capacity(alphabet.len());
    for &e in &alphabet {
        let (ename, controllable) = &efa.events[e];
        let id = b.event(ename, *controllable, line)?;
        let holders: Vec<usize> = (0..comps.len()).filter(|&i| comps[i].alphabet.contains(&e)).collect();
        events.push((e, id, holders));
    }
    let Some(init) = comps.iter().map(|c| c.initial).collect::<Option<Vec<usize>>>() else {
        return b.finish();
    };
    let mut env: Vec<i64> = efa.variables.iter().map(|v| v.initial).collect();
    let values = |env: &[i64]| vars.iter().map(|&v| env[v]).collect::<Vec<i64>>();
    let key = (init, values(&env));
    let mut seen: HashMap<Key, _> = HashMap::new();
    let mut queue = VecDeque::new();
    let first = add_state(&mut b, efa, &comps, vars, &key, &mut env, line)?;
    b.initial(first, line)?;
    seen.insert(key.clone(), first);
    queue.push_back(key);
    while let Some((states, vals)) = queue.pop_front() {
        let source = seen[&(states.clone(), vals.clone())];
        for (&v, &x) in vars.iter().zip(&vals) {
            env[v] = x;
        }
        for (e, id, holders) in &events {
            // The edges of each holder enabled from its current state.
            let enabled: Vec<Vec<&Edge>> = holders
                .iter()
                .map(|&h| {
                    let c = comps[h];
                    c.edges
                        .iter()
                        .filter(|x| x.source == states[h] && x.events.contains(e))
                        .filter(|x| x.guards.iter().all(|g| g.holds(&env)))
                        .collect()
                })
                .collect();
            if enabled.iter().any(Vec::is_empty) {
                continue;
            }
            let mut successor: Option<(Key, usize)> = None;
            let mut pick = vec![0usize; holders.len()];
            loop {
                let chosen: Vec<&Edge> = pick.iter().zip(&enabled).map(|(&i, es)| es[i]).collect();
                if let Some(next) = step(efa, &states, &env, vars, holders, &chosen) {
                    let at = chosen.iter().map(|x| x.line).max().unwrap_or(line);
                    match &successor {
                        Some((other, _)) if *other != next => {
                            let here = state_name(efa, &comps, vars, &states, &env);
                            return Err(ParseError::syntax(
                                file,
                                at,
                                format!(
                                    "event '{}' is nondeterministic in '{name}' at '{here}': two edges \
                                     whose guards both hold lead to different states or values",
                                    efa.events[*e].0
                                ),
                            ));
                        }
                        Some(_) => {}
                        None => successor = Some((next, at)),
                    }
                }
                if !advance(&mut pick, &enabled) {
                    break;
                }
            }
            let Some((next, at)) = successor else { continue };
            let target = match seen.get(&next) {
                Some(&t) => t,
                None => {
                    if seen.len() >= MAX_STATES {
                        return Err(ParseError::unsupported(
                            file,
                            line,
                            format!("unfolding '{name}' passes {MAX_STATES} states"),
                        ));
                    }
                    let mut scratch = env.clone();
                    let t = add_state(&mut b, efa, &comps, vars, &next, &mut scratch, line)?;
                    seen.insert(next.clone(), t);
                    queue.push_back(next);
                    t
                }
            };
            b.transition(source, *id, target, at);
        }
    }
    b.finish()
}

/// The state (`states`, the values of `vars` after `chosen` edges are taken by `holders` from
/// `states` under `env`), or `None` when the actions have no value, clash, or leave a range.
fn step(
    efa: &Efa,
    states: &[usize],
    env: &[i64],
    vars: &[usize],
    holders: &[usize],
    chosen: &[&Edge],
) -> Option<Key> {
    let mut next_states = states.to_vec();
    let mut next: Vec<Option<i64>> = vec![None; vars.len()];
    for (&h, edge) in holders.iter().zip(chosen) {
        next_states[h] = edge.target;
        for a in &edge.actions {
            let value = a.apply(env)?;
            let var = &efa.variables[a.var];
            if value < var.min || value > var.max {
                return None;
            }
            let slot = vars.iter().position(|&v| v == a.var)?;
            match next[slot] {
                Some(other) if other != value => return None,
                _ => next[slot] = Some(value),
            }
        }
    }
    let values = vars.iter().zip(next).map(|(&v, x)| x.unwrap_or(env[v])).collect();
    Some((next_states, values))
}

/// Moves `pick` to the next combination of one edge per holder; `false` after the last.
fn advance(pick: &mut [usize], enabled: &[Vec<&Edge>]) -> bool {
    for (p, es) in pick.iter_mut().zip(enabled) {
        *p += 1;
        if *p < es.len() {
            return true;
        }
        *p = 0;
    }
    false
}

/// Adds the product state `key` (component states, values of `vars`) to `b`; `env` is scratch.
fn add_state(
    b: &mut Builder,
    efa: &Efa,
    comps: &[&Component],
    vars: &[usize],
    key: &Key,
    env: &mut [i64],
    line: usize,
) -> Result<crate::model::StateId, ParseError> {
    let (states, vals) = key;
    for (&v, &x) in vars.iter().zip(vals) {
        env[v] = x;
    }
    let marked = comps.iter().zip(states).all(|(c, &s)| c.states[s].1)
        && vars.iter().all(|&v| efa.variables[v].marked.as_ref().is_none_or(|m| m.holds(env)));
    b.state(state_name(efa, comps, vars, states, env), marked, line)
}

/// `state.state.var=value…`.
fn state_name(efa: &Efa, comps: &[&Component], vars: &[usize], states: &[usize], env: &[i64]) -> String {
    let parts = comps.iter().zip(states).map(|(c, &s)| c.states[s].0.clone());
    let values = vars.iter().map(|&v| format!("{}={}", efa.variables[v].name, env[v]));
    parts.chain(values).collect::<Vec<_>>().join(".")
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use proptest::prelude::*;

    use super::*;
    use crate::formats::efa::expr::{Action, AssignOp, BinaryOp, Expr};
    use crate::formats::efa::Variable;

    /// A configuration of the module: each component's state and every variable's value.
    type Config = (Vec<usize>, Vec<i64>);

    /// The brute-force reference: the configurations `event` leads to from `config`, by the semantics
    /// as documented (every holder takes an enabled edge, actions from the old values, a clash or a
    /// value out of range blocks), enumerating every choice of edges.
    fn successors(efa: &Efa, (states, env): &Config, event: usize) -> HashSet<Config> {
        let mut out = HashSet::new();
        let mut partial: Vec<(Vec<usize>, Vec<Option<i64>>)> =
            vec![(states.clone(), vec![None; efa.variables.len()])];
        for (i, c) in efa.components.iter().enumerate() {
            if !c.alphabet.contains(&event) {
                continue;
            }
            let mut next = Vec::new();
            for (s, assigned) in &partial {
                for e in c.edges.iter().filter(|e| e.source == states[i] && e.events.contains(&event)) {
                    if !e.guards.iter().all(|g| g.eval(env).is_some_and(|v| v != 0)) {
                        continue;
                    }
                    let mut s = s.clone();
                    let mut assigned = assigned.clone();
                    s[i] = e.target;
                    let ok = e.actions.iter().all(|a| {
                        let Some(v) = a.apply(env) else { return false };
                        let var = &efa.variables[a.var];
                        let fits = (var.min..=var.max).contains(&v);
                        let agrees = assigned[a.var].is_none_or(|w| w == v);
                        assigned[a.var] = Some(v);
                        fits && agrees
                    });
                    if ok {
                        next.push((s, assigned));
                    }
                }
            }
            partial = next;
        }
        for (s, assigned) in partial {
            let values = assigned.iter().zip(env).map(|(a, &v)| a.unwrap_or(v)).collect();
            out.insert((s, values));
        }
        out
    }

    fn marked(efa: &Efa, (states, env): &Config) -> bool {
        efa.components.iter().zip(states).all(|(c, &s)| c.states[s].1)
            && efa.variables.iter().all(|v| v.marked.as_ref().is_none_or(|m| m.holds(env)))
    }

    fn initial(efa: &Efa) -> Config {
        let states = efa.components.iter().map(|c| c.initial.unwrap_or(0)).collect();
        (states, efa.variables.iter().map(|v| v.initial).collect())
    }

    /// Whether some reachable configuration has an event with two successors.
    fn nondeterministic(efa: &Efa) -> bool {
        let mut seen = HashSet::from([initial(efa)]);
        let mut queue = vec![initial(efa)];
        while let Some(c) = queue.pop() {
            for e in 0..efa.events.len() {
                let next = successors(efa, &c, e);
                if next.len() > 1 {
                    return true;
                }
                for n in next {
                    if seen.insert(n.clone()) {
                        queue.push(n);
                    }
                }
            }
        }
        false
    }

    /// The module cut into sub-modules of components that share variables (transitively).
    fn groups(efa: &Efa) -> Vec<Efa> {
        let vars: Vec<Vec<usize>> = efa.components.iter().map(Component::variables).collect();
        let mut group: Vec<usize> = (0..vars.len()).collect();
        for _ in 0..vars.len() {
            for i in 0..vars.len() {
                for j in 0..vars.len() {
                    if vars[i].iter().any(|v| vars[j].contains(v)) {
                        let g = group[i].min(group[j]);
                        (group[i], group[j]) = (g, g);
                    }
                }
            }
        }
        let mut out: Vec<Efa> = Vec::new();
        for g in 0..vars.len() {
            let components: Vec<Component> =
                (0..vars.len()).filter(|&i| group[i] == g).map(|i| efa.components[i].clone()).collect();
            if !components.is_empty() {
                out.push(Efa { components, ..efa.clone() });
            }
        }
        out
    }

    fn plain_nondeterministic(c: &Component) -> bool {
        let plain = c.edges.iter().all(|e| e.guards.is_empty() && e.actions.is_empty());
        plain
            && c.edges.iter().any(|e| {
                c.edges.iter().any(|f| e.source == f.source && e.events == f.events && e.target != f.target)
            })
    }

    /// Runs `word` on the unfolded automata in parallel: `None` if it is blocked, else whether the
    /// end is marked.
    fn run(automata: &[Automaton], efa: &Efa, word: &[usize]) -> Option<bool> {
        let mut states: Vec<_> = automata.iter().map(|a| a.initial).collect::<Option<Vec<_>>>()?;
        for &e in word {
            let name = &efa.events[e].0;
            for (a, s) in automata.iter().zip(&mut states) {
                let Some(id) = a.event_id(name) else { continue };
                let t = a.transitions.iter().find(|t| t.source == *s && t.event == id)?;
                *s = t.target;
            }
        }
        Some(automata.iter().zip(&states).all(|(a, s)| a.states[s.index()].marked))
    }

    fn words(events: usize, max_len: usize) -> Vec<Vec<usize>> {
        let mut all = vec![vec![]];
        let mut frontier = vec![vec![]];
        for _ in 0..max_len {
            frontier = frontier
                .iter()
                .flat_map(|w: &Vec<usize>| {
                    (0..events).map(move |e| {
                        let mut w = w.clone();
                        w.push(e);
                        w
                    })
                })
                .collect();
            all.extend(frontier.iter().cloned());
        }
        all
    }

    fn expr_strategy() -> impl Strategy<Value = Expr> {
        let op = prop_oneof![Just(BinaryOp::Eq), Just(BinaryOp::Ne), Just(BinaryOp::Lt), Just(BinaryOp::Gt)];
        (0..2usize, op, 0..3i64)
            .prop_map(|(v, op, k)| Expr::Binary(op, Box::new(Expr::Var(v)), Box::new(Expr::Int(k))))
    }

    fn action_strategy() -> impl Strategy<Value = Action> {
        let op = prop_oneof![Just(AssignOp::Set), Just(AssignOp::Add), Just(AssignOp::Sub)];
        (0..2usize, op, 0..3i64).prop_map(|(var, op, k)| Action { var, op, value: Expr::Int(k) })
    }

    fn component_strategy(i: usize) -> impl Strategy<Value = Component> {
        (1..4usize, prop::collection::vec(any::<bool>(), 3), 1u8..8).prop_flat_map(
            move |(n, marks, alpha)| {
                let alphabet: Vec<usize> = (0..3).filter(|e| alpha & (1 << e) != 0).collect();
                let edge = (
                    0..n,
                    0..n,
                    prop::sample::select(alphabet.clone()),
                    prop::option::of(expr_strategy()),
                    prop::option::of(action_strategy()),
                )
                    .prop_map(|(source, target, e, g, a)| Edge {
                        source,
                        target,
                        events: vec![e],
                        guards: g.into_iter().collect(),
                        actions: a.into_iter().collect(),
                        line: 1,
                    });
                prop::collection::vec(edge, 0..6).prop_map(move |edges| Component {
                    name: format!("C{i}"),
                    kind: Kind::Plant,
                    alphabet: alphabet.clone(),
                    states: (0..n).map(|s| (format!("q{s}"), marks[s])).collect(),
                    initial: Some(0),
                    edges,
                    line: 1,
                })
            },
        )
    }

    fn efa_strategy() -> impl Strategy<Value = Efa> {
        let comps = (component_strategy(0), component_strategy(1), component_strategy(2), 1..4usize)
            .prop_map(|(a, b, c, n)| [a, b, c].into_iter().take(n).collect::<Vec<_>>());
        // A component may be a specification, which reads the variables and assigns none.
        let comps = (comps, any::<[bool; 3]>()).prop_map(|(mut comps, spec)| {
            for (c, spec) in comps.iter_mut().zip(spec) {
                if spec {
                    c.kind = Kind::Spec;
                    c.edges.iter_mut().for_each(|e| e.actions.clear());
                }
            }
            comps
        });
        (comps, any::<(bool, bool)>()).prop_map(|(components, (m0, m1))| {
            let var = |name: &str, max, marked: bool| Variable {
                name: name.into(),
                min: 0,
                max,
                initial: 0,
                marked: marked.then(|| {
                    Expr::Binary(
                        BinaryOp::Eq,
                        Box::new(Expr::Var(usize::from(name == "y"))),
                        Box::new(Expr::Int(0)),
                    )
                }),
                line: 1,
            };
            Efa {
                events: vec![("a".into(), true), ("b".into(), false), ("c".into(), true)],
                variables: vec![var("x", 2, m0), var("y", 1, m1)],
                components,
            }
        })
    }

    proptest! {
        #[test]
        fn unfolding_agrees_with_the_interpreter(efa in efa_strategy()) {
            let file = Path::new("random.wmod");
            match unfold(file, &efa) {
                // A component without guards and actions is kept whole, so nondeterminism in a state
                // it cannot reach is refused too, as the plain reader does.
                // Nondeterminism is judged in each unfolded automaton, whose components are linked by
                // variables: a choice that another automaton's components block is still refused.
                // A specification is unfolded with the plants whose variables it reads, and
                // nondeterminism is judged there too.
                Err(e) => prop_assert!(
                    groups(&efa).iter().any(nondeterministic)
                        || efa.components.iter().any(plain_nondeterministic)
                        || (efa.components.iter().any(|c| c.kind == Kind::Spec)
                            && e.to_string().contains("is nondeterministic in")),
                    "{e}"
                ),
                Ok(automata) => {
                    prop_assert!(!nondeterministic(&efa));
                    for a in &automata {
                        prop_assert_eq!(a.validate(), Ok(()));
                    }
                    for word in words(efa.events.len(), 5) {
                        let mut config = Some(initial(&efa));
                        for &e in &word {
                            config = config.and_then(|c| successors(&efa, &c, e).into_iter().next());
                        }
                        let expected = config.map(|c| marked(&efa, &c));
                        prop_assert_eq!(run(&automata, &efa, &word), expected, "{:?}", word);
                    }
                }
            }
        }
    }

    #[test]
    fn a_specification_reads_the_plants_variable_and_is_unfolded_with_the_plant() {
        // Plant M counts `go` in x (0..2); specification S allows `go` while x < 1.
        let edge = |guards, actions| Edge { source: 0, target: 0, events: vec![0], guards, actions, line: 1 };
        let comp = |name: &str, kind, edge| Component {
            name: name.into(),
            kind,
            alphabet: vec![0],
            states: vec![("q".into(), true)],
            initial: Some(0),
            edges: vec![edge],
            line: 1,
        };
        let count = Action { var: 0, op: AssignOp::Add, value: Expr::Int(1) };
        let below = Expr::Binary(BinaryOp::Lt, Box::new(Expr::Var(0)), Box::new(Expr::Int(1)));
        let x = Variable { name: "x".into(), min: 0, max: 2, initial: 0, marked: None, line: 1 };
        let efa = Efa {
            events: vec![("go".into(), true)],
            variables: vec![x],
            components: vec![
                comp("M", Kind::Plant, edge(vec![], vec![count])),
                comp("S", Kind::Spec, edge(vec![below], vec![])),
            ],
        };
        let a = unfold(Path::new("m"), &efa).unwrap();
        let figures: Vec<_> =
            a.iter().map(|a| (a.name.as_str(), a.kind, a.states.len(), a.transitions.len())).collect();
        assert_eq!(figures, [("M", Kind::Plant, 3, 2), ("S", Kind::Spec, 2, 1)]);
        assert_eq!(a[1].states[1].name, "q.q.x=1");
    }

    #[test]
    fn a_clash_of_two_actions_blocks_the_event() {
        let edge = |k| Edge {
            source: 0,
            target: 0,
            events: vec![0],
            guards: vec![],
            actions: vec![Action { var: 0, op: AssignOp::Set, value: Expr::Int(k) }],
            line: 1,
        };
        let comp = |name: &str, k| Component {
            name: name.into(),
            kind: Kind::Plant,
            alphabet: vec![0],
            states: vec![("q".into(), true)],
            initial: Some(0),
            edges: vec![edge(k)],
            line: 1,
        };
        let x = Variable { name: "x".into(), min: 0, max: 3, initial: 0, marked: None, line: 1 };
        let efa = Efa {
            events: vec![("e".into(), true)],
            variables: vec![x],
            components: vec![comp("A", 1), comp("B", 2)],
        };
        let a = unfold(Path::new("m"), &efa).unwrap();
        assert_eq!((a.len(), a[0].states.len(), a[0].transitions.len()), (1, 1, 0));
    }
}
