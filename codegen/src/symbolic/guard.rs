//! Guards off the BDDs: the state feedback f of the monolithic supervisor read directly off the symbolic
//! engine's sets (as ESCET's data-based synthesis gives a guard per controllable event), so a
//! state-based program scales with the plant's structure, not with its product.
//!
//! With R the supervisor's reachable states (plant bits and specification bits) and pre_σ(R) the states
//! with a σ step into R, per controllable event σ some plant holds:
//!
//! - **allowed** (f_σ): the plant states x some state of R lies over and at which every such state
//!   enables σ — `∃y R(x, y) ∧ ¬∃y (R ∧ ¬pre_σ(R))(x, y)`, the definition of
//!   [`Sfbc`](crate::feedback::Sfbc) on the explicit closed loop;
//! - **memory**: the plant states over which one state of R enables σ and another does not (the
//!   supervisor's memory decides there; a state-based program without memory cannot be written).
//!
//! Both are sets over the plants' state bits only. [`Guards::to_signals`] rewrites such a set over the
//! signals of the plants' state vectors: each state bit becomes the disjunction of the formulas of the
//! states whose code has it set, node by node (the result's size follows the BDD's, not the number of
//! states it holds).

use biodivine_lib_bdd::{Bdd, BddPartialValuation, BddValuation, BddVariable, BddVariableSet};
use num_bigint::BigUint;

use super::encoding::Space;
use super::fixpoint::Walk;
use super::Options;
use crate::config::Cube;
use crate::model::{Automaton, Dfa, EventId};
use crate::synth::{Config, Inputs, SynthError};

/// The guard of one controllable event.
pub struct Guard {
    /// The event's name.
    pub event: String,
    /// The plant states where f_σ = 1, over the plants' state bits.
    pub allowed: Bdd,
    /// The plant states where the supervisor's memory decides σ.
    pub memory: Bdd,
}

/// The guards of the monolithic supervisor of a set of plants and specifications.
pub struct Guards {
    space: Space,
    plants: usize,
    /// The reachable plant states of the supervised plant, over the plants' state bits.
    pub reachable: Bdd,
    /// One guard per controllable event some plant holds, ascending by global event id.
    pub guards: Vec<Guard>,
}

impl Guards {
    /// Synthesises supC of `plants` and `specs` on BDDs and reads the guards off it.
    pub fn compute(
        plants: &[Automaton],
        specs: &[Automaton],
        cfg: &Config,
        options: &Options,
    ) -> Result<Guards, SynthError> {
        let name = "S_monolithic";
        let inputs = Inputs::new(plants.iter().chain(specs))?;
        let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
        let space = Space::new(&dfas, &inputs.controllable, options.order, name)?;
        let sup = Walk::new(&space, cfg, name).supc(plants.len())?;
        let specs_bits: Vec<BddVariable> =
            space.components[plants.len()..].iter().flat_map(|c| c.cur.iter().copied()).collect();
        let over_plants = |set: &Bdd| set.exists(&specs_bits);
        let reachable = over_plants(&sup);
        let guards = space
            .events
            .iter()
            .filter(|e| e.controllable && e.parts.iter().any(|&(c, _)| c < plants.len()))
            .map(|e| {
                let event = inputs.table.name(EventId::from_u32(e.event)).to_owned();
                cfg.stage(&format!("{name}: the guard of {event}"));
                let enables = space.preimage(e, &sup);
                let refused = over_plants(&sup.and_not(&enables));
                let granted = over_plants(&sup.and(&enables));
                Guard { event, allowed: reachable.and_not(&refused), memory: granted.and(&refused) }
            })
            .collect();
        Ok(Guards { space, plants: plants.len(), reachable, guards })
    }

    /// Whether the set `set` (over the plants' state bits) holds the plant state `states` (one local
    /// state index per plant, in the order given).
    pub fn holds(&self, set: &Bdd, states: &[u32]) -> bool {
        let mut valuation = BddValuation::all_false(self.space.vars.num_vars());
        for (c, &s) in states.iter().enumerate().take(self.plants) {
            self.space.set_state(&mut valuation, c, s);
        }
        set.eval_in(&valuation)
    }

    /// The number of plant states in `set` (over the plants' state bits), exactly.
    pub fn count(&self, set: &Bdd) -> BigUint {
        let plant_bits: usize = self.space.components[..self.plants].iter().map(|c| c.cur.len()).sum();
        set.exact_cardinality() >> (self.space.vars.num_vars() as usize - plant_bits)
    }

    /// `set` (over the plants' state bits) over `signals` signals, plant `p`'s state `s` being the
    /// valuations where `formulas[p][s]` holds: a valuation is in the result iff it reads as exactly one
    /// state per plant and that tuple is in `set`. The formulas of one plant's states are disjoint (the
    /// `[state]` section is checked so).
    pub fn to_signals(&self, set: &Bdd, formulas: &[Vec<Cube>], signals: usize) -> Bdd {
        let vars = BddVariableSet::new_anonymous(signals as u16);
        let cube = |c: Cube| {
            let values: Vec<(BddVariable, bool)> = c
                .literals()
                .filter(|&(i, _)| i < signals)
                .map(|(i, v)| (BddVariable::from_index(i), v))
                .collect();
            vars.mk_conjunctive_clause(&BddPartialValuation::from_values(&values))
        };
        // Per BDD variable, its function over the signals: a plant's state bit is the disjunction of the
        // formulas of the states whose code sets it; every other variable (the sets here never mention
        // one) reads FALSE.
        let mut bit = vec![vars.mk_false(); self.space.vars.num_vars() as usize];
        let mut readable = vars.mk_true();
        for (component, states) in self.space.components.iter().zip(formulas).take(self.plants) {
            let width = component.cur.len();
            for (i, v) in component.cur.iter().enumerate() {
                bit[v.to_index()] = states
                    .iter()
                    .enumerate()
                    .filter(|&(s, _)| (s >> (width - 1 - i)) & 1 == 1)
                    .fold(vars.mk_false(), |acc, (_, &c)| acc.or(&cube(c)));
            }
            readable = readable.and(&states.iter().fold(vars.mk_false(), |acc, &c| acc.or(&cube(c))));
        }
        // The nodes come children first: each node is if-then-else of its variable's function.
        let mut image: Vec<Bdd> = Vec::with_capacity(set.size());
        for node in set.pointers() {
            image.push(if node.is_zero() {
                vars.mk_false()
            } else if node.is_one() {
                vars.mk_true()
            } else {
                let (low, high) = (set.low_link_of(node), set.high_link_of(node));
                Bdd::if_then_else(
                    &bit[set.var_of(node).to_index()],
                    &image[high.to_index()],
                    &image[low.to_index()],
                )
            });
        }
        image.pop().unwrap_or_else(|| vars.mk_false()).and(&readable)
    }
}
