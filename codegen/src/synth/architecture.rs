//! The three supervisor architectures: monolithic, modular and local modular.
//!
//! - **Monolithic**: one supervisor, supC of the whole plant and all specifications together.
//! - **Modular**: one supervisor per specification against the whole plant.
//! - **Local modular**: one supervisor per specification against its *local plant*, the product of the
//!   plant subsystems that share at least one event with it.
//!
//! Modular supervisors can conflict: each is nonblocking alone, yet together they may block. The conflict
//! check tests whether the product of all supervisors is nonblocking. When it fails, the smallest
//! conflicting group is searched (pairs of supervisors sharing events first, then triples, …), its
//! specifications are merged and synthesised together, and the check runs again until the set is
//! nonconflicting.

use std::collections::HashMap;

use crate::model::{Automaton, Kind};

use super::as_written::shares_event;
use super::product::tuple_name;
use super::supc::{supc_dfa, Synthesised};
use super::verify::first_blocking;
use super::{Config, Inputs, SynthError};
use crate::model::Dfa;

/// Conflict checks tried on subsets before giving up and merging every specification.
const SUBSET_CHECK_BUDGET: usize = 1000;

/// One synthesised supervisor with what it was built from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Supervisor {
    /// The supervisor (kind [`Kind::Supervisor`]), trim; states are named by (plant states, spec states).
    pub automaton: Automaton,
    /// Names of the specifications it enforces (more than one after a merge).
    pub specs: Vec<String>,
    /// Names of the plant subsystems of its (local) plant.
    pub plants: Vec<String>,
}

/// A set of modular or local modular supervisors and the conflict verdict.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LocalModularResult {
    /// One supervisor per specification group, in the order of each group's first specification.
    pub supervisors: Vec<Supervisor>,
    /// Whether the product of the supervisors is nonblocking. Always true when
    /// [`Config::merge_conflicting`] is set (merging continues until it is).
    pub nonconflicting: bool,
    /// The groups of specifications that had to be merged, each in input order.
    pub merged: Vec<Vec<String>>,
}

impl LocalModularResult {
    /// Sum of the supervisors' state counts.
    pub fn total_states(&self) -> usize {
        self.supervisors.iter().map(|s| s.automaton.states.len()).sum()
    }

    /// Sum of the supervisors' transition counts.
    pub fn total_transitions(&self) -> usize {
        self.supervisors.iter().map(|s| s.automaton.transitions.len()).sum()
    }
}

/// Name of the supervisor of a group of specifications: `E2`, `E6` give `S2_6`; names without the
/// `E` prefix are kept whole (`buffer1` gives `S_buffer1`).
fn supervisor_name(specs: &[&str]) -> String {
    let stripped: Option<Vec<&str>> =
        specs.iter().map(|s| s.strip_prefix('E').filter(|r| !r.is_empty())).collect();
    match stripped {
        Some(parts) => format!("S{}", parts.join("_")),
        None => format!("S_{}", specs.join("_")),
    }
}

/// Shared state of one modular or local modular run.
struct Run<'a> {
    plants: &'a [Automaton],
    specs: &'a [Automaton],
    inputs: Inputs,
    local: bool,
    cfg: &'a Config,
    cache: HashMap<Vec<usize>, (Vec<usize>, Synthesised)>,
}

