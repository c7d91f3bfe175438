//! Extended finite automata (Supremica's "EFA"): automata whose edges carry guards over bounded
//! integer variables and actions that update them, and their exact unfolding into plain automata.
//!
//! The semantics is the one Supremica and Waters give a module with variables: the module is the
//! synchronous product of its components and its variables. An event is enabled in a state when every
//! component with the event in its alphabet has an edge for it from its current state whose guards
//! all hold; it then moves every such component along that edge and performs all their actions at
//! once, each computed from the values before the event. A variable that no action names keeps its
//! value; an event whose actions give one variable two different values, or a value outside its
//! range, is blocked (Waters reads actions as constraints on the next values, and a set of
//! constraints with no solution allows no transition). An expression that overflows or divides by
//! zero has no value and the edge carrying it is not taken. A state is marked when every component's
//! state is marked and every variable's value satisfies its `:accepting` marking predicate (a variable
//! without one is marked at every value).
//!
//! [`unfold`] builds that product exactly, one plain automaton per set of components linked through
//! the variables they read or write (components touching no variable stay as they are), keeping only
//! the reachable states.

pub mod expr;
mod unfold;
pub(crate) mod wmod;

pub use unfold::{unfold, MAX_STATES};

use crate::model::Kind;
use expr::{Action, Expr};

/// A bounded integer variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variable {
    /// Its name, as guards and actions refer to it.
    pub name: String,
    /// The least value of its range.
    pub min: i64,
    /// The greatest value of its range.
    pub max: i64,
    /// Its initial value.
    pub initial: i64,
    /// The predicate over this variable that its marked values satisfy (`None`: every value).
    pub marked: Option<Expr>,
    /// Where it is declared (for messages).
    pub line: usize,
}

/// An edge of an EFA component.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The source state's index in [`Component::states`].
    pub source: usize,
    /// The target state's index.
    pub target: usize,
    /// The events labelling it, as indices into [`Efa::events`].
    pub events: Vec<usize>,
    /// Guards, all of which must hold.
    pub guards: Vec<Expr>,
    /// Actions, performed at once.
    pub actions: Vec<Action>,
    /// Where it is written (for messages).
    pub line: usize,
}

/// A component whose edges may carry guards and actions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Component {
    /// Its name.
    pub name: String,
    /// Its role.
    pub kind: Kind,
    /// Its alphabet, as indices into [`Efa::events`], in declaration order.
    pub alphabet: Vec<usize>,
    /// Its states: name and whether it is marked.
    pub states: Vec<(String, bool)>,
    /// The initial state's index (`None` for a component without states).
    pub initial: Option<usize>,
    /// Its edges.
    pub edges: Vec<Edge>,
    /// Where it is declared (for messages).
    pub line: usize,
}

impl Component {
    /// The index of every variable its guards and actions read or write, sorted, without repeats.
    pub fn variables(&self) -> Vec<usize> {
        let mut vars = Vec::new();
        for e in &self.edges {
            e.guards.iter().for_each(|g| g.visit_vars(&mut |v| vars.push(v)));
            for a in &e.actions {
                vars.push(a.var);
                a.value.visit_vars(&mut |v| vars.push(v));
            }
        }
        vars.sort_unstable();
        vars.dedup();
        vars
    }
}

/// A module with variables: events (name, controllable), variables and components.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Efa {
    /// The module's events: name and whether it is controllable.
    pub events: Vec<(String, bool)>,
    /// Its variables.
    pub variables: Vec<Variable>,
    /// Its components.
    pub components: Vec<Component>,
}
