//! Unfolds the variables of an [`Efa`] into plain automata, exactly (the semantics is in
//! [`super`]'s documentation).

use std::collections::{HashMap, VecDeque};
use std::path::Path;

use super::{Component, Edge, Efa};
use crate::formats::builder::Builder;
use crate::formats::ParseError;
use crate::model::{Automaton, Kind};

/// The most states one unfolded automaton may have: a larger product is refused, not built.
pub const MAX_STATES: usize = 1 << 20;

/// The plain automata of `efa` (read from `file`, for messages): one per set of components linked by
/// shared variables, in the order of each set's first component, named after its components joined by
/// `||`, with states named `state.state.var=value…`; a component that touches no variable is kept as
/// it is (all its states), and a variable no component touches becomes a one-state automaton (its
/// initial value may be unmarked).
///
/// Fails when components of different kinds share a variable, when an event is nondeterministic in
/// the product (two edges whose guards both hold lead to different states), or when a product passes
/// [`MAX_STATES`].
pub fn unfold(file: &Path, efa: &Efa) -> Result<Vec<Automaton>, ParseError> {
    let n = efa.components.len();
    let vars: Vec<Vec<usize>> = efa.components.iter().map(Component::variables).collect();
    let mut parent: Vec<usize> = (0..n).collect();
    let mut owner: Vec<Option<usize>> = vec![None; efa.variables.len()];
    for (c, vs) in vars.iter().enumerate() {
        for &v in vs {
            match owner.get(v).copied().flatten() {
                Some(o) => {
                    let (a, b) = (find(&mut parent, o), find(&mut parent, c));
                    parent[a.max(b)] = a.min(b);
                }
                None => owner[v] = Some(c),
            }
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
        let members: Vec<usize> = (c..n).filter(|&m| find(&mut parent, m) == root).collect();
        let mut group_vars: Vec<usize> = members.iter().flat_map(|&m| vars[m].iter().copied()).collect();
        group_vars.sort_unstable();
        group_vars.dedup();
        let comp = &efa.components[c];
        let plain =
            members.len() == 1 && comp.edges.iter().all(|e| e.guards.is_empty() && e.actions.is_empty());
        out.push(if plain { copy(file, efa, comp)? } else { product(file, efa, &members, &group_vars)? });
    }
    for (v, _) in owner.iter().enumerate().filter(|(_, o)| o.is_none()) {
        out.push(product(file, efa, &[], &[v])?);
    }
    Ok(out)
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
/// variables).
fn product(file: &Path, efa: &Efa, members: &[usize], vars: &[usize]) -> Result<Automaton, ParseError> {
    let comps: Vec<&Component> = members.iter().map(|&m| &efa.components[m]).collect();
    let line = comps.first().map_or_else(|| efa.variables[vars[0]].line, |c| c.line);
    let kind = kind(file, &comps)?;
    let name = if comps.is_empty() {
        efa.variables[vars[0]].name.clone()
    } else {
        comps.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join("||")
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
    let mut seen: HashMap<(Vec<usize>, Vec<i64>), _> = HashMap::new();
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
            let mut successor: Option<((Vec<usize>, Vec<i64>), usize)> = None;
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

/// The one role of `comps` (a plant when there is none: a lone variable).
fn kind(file: &Path, comps: &[&Component]) -> Result<Kind, ParseError> {
    let Some(first) = comps.first() else { return Ok(Kind::Plant) };
    match comps.iter().find(|c| c.kind != first.kind) {
        None => Ok(first.kind),
        Some(other) => Err(ParseError::unsupported(
            file,
            other.line,
            format!(
                "'{}' ({}) and '{}' ({}) share variables; variables shared by components of \
                 different kinds are not supported",
                first.name,
                first.kind.as_str(),
                other.name,
                other.kind.as_str()
            ),
        )),
    }
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
) -> Option<(Vec<usize>, Vec<i64>)> {
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
    key: &(Vec<usize>, Vec<i64>),
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