impl Run<'_> {
    fn plant_dfa(&self, i: usize) -> &Dfa {
        &self.inputs.dfas[i]
    }

    fn spec_dfa(&self, j: usize) -> &Dfa {
        &self.inputs.dfas[self.plants.len() + j]
    }

    /// The plant subsystems of the group's plant: all of them, or (local) those sharing an event.
    fn plants_of(&self, group: &[usize]) -> Vec<usize> {
        (0..self.plants.len())
            .filter(|&i| {
                !self.local || group.iter().any(|&j| shares_event(self.plant_dfa(i), self.spec_dfa(j)))
            })
            .collect()
    }

    fn synthesise(&mut self, group: &[usize]) -> Result<(), SynthError> {
        if self.cache.contains_key(group) {
            return Ok(());
        }
        let names: Vec<&str> = group.iter().map(|&j| self.specs[j].name.as_str()).collect();
        let name = supervisor_name(&names);
        self.cfg.stage(&name);
        let plants = self.plants_of(group);
        let p: Vec<&Dfa> = plants.iter().map(|&i| self.plant_dfa(i)).collect();
        let s: Vec<&Dfa> = group.iter().map(|&j| self.spec_dfa(j)).collect();
        let r = supc_dfa(&p, &s, &self.inputs, self.cfg, &name)?;
        self.cache.insert(group.to_vec(), (plants, r));
        Ok(())
    }

    /// The verdict when the group's supervisor is empty: no supervisor exists, and why.
    fn exists(&self, group: &[usize]) -> Result<(), SynthError> {
        let (plants, r) = &self.cache[group];
        let sources: Vec<&Automaton> =
            plants.iter().map(|&i| &self.plants[i]).chain(group.iter().map(|&j| &self.specs[j])).collect();
        match r.no_supervisor(&self.inputs, &sources, plants.len()) {
            Some(verdict) => Err(SynthError::NoSupervisor(Box::new(verdict))),
            None => Ok(()),
        }
    }

    fn supervisor(&self, group: &[usize]) -> &Dfa {
        &self.cache[group].1.dfa
    }

    /// Whether the product of the groups' supervisors blocks, checked one independent subsystem at a
    /// time: supervisors that share no event, directly or through others, form independent products,
    /// and a product of independent nonempty automata is nonblocking exactly when each is. So the
    /// product of the whole set — the product of the subsystems' sizes — is never built.
    fn conflicting(&self, groups: &[&Vec<usize>]) -> Result<bool, SynthError> {
        let dfas: Vec<&Dfa> = groups.iter().map(|g| self.supervisor(g)).collect();
        if dfas.iter().any(|d| d.initial.is_none()) {
            // An empty supervisor empties the product: nothing reachable blocks.
            return Ok(false);
        }
        let parts = subsystems(&dfas);
        for (k, part) in parts.iter().enumerate() {
            let members: Vec<&Dfa> = part.iter().map(|&i| dfas[i]).collect();
            let what = if parts.len() == 1 {
                String::from("supervisor product")
            } else {
                format!("supervisor product, subsystem {} of {}", k + 1, parts.len())
            };
            if self.conflicting_product(&members, &what)? {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Whether the product of `dfas` blocks (explicitly, or by the configured engine).
    fn conflicting_product(&self, dfas: &[&Dfa], what: &str) -> Result<bool, SynthError> {
        let explicit = |cfg: &Config| first_blocking(dfas, &self.inputs, cfg, what).map(|(_, b)| b.is_some());
        let Some(check) = &self.cfg.nonblocking else { return explicit(self.cfg) };
        let first = check.explicit_states().min(self.cfg.state_limit);
        if first > 0 {
            match explicit(&Config { state_limit: first, ..self.cfg.clone() }) {
                Err(SynthError::StateLimit { .. }) => {}
                decided => return decided,
            }
        }
        check.nonblocking(dfas, self.cfg, what).map(|nonblocking| !nonblocking)
    }

    /// The smallest conflicting group of supervisors, searched by size (sets whose supervisors are not
    /// connected by shared events cannot conflict and are skipped); every group when the budget runs out.
    fn conflicting_group(&self, groups: &[Vec<usize>]) -> Result<Vec<usize>, SynthError> {
        let n = groups.len();
        let shares = |a: usize, b: usize| {
            let sb = self.supervisor(&groups[b]);
            self.supervisor(&groups[a]).alphabet.iter().any(|&e| sb.has_event(e))
        };
        let mut budget = SUBSET_CHECK_BUDGET;
        for k in 2..n {
            let mut subset: Vec<usize> = (0..k).collect();
            loop {
                if connected(&subset, &shares) {
                    if budget == 0 {
                        return Ok((0..n).collect());
                    }
                    budget -= 1;
                    let members: Vec<&Vec<usize>> = subset.iter().map(|&i| &groups[i]).collect();
                    if self.conflicting(&members)? {
                        return Ok(subset);
                    }
                }
                if !next_combination(&mut subset, n) {
                    break;
                }
            }
        }
        Ok((0..n).collect())
    }

    fn result(self, groups: Vec<Vec<usize>>, nonconflicting: bool) -> LocalModularResult {
        let merged = groups
            .iter()
            .filter(|g| g.len() > 1)
            .map(|g| g.iter().map(|&j| self.specs[j].name.clone()).collect())
            .collect();
        let supervisors = groups
            .iter()
            .map(|g| {
                let (plants, r) = &self.cache[g];
                let names: Vec<&str> = g.iter().map(|&j| self.specs[j].name.as_str()).collect();
                let sources: Vec<&Automaton> = plants
                    .iter()
                    .map(|&i| &self.plants[i])
                    .chain(g.iter().map(|&j| &self.specs[j]))
                    .collect();
                let automaton =
                    r.dfa.to_automaton(&supervisor_name(&names), Kind::Supervisor, &self.inputs.table, |q| {
                        tuple_name(&r.walk, &sources, r.product_ids[q as usize])
                    });
                Supervisor {
                    automaton,
                    specs: names.iter().map(|s| s.to_string()).collect(),
                    plants: plants.iter().map(|&i| self.plants[i].name.clone()).collect(),
                }
            })
            .collect();
        LocalModularResult { supervisors, nonconflicting, merged }
    }
}

/// The automata of `dfas` grouped into the components of the "shares an event" graph (indices, each
/// component ascending, components by their first member).
fn subsystems(dfas: &[&Dfa]) -> Vec<Vec<usize>> {
    let mut component = vec![usize::MAX; dfas.len()];
    let mut parts: Vec<Vec<usize>> = Vec::new();
    for start in 0..dfas.len() {
        if component[start] != usize::MAX {
            continue;
        }
        component[start] = parts.len();
        let mut part = vec![start];
        let mut k = 0;
        while k < part.len() {
            let a = dfas[part[k]];
            for j in 0..dfas.len() {
                if component[j] == usize::MAX && a.alphabet.iter().any(|&e| dfas[j].has_event(e)) {
                    component[j] = parts.len();
                    part.push(j);
                }
            }
            k += 1;
        }
        part.sort_unstable();
        parts.push(part);
    }
    parts
}

/// Whether the members of `subset` form one component of the "shares an event" graph.
fn connected(subset: &[usize], shares: &impl Fn(usize, usize) -> bool) -> bool {
    let mut reached = vec![false; subset.len()];
    reached[0] = true;
    let mut stack = vec![0];
    while let Some(i) = stack.pop() {
        for j in 0..subset.len() {
            if !reached[j] && shares(subset[i], subset[j]) {
                reached[j] = true;
                stack.push(j);
            }
        }
    }
    reached.iter().all(|&r| r)
}

/// Advances `c` to the next k-combination of 0..n in lexicographic order; false after the last.
fn next_combination(c: &mut [usize], n: usize) -> bool {
    let k = c.len();
    for i in (0..k).rev() {
        if c[i] < n - k + i {
            c[i] += 1;
            for j in i + 1..k {
                c[j] = c[j - 1] + 1;
            }
            return true;
        }
    }
    false
}

fn run(
    plants: &[Automaton],
    specs: &[Automaton],
    local: bool,
    cfg: &Config,
) -> Result<LocalModularResult, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(specs))?;
    let mut run = Run { plants, specs, inputs, local, cfg, cache: HashMap::new() };
    let mut groups: Vec<Vec<usize>> = (0..specs.len()).map(|j| vec![j]).collect();
    loop {
        for g in &groups {
            run.synthesise(g)?;
            run.exists(g)?;
        }
        let all: Vec<&Vec<usize>> = groups.iter().collect();
        cfg.stage("conflict check");
        if !run.conflicting(&all)? {
            return Ok(run.result(groups, true));
        }
        if !cfg.merge_conflicting {
            return Ok(run.result(groups, false));
        }
        let conflict = run.conflicting_group(&groups)?;
        let mut merged: Vec<usize> = conflict.iter().flat_map(|&i| groups[i].iter().copied()).collect();
        merged.sort_unstable();
        let first = conflict[0];
        groups[first] = merged;
        for &i in conflict[1..].iter().rev() {
            groups.remove(i);
        }
    }
}

