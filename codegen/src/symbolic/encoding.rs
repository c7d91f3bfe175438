//! The symbolic encoding of a set of automata: each component's state as a group of binary BDD
//! variables, and the transition relation partitioned per event.
//!
//! Component `c` with `k` states takes `⌈log2 k⌉` bits, most significant first; each bit has a current
//! variable and, right after it, its next-state twin (interleaved, so renaming one into the other never
//! crosses a variable and a relation stays as small as its components). Components follow the order of
//! [`Order`](super::Order).
//!
//! The relation of event `e` is the conjunction, over the components holding `e`, of their local
//! relations `x_c = s ∧ x'_c = t` for each transition `s -e-> t`; the components not holding `e` keep
//! their state, and the relation does not mention them at all: an image quantifies and renames only
//! the holders' bits.

use std::collections::HashMap;

use biodivine_lib_bdd::{op_function, Bdd, BddValuation, BddVariable, BddVariableSet};
use num_bigint::BigUint;

use super::order::{component_order, Order};
use crate::model::Dfa;
use crate::synth::SynthError;

/// Most BDD variables the library holds (its variable ids are `u16`).
const MAX_VARIABLES: usize = u16::MAX as usize;

/// One component's bits.
pub(crate) struct Component {
    /// Current-state variables, most significant bit first.
    pub cur: Vec<BddVariable>,
    /// Next-state variables, in the same order.
    pub next: Vec<BddVariable>,
}

/// The relation of one event.
pub(crate) struct EventRelation {
    /// Global event id.
    pub event: u32,
    /// Whether the event is controllable.
    pub controllable: bool,
    /// Each holder (component index) with its local relation over its current and next bits.
    pub parts: Vec<(usize, Bdd)>,
    /// The conjunction of the parts.
    pub relation: Bdd,
    /// Whether each variable is a current bit of a holder (quantified by an image).
    cur_mask: Vec<bool>,
    /// Whether each variable is a next bit of a holder (quantified by a preimage).
    next_mask: Vec<bool>,
    /// The holders' next bits to their current ones.
    to_cur: HashMap<BddVariable, BddVariable>,
    /// The holders' current bits to their next ones.
    to_next: HashMap<BddVariable, BddVariable>,
}

/// A set of automata over one event table, encoded.
pub(crate) struct Space {
    /// The BDD variables (current and next bits, interleaved).
    pub vars: BddVariableSet,
    /// The components, in the order of the automata given (not the variable order).
    pub components: Vec<Component>,
    /// One relation per event of the union of the alphabets, ascending by global id.
    pub events: Vec<EventRelation>,
    /// The tuples of valid codes (each component's code below its state count).
    pub valid: Bdd,
    /// The tuples of marked states.
    pub marked: Bdd,
    /// The initial tuple; false when a component has no initial state.
    pub initial: Bdd,
    /// State bits of all components together.
    bits: usize,
}

/// Bits to number `states` states.
fn bits_for(states: usize) -> usize {
    (usize::BITS - states.saturating_sub(1).leading_zeros()) as usize
}

impl Space {
    /// Encodes `dfas` (over one event table whose controllable events `controllable` marks), its bits in
    /// the order `order` gives; `what` names the product in errors.
    pub(crate) fn new(
        dfas: &[&Dfa],
        controllable: &[bool],
        order: Order,
        what: &str,
    ) -> Result<Space, SynthError> {
        let bits: usize = dfas.iter().map(|d| bits_for(d.state_count())).sum();
        if 2 * bits > MAX_VARIABLES {
            return Err(SynthError::TooManyBits { what: what.to_owned(), bits, max: MAX_VARIABLES });
        }
        let vars = BddVariableSet::new_anonymous((2 * bits) as u16);
        let mut components: Vec<Component> =
            dfas.iter().map(|_| Component { cur: Vec::new(), next: Vec::new() }).collect();
        let mut at = 0;
        for c in component_order(dfas, order) {
            for _ in 0..bits_for(dfas[c].state_count()) {
                components[c].cur.push(BddVariable::from_index(at));
                components[c].next.push(BddVariable::from_index(at + 1));
                at += 2;
            }
        }
        let mut space = Space {
            valid: vars.mk_true(),
            marked: vars.mk_true(),
            initial: vars.mk_true(),
            vars,
            components,
            events: Vec::new(),
            bits,
        };
        for (c, d) in dfas.iter().enumerate() {
            let cur = &space.components[c].cur;
            let states: Vec<Bdd> = (0..d.state_count() as u32).map(|s| space.code(cur, s)).collect();
            let any = states.iter().fold(space.vars.mk_false(), |acc, s| acc.or(s));
            let marked = (0..d.state_count() as u32)
                .filter(|&s| d.is_marked(s))
                .fold(space.vars.mk_false(), |acc, s| acc.or(&states[s as usize]));
            let initial = d.initial().map_or_else(|| space.vars.mk_false(), |s| states[s as usize].clone());
            space.valid = space.valid.and(&any);
            space.marked = space.marked.and(&marked);
            space.initial = space.initial.and(&initial);
        }
        let mut union: Vec<u32> = dfas.iter().flat_map(|d| d.alphabet().iter().copied()).collect();
        union.sort_unstable();
        union.dedup();
        for e in union {
            let parts: Vec<(usize, Bdd)> = dfas
                .iter()
                .enumerate()
                .filter(|(_, d)| d.has_event(e))
                .map(|(c, d)| (c, space.local_relation(c, d, e)))
                .collect();
            let relation = parts.iter().fold(space.vars.mk_true(), |acc, (_, r)| acc.and(r));
            let n = space.vars.num_vars() as usize;
            let (mut cur_mask, mut next_mask) = (vec![false; n], vec![false; n]);
            let (mut to_cur, mut to_next) = (HashMap::new(), HashMap::new());
            for &(c, _) in &parts {
                let comp = &space.components[c];
                for (&x, &y) in comp.cur.iter().zip(&comp.next) {
                    cur_mask[x.to_index()] = true;
                    next_mask[y.to_index()] = true;
                    to_cur.insert(y, x);
                    to_next.insert(x, y);
                }
            }
            let controllable = controllable.get(e as usize).copied().unwrap_or(true);
            space.events.push(EventRelation {
                event: e,
                controllable,
                parts,
                relation,
                cur_mask,
                next_mask,
                to_cur,
                to_next,
            });
        }
        Ok(space)
    }

