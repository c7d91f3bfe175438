//! The `[state]` section bound to a supervisor set's plants: per plant, the cube of each state and the
//! outputs each controllable event's command writes, checked against the automata, and the walk that
//! proves the state vectors consistent with the plant's transitions.

use crate::config::{Cube, Direction, Signals};
use crate::model::EventId;
use crate::pack::{PackSet, Role};

use super::FeedbackError;

/// The state vector of every plant of a set.
#[derive(Clone, Debug)]
pub struct Vector {
    /// The checked section.
    pub signals: Signals,
    /// Per plant (the set's first members, in order): its component in [`Signals::components`].
    pub component: Vec<usize>,
    /// Per plant, per local state: the state's formula.
    pub cubes: Vec<Vec<Cube>>,
    /// Per global event id: the plant whose command it is and the outputs it writes (controllable events
    /// of a plant only).
    pub commands: Vec<Option<(usize, Cube)>>,
    /// The signals' values in the initial state: the initial states' literals, every other signal FALSE.
    pub initial: u64,
}

fn err(key: String, message: impl Into<String>) -> FeedbackError {
    FeedbackError::Vector { key, message: message.into() }
}

impl Vector {
    /// Binds `signals` to the plants of `set`: every plant has a component and every component a plant,
    /// every state a formula and every formula a state, every controllable event of a plant a command
    /// (and no other event one); then walks each component's reachable (state, signal values) pairs and
    /// requires that every transition leads to values its target's formula reads as that target — a
    /// command by writing its outputs, a sensor event by the inputs its target's formula fixes.
    pub fn bind(set: &PackSet, signals: Signals) -> Result<Vector, FeedbackError> {
        let plants: Vec<_> = set.members().iter().filter(|m| m.role == Role::Plant).collect();
        let table = set.events();
        let mut component = Vec::new();
        let mut cubes = Vec::new();
        let mut commands = vec![None; table.len()];
        for (p, plant) in plants.iter().enumerate() {
            let a = &plant.automaton;
            let (c, comp) = signals.component(&a.name).ok_or_else(|| {
                err("state.components".into(), format!("plant {} has no state vector", a.name))
            })?;
            let key = format!("state.components.{}", a.name);
            let mut per_state = Vec::new();
            for s in &a.states {
                let cube = comp.states.get(&s.name).ok_or_else(|| {
                    err(format!("{key}.states"), format!("state {} has no formula", s.name))
                })?;
                per_state.push(*cube);
            }
            if let Some(extra) = comp.states.keys().find(|n| !a.states.iter().any(|s| &s.name == *n)) {
                return Err(err(format!("{key}.states.{extra}"), format!("{} has no state {extra}", a.name)));
            }
            for e in &a.events {
                let id = table.id(&e.name).map(EventId::index);
                match (comp.commands.get(&e.name), e.controllable, id) {
                    (Some(cube), true, Some(id)) => commands[id] = Some((p, *cube)),
                    (None, true, _) => {
                        return Err(err(
                            format!("{key}.commands"),
                            format!("controllable event {} has no command", e.name),
                        ))
                    }
                    (Some(_), false, _) => {
                        return Err(err(
                            format!("{key}.commands.{}", e.name),
                            "an uncontrollable event is no command",
                        ))
                    }
                    _ => {}
                }
            }
            if let Some(extra) = comp.commands.keys().find(|n| !a.events.iter().any(|e| &e.name == *n)) {
                return Err(err(
                    format!("{key}.commands.{extra}"),
                    format!("{} has no event {extra}", a.name),
                ));
            }
            component.push(c);
            cubes.push(per_state);
        }
        if let Some(c) =
            signals.components.iter().find(|c| !plants.iter().any(|p| p.automaton.name == c.name))
        {
            return Err(err(format!("state.components.{}", c.name), "no plant of the set has this name"));
        }
        let initial = plants.iter().zip(&cubes).fold(0, |v, (p, cs)| v | cs[p.initial().index()].value);
        let vector = Vector { signals, component, cubes, commands, initial };
        for p in 0..plants.len() {
            vector.walk(set, p)?;
        }
        Ok(vector)
    }

    /// What `event`'s command writes: its outputs, nothing for an event that is no command.
    pub fn command(&self, event: EventId) -> Cube {
        self.commands.get(event.index()).copied().flatten().map_or(Cube::default(), |(_, c)| c)
    }

    /// The input signals of plant `p`'s component.
    pub fn inputs(&self, p: usize) -> u64 {
        let c = self.component[p];
        self.signals
            .signals
            .iter()
            .enumerate()
            .filter(|(_, s)| s.component == c && s.direction == Direction::Input)
            .fold(0, |m, (i, _)| m | 1 << i)
    }

    /// The signal values after plant `p` takes `event` to local state `target` from values `v`.
    pub fn after(&self, p: usize, event: EventId, target: usize, v: u64) -> u64 {
        match self.commands.get(event.index()).copied().flatten() {
            Some((_, cmd)) => (v & !cmd.mask) | cmd.value,
            None => {
                let fixed = self.cubes[p][target].mask & self.inputs(p);
                (v & !fixed) | (self.cubes[p][target].value & fixed)
            }
        }
    }

    fn walk(&self, set: &PackSet, p: usize) -> Result<(), FeedbackError> {
        let plant = &set.members()[p];
        let name = &plant.automaton.name;
        let mut seen = std::collections::BTreeSet::new();
        let mut todo = vec![(plant.initial().index(), self.initial)];
        while let Some((s, v)) = todo.pop() {
            if !seen.insert((s, v)) {
                continue;
            }
            for (e, t) in plant.out(s) {
                let next = self.after(p, e, t.index(), v);
                if !self.cubes[p][t.index()].holds(next) {
                    let ev = set.events().name(e);
                    let target = &plant.automaton.states[t.index()].name;
                    let key = match self.commands[e.index()] {
                        Some(_) => format!("state.components.{name}.commands.{ev}"),
                        None => format!("state.components.{name}.states.{target}"),
                    };
                    let from = &plant.automaton.states[s].name;
                    return Err(err(
                        key,
                        format!(
                            "after {ev} from {from} the signals ({}) do not read as {target}",
                            self.show(next, p)
                        ),
                    ));
                }
                todo.push((t.index(), next));
            }
        }
        Ok(())
    }

    /// The values of plant `p`'s signals in `v`, as `NAME=0/1` words.
    pub fn show(&self, v: u64, p: usize) -> String {
        let c = self.component[p];
        let words: Vec<String> = self
            .signals
            .signals
            .iter()
            .enumerate()
            .filter(|(_, s)| s.component == c)
            .map(|(i, s)| format!("{}={}", s.name, v >> i & 1))
            .collect();
        words.join(" ")
    }

    /// The formula of plant state `x` (local states of the plants, in order): its components' cubes.
    pub fn cube(&self, x: &[u32]) -> Cube {
        x.iter().enumerate().fold(Cube::default(), |c, (p, &s)| {
            let k = self.cubes[p][s as usize];
            Cube { mask: c.mask | k.mask, value: c.value | k.value }
        })
    }
}
