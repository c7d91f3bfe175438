//! The supremal controllable nonblocking sublanguage supC(G, K) with K = G ‖ E.
//!
//! The walk builds the reachable product of the plant components and the specification components (the
//! specification is thereby lifted to the plant alphabet: events it does not have are free). A product
//! state is bad when the plant can generate an uncontrollable event there that the specification refuses.
//! The fixpoint then alternates two removals until neither removes anything: bad states propagate backwards
//! along uncontrollable transitions (a state that can be pushed into a removed state by the plant is
//! removed), and states that can no longer reach a marked state are removed. What stays, restricted to its
//! accessible part, is the supervisor: controllable with respect to G, nonblocking and maximally permissive.
//!
//! When the initial state itself is removed no supervisor exists; [`Synthesised::no_supervisor`] says
//! why, with a shortest string of uncontrollable events from the initial state into a state the fixpoint
//! removed for a reason of its own (bad, or blocking) rather than for being pushed there.

use crate::model::{Automaton, EventId, Kind};

use super::product::{tuple_name, Exploration, Options};
use super::reverse::Reverse;
use super::trim::{coaccessible_mask, restrict};
use super::verify::{uncontrollable_path, Forbidden, NoSupervisor};
use super::{Config, Inputs, SynthError};
use crate::model::Dfa;

/// What the fixpoint did with a product state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Fate {
    /// Kept: part of the supervisor (when accessible).
    Kept,
    /// Removed: the plant generates an uncontrollable event there that the specification refuses.
    Bad,
    /// Removed: an uncontrollable event leads from it to a removed state.
    Pushed,
    /// Removed: no marked state can be reached from it through kept states.
    Blocking,
}

/// A supervisor as product states: the walk, the trim controllable part, each state's product id and
/// what the fixpoint did with every product state.
pub(crate) struct Synthesised {
    pub walk: Exploration,
    pub dfa: Dfa,
    pub product_ids: Vec<u32>,
    pub fate: Vec<Fate>,
}

impl Synthesised {
    /// When the supervisor is empty, why: a shortest string of uncontrollable events from the initial
    /// product state into a state removed as bad or blocking. `sources` are the plant then the
    /// specification components of the walk, named in the state tuple.
    pub(crate) fn no_supervisor(
        &self,
        inputs: &Inputs,
        sources: &[&Automaton],
        plants: usize,
    ) -> Option<NoSupervisor> {
        if self.dfa.state_count() > 0 {
            return None;
        }
        let names = |v: &[&Automaton]| v.iter().map(|a| a.name.clone()).collect::<Vec<_>>();
        let (plant_names, spec_names) = (names(&sources[..plants]), names(&sources[plants..]));
        let event = |e: u32| inputs.table.name(EventId::from_u32(e)).to_owned();
        let roots: Vec<bool> = self.fate.iter().map(|f| matches!(f, Fate::Bad | Fate::Blocking)).collect();
        let Some((path, end)) = uncontrollable_path(&self.walk.dfa, &inputs.controllable, &roots) else {
            // No initial state: an automaton of the set has no state at all.
            return Some(NoSupervisor {
                specs: spec_names,
                plants: plant_names,
                trace: Vec::new(),
                state: String::new(),
                forbidden: Forbidden::NoInitialState,
            });
        };
        let forbidden = match self.walk.bad.binary_search_by_key(&end, |&(s, _)| s) {
            Ok(i) => Forbidden::Refused { event: event(self.walk.bad[i].1) },
            Err(_) => Forbidden::Blocking,
        };
        Some(NoSupervisor {
            specs: spec_names,
            plants: plant_names,
            trace: path.into_iter().map(event).collect(),
            state: tuple_name(&self.walk, sources, end),
            forbidden,
        })
    }
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
    super::memory::admit(cfg, what, walk.dfa.state_count(), Reverse::bytes(&walk.dfa))?;
    let fate = controllable_nonblocking(&walk.dfa, walk.bad.iter().map(|&(s, _)| s), &inputs.controllable);
    let alive: Vec<bool> = fate.iter().map(|&f| f == Fate::Kept).collect();
    let (dfa, product_ids) = restrict(&walk.dfa, &alive);
    Ok(Synthesised { walk, dfa, product_ids, fate })
}

/// The largest set of states without `bad` states that is closed under uncontrollable transitions
/// (no uncontrollable transition leaves it) and in which every state reaches a marked state: the states
/// whose fate is [`Fate::Kept`]; every other state says why it was removed.
pub(crate) fn controllable_nonblocking(
    d: &Dfa,
    bad: impl Iterator<Item = u32>,
    controllable: &[bool],
) -> Vec<Fate> {
    let rev = Reverse::new(d);
    let mut alive = vec![true; d.state_count()];
    let mut fate = vec![Fate::Kept; d.state_count()];
    let mut work: Vec<u32> = Vec::new();
    for s in bad {
        alive[s as usize] = false;
        fate[s as usize] = Fate::Bad;
        work.push(s);
    }
    loop {
        while let Some(s) = work.pop() {
            for (p, e) in rev.preds(s) {
                if alive[p as usize] && !controllable[e as usize] {
                    alive[p as usize] = false;
                    fate[p as usize] = Fate::Pushed;
                    work.push(p);
                }
            }
        }
        let co = coaccessible_mask(d, &rev, &alive);
        for s in 0..d.state_count() {
            if alive[s] && !co[s] {
                alive[s] = false;
                fate[s] = Fate::Blocking;
                work.push(s as u32);
            }
        }
        if work.is_empty() {
            return fate;
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