    /// The code of state `s` on the bits `bits` (most significant first).
    fn code(&self, bits: &[BddVariable], s: u32) -> Bdd {
        let width = bits.len();
        bits.iter().enumerate().fold(self.vars.mk_true(), |acc, (i, &v)| {
            acc.and(&self.vars.mk_literal(v, (s >> (width - 1 - i)) & 1 == 1))
        })
    }

    /// Component `c`'s (automaton `d`) transitions on event `e` over its current and next bits.
    fn local_relation(&self, c: usize, d: &Dfa, e: u32) -> Bdd {
        let comp = &self.components[c];
        (0..d.state_count() as u32)
            .filter_map(|s| d.step(s, e).map(|t| (s, t)))
            .fold(self.vars.mk_false(), |acc, (s, t)| {
                acc.or(&self.code(&comp.cur, s).and(&self.code(&comp.next, t)))
            })
    }

    /// The states reached from `set` by one `e` step.
    pub(crate) fn image(&self, e: &EventRelation, set: &Bdd) -> Bdd {
        let mask = &e.cur_mask;
        let mut out =
            Bdd::binary_op_with_exists_trigger(set, &e.relation, |v| mask[v.to_index()], op_function::and);
        // SAFETY (of the renaming, which the library checks and panics on rather than corrupt): the
        // holders' current bits were quantified away, and each next bit directly follows its current
        // twin, so moving a node from one to the other keeps the variable order.
        unsafe { out.rename_variables(&e.to_cur) };
        out
    }

    /// The states with an `e` step into `set`.
    pub(crate) fn preimage(&self, e: &EventRelation, set: &Bdd) -> Bdd {
        let mut primed = set.clone();
        // SAFETY (as in `image`): `set` is over current bits only, so the next twins are free, and each
        // follows its current bit directly.
        unsafe { primed.rename_variables(&e.to_next) };
        let mask = &e.next_mask;
        Bdd::binary_op_with_exists_trigger(&primed, &e.relation, |v| mask[v.to_index()], op_function::and)
    }

    /// The states where component `c` can take the step whose local relation is `part`.
    pub(crate) fn enabled(&self, part: &Bdd, c: usize) -> Bdd {
        part.exists(&self.components[c].next)
    }

    /// The number of states (tuples) in `set`, a set over the current bits.
    pub(crate) fn count(&self, set: &Bdd) -> BigUint {
        // The cardinality counts every assignment of the next bits too, which `set` leaves free.
        set.exact_cardinality() >> self.bits
    }

    /// The valuation of the current bits that encodes the tuple `states` (one state per component).
    pub(crate) fn valuation(&self, states: &[u32]) -> BddValuation {
        let mut valuation = BddValuation::all_false(self.vars.num_vars());
        for (c, &s) in states.iter().enumerate() {
            self.set_state(&mut valuation, c, s);
        }
        valuation
    }

    /// Sets component `c`'s bits of `valuation` to the code of state `s`.
    pub(crate) fn set_state(&self, valuation: &mut BddValuation, c: usize, s: u32) {
        let cur = &self.components[c].cur;
        let width = cur.len();
        for (i, &v) in cur.iter().enumerate() {
            valuation.set_value(v, (s >> (width - 1 - i)) & 1 == 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_number_the_states() {
        assert_eq!([1, 2, 3, 4, 5, 8, 9].map(bits_for), [0, 1, 2, 2, 3, 3, 4]);
    }
}
