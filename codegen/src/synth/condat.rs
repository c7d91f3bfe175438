//! Control data (TCT `condat`): per supervisor state, the events it disables where the plant would allow
//! them — what a supervisor *does*, as opposed to the language it tracks.
//!
//! A supervisor state `x` disables `e` when, in some state of `plant ‖ supervisor` reached together with
//! `x`, the plant enables `e` (or lacks `e` altogether) and `x` has no `e` transition. Reduction
//! (`reduce`) merges states whose control data do not clash; [`condat`] reports the controllable part, as
//! TCT's condat lists it and as the hybrid controller turns it into inhibitor arcs.

use crate::model::{Automaton, Dfa, EventId};

use super::product::{Exploration, Options};
use super::{Config, Inputs, SynthError};

/// The control data of every supervisor state, as event bitsets over the global event ids.
pub(crate) struct ControlData {
    words: usize,
    enabled: Vec<u64>,
    disabled: Vec<u64>,
    /// Whether each supervisor state is marked.
    pub(crate) marked: Vec<bool>,
    /// Whether each supervisor state is reached together with a marked plant state.
    pub(crate) plant_marked: Vec<bool>,
}

impl ControlData {
    /// The control data of `sup` against the plant `‖ plants`, from one walk of their product.
    pub(crate) fn new(plants: &[&Dfa], sup: &Dfa, inputs: &Inputs, cfg: &Config) -> Result<Self, SynthError> {
        let n = sup.state_count();
        let words = inputs.table.len().div_ceil(64).max(1);
        let mut enabled = vec![0u64; n * words];
        let mut disabled = vec![0u64; n * words];
        for x in 0..n as u32 {
            for (e, _) in sup.edges(x) {
                enabled[x as usize * words + e as usize / 64] |= 1 << (e % 64);
            }
        }
        let mut components: Vec<&Dfa> = plants.to_vec();
        components.push(sup);
        let walk = Exploration::run(
            &components,
            &inputs.controllable,
            Options { plants: components.len(), parents: false },
            cfg,
            "plant || supervisor",
        )?;
        let mut plant_marked = vec![false; n];
        let mut g = vec![0u32; plants.len()];
        for s in 0..walk.dfa.state_count() as u32 {
            for (c, gc) in g.iter_mut().enumerate() {
                *gc = walk.component_state(s, c);
            }
            let x = walk.component_state(s, plants.len());
            if plants.iter().zip(&g).all(|(d, &q)| d.marked[q as usize]) {
                plant_marked[x as usize] = true;
            }
            for &e in &sup.alphabet {
                let plant_enables =
                    plants.iter().zip(&g).all(|(d, &q)| !d.has_event(e) || d.step(q, e).is_some());
                if plant_enables && sup.step(x, e).is_none() {
                    disabled[x as usize * words + e as usize / 64] |= 1 << (e % 64);
                }
            }
        }
        Ok(ControlData { words, enabled, disabled, marked: sup.marked.clone(), plant_marked })
    }

    /// Whether `x` and `y` may share a cell of a control congruence: neither enables what the other
    /// disables, and they agree on marking where both meet a marked plant state or both do not.
    pub(crate) fn consistent(&self, x: u32, y: u32) -> bool {
        let (x, y) = (x as usize, y as usize);
        let w = self.words;
        let clash = (0..w).any(|i| {
            self.enabled[x * w + i] & self.disabled[y * w + i] != 0
                || self.enabled[y * w + i] & self.disabled[x * w + i] != 0
        });
        !clash && (self.plant_marked[x] != self.plant_marked[y] || self.marked[x] == self.marked[y])
    }

    /// Whether state `x` disables the global event `e`.
    fn disables(&self, x: usize, e: u32) -> bool {
        self.disabled[x * self.words + e as usize / 64] & (1 << (e % 64)) != 0
    }
}

/// TCT's `condat(G, S)`: for each state of `supervisor` (in its order), the controllable events it
/// disables against the plant `‖ plants`, sorted by name. A state no closed-loop string reaches disables
/// nothing.
pub fn condat(
    plants: &[Automaton],
    supervisor: &Automaton,
    cfg: &Config,
) -> Result<Vec<Vec<String>>, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(std::iter::once(supervisor)))?;
    let (p, s) = inputs.dfas.split_at(plants.len());
    let data = ControlData::new(&p.iter().collect::<Vec<_>>(), &s[0], &inputs, cfg)?;
    Ok((0..supervisor.states.len())
        .map(|x| {
            let mut events: Vec<String> = s[0]
                .alphabet
                .iter()
                .filter(|&&e| inputs.controllable[e as usize] && data.disables(x, e))
                .map(|&e| inputs.table.name(EventId::from_u32(e)).to_string())
                .collect();
            events.sort();
            events
        })
        .collect())
}