/// Local modular synthesis: one supervisor per specification against its local plant (the plant
/// subsystems sharing an event with it), then the conflict check, merging conflicting specifications until
/// the set is nonconflicting (see [`Config::merge_conflicting`]). Stops with
/// [`SynthError::NoSupervisor`] when a specification (or a merged group) has none.
pub fn local_modular(
    plants: &[Automaton],
    specs: &[Automaton],
    cfg: &Config,
) -> Result<LocalModularResult, SynthError> {
    run(plants, specs, true, cfg)
}

/// Modular synthesis: one supervisor per specification against the whole plant, conflicts handled as in
/// [`local_modular`].
pub fn modular(
    plants: &[Automaton],
    specs: &[Automaton],
    cfg: &Config,
) -> Result<LocalModularResult, SynthError> {
    run(plants, specs, false, cfg)
}

/// Monolithic synthesis: one supervisor, supC of the product of all plants and all specifications;
/// [`SynthError::NoSupervisor`] when it is empty.
pub fn monolithic(plants: &[Automaton], specs: &[Automaton], cfg: &Config) -> Result<Supervisor, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(specs))?;
    let (p, s) = inputs.dfas.split_at(plants.len());
    cfg.stage("monolithic supervisor");
    let name = "S_monolithic";
    let r = supc_dfa(&p.iter().collect::<Vec<_>>(), &s.iter().collect::<Vec<_>>(), &inputs, cfg, name)?;
    let sources: Vec<&Automaton> = plants.iter().chain(specs).collect();
    if let Some(verdict) = r.no_supervisor(&inputs, &sources, plants.len()) {
        return Err(SynthError::NoSupervisor(Box::new(verdict)));
    }
    let automaton = r.dfa.to_automaton(name, Kind::Supervisor, &inputs.table, |q| {
        tuple_name(&r.walk, &sources, r.product_ids[q as usize])
    });
    Ok(Supervisor {
        automaton,
        specs: specs.iter().map(|a| a.name.clone()).collect(),
        plants: plants.iter().map(|a| a.name.clone()).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_follow_the_paper() {
        assert_eq!(supervisor_name(&["E1"]), "S1");
        assert_eq!(supervisor_name(&["E2", "E6"]), "S2_6");
        assert_eq!(supervisor_name(&["buffer", "E3"]), "S_buffer_E3");
    }

    #[test]
    fn subsystems_are_the_components_of_shared_events() {
        use crate::model::testing::build;
        let automata = [
            build("A", &["0"], &["a"], &[("0", "a", "0")]),
            build("B", &["0"], &["b"], &[("0", "b", "0")]),
            build("C", &["0"], &["a", "c"], &[("0", "a", "0"), ("0", "c", "0")]),
            build("D", &["0"], &["d"], &[("0", "d", "0")]),
            build("E", &["0"], &["c", "b"], &[("0", "c", "0"), ("0", "b", "0")]),
        ];
        let inputs = Inputs::new(automata.iter()).unwrap();
        let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
        assert_eq!(subsystems(&dfas), [vec![0, 1, 2, 4], vec![3]]);
    }

    #[test]
    fn combinations_are_enumerated_in_order() {
        let mut c = vec![0, 1];
        let mut all = vec![c.clone()];
        while next_combination(&mut c, 4) {
            all.push(c.clone());
        }
        assert_eq!(all, [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]);
    }
}
