//! The supremal controllable nonblocking sublanguage supC(G, K) with K = G ‖ E.
//!
//! The walk builds the reachable product of the plant components and the specification components (the
//! specification is thereby lifted to the plant alphabet: events it does not have are free). A product
//! state is bad when the plant can generate an uncontrollable event there that the specification refuses.
//! The fixpoint then alternates two removals until neither removes anything: bad states propagate backwards
//! along uncontrollable transitions (a state that can be pushed into a removed state by the plant is
//! removed), and states that can no longer reach a marked state are removed. What stays, restricted to its
//! accessible part, is the supervisor: controllable with respect to G, nonblocking and maximally permissive.

use crate::model::{Automaton, Kind};

use super::product::{tuple_name, Exploration, Options};
use super::reverse::Reverse;
use super::trim::{coaccessible_mask, restrict};
use super::{Config, Inputs, SynthError};
use crate::model::Dfa;

/// A supervisor as product states: the walk, the trim controllable part and each state's product id.
pub(crate) struct Synthesised {
    pub walk: Exploration,
    pub dfa: Dfa,
    pub product_ids: Vec<u32>,
}

/// supC of the plant components `plants` and the specification components `specs`.
pub(crate) fn supc_dfa(
    plants: &[&Dfa],
    specs: &[&Dfa],
    inputs: &Inputs,
    cfg: &Config,
    what: &str,
) -> Result<Synthesised, SynthError> {
    let components: Vec<&Dfa> = plants.iter().chain(specs).copied().collect();
    let walk = Exploration::run(
        &components,
        &inputs.controllable,
        Options { plants: plants.len(), parents: false },
        cfg,
        what,
    )?;
    let alive = controllable_nonblocking(&walk.dfa, walk.bad.iter().map(|&(s, _)| s), &inputs.controllable);
    let (dfa, product_ids) = restrict(&walk.dfa, &alive);
    Ok(Synthesised { walk, dfa, product_ids })
}

/// The largest set of states without `bad` states that is closed under uncontrollable transitions
/// (no uncontrollable transition leaves it) and in which every state reaches a marked state.
pub(crate) fn controllable_nonblocking(
    d: &Dfa,
    bad: impl Iterator<Item = u32>,
    controllable: &[bool],
) -> Vec<bool> {
    let rev = Reverse::new(d);
    let mut alive = vec![true; d.state_count()];
    let mut work: Vec<u32> = Vec::new();
    for s in bad {
        alive[s as usize] = false;
        work.push(s);
    }
    loop {
        while let Some(s) = work.pop() {
            for (p, e) in rev.preds(s) {
                if alive[p as usize] && !controllable[e as usize] {
                    alive[p as usize] = false;
                    work.push(p);
                }
            }
        }
        let co = coaccessible_mask(d, &rev, &alive);
        for s in 0..d.state_count() {
            if alive[s] && !co[s] {
                alive[s] = false;
                work.push(s as u32);
            }
        }
        if work.is_empty() {
            return alive;
        }
    }
}

/// supC(G, G ‖ E) for the plant `G = ‖ plants` and the specification `E = ‖ specs`.
///
/// The result is trim (empty when no nonblocking controllable behaviour exists), its alphabet is the
/// union of all alphabets and its states are named by the tuple of plant and specification states.
pub fn supc(plants: &[Automaton], specs: &[Automaton], cfg: &Config) -> Result<Automaton, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(specs))?;
    let (p, s) = inputs.dfas.split_at(plants.len());
    let names = |v: &[Automaton]| v.iter().map(|a| a.name.as_str()).collect::<Vec<_>>().join("||");
    let name = format!("supC({},{})", names(plants), names(specs));
    let r = supc_dfa(&p.iter().collect::<Vec<_>>(), &s.iter().collect::<Vec<_>>(), &inputs, cfg, &name)?;
    let sources: Vec<&Automaton> = plants.iter().chain(specs).collect();
    Ok(r.dfa.to_automaton(&name, Kind::Supervisor, &inputs.table, |q| {
        tuple_name(&r.walk, &sources, r.product_ids[q as usize])
    }))
}
