//! The state feedback as the state-based firmware's tables (`[runtime] mode = "state"`,
//! docs/state-based.md), as data: what `codegen emit` writes ([`crate::emit::state`]) instead of the
//! supervisor tables for `firmware::state::StateRuntime`, and what the runtime compiled for the host
//! runs in the tests ([`StateTables::host`]) — the
//! signal word's layout (bit `i`: signal `i`, at most 32), per controllable event its F_σ cubes as
//! `(mask, value)` pairs over the word, per event what it writes into the word (a command its outputs, a
//! sensor event its *virtual pins*: the input literals of its target state), and per component its
//! states' formulas for the local choice policies. No supervisor table.
//!
//! Refused with a [`FeedbackError`]: more than 32 signals; an uncontrollable event whose input effect
//! depends on its source state (two transitions to targets fixing different inputs: one write per event
//! cannot stand for it); a feedback where the supervisors' memory decides (the firmware keeps no
//! supervisor state; a `[state] memory` program is PLC-only).

use firmware::state::{Cube as WordCube, Reading, Rule as WordRule};

use crate::config::Cube;
use crate::model::EventId;
use crate::pack::{PackSet, Role};

use super::{FeedbackError, Rule, Sfbc, Vector};

/// Most signals in the packed word.
pub const WORD_BITS: usize = 32;

fn refuse(key: &str, message: impl Into<String>) -> FeedbackError {
    FeedbackError::Vector { key: key.into(), message: message.into() }
}

/// Per event id, what it writes into the word: a command its outputs, an uncontrollable event of a
/// plant the inputs its target state fixes (the same from every source, else refused), others nothing.
pub fn writes(set: &PackSet, vector: &Vector) -> Result<Vec<Cube>, FeedbackError> {
    let table = set.events();
    let mut out: Vec<Cube> =
        vector.commands.iter().map(|c| c.map_or(Cube::default(), |(_, cube)| cube)).collect();
    out.resize(table.len(), Cube::default());
    let plants = set.members().iter().filter(|m| m.role == Role::Plant);
    for (p, plant) in plants.enumerate() {
        let inputs = vector.inputs(p);
        // Per event of this plant: the pins of its first transition, and that transition's source.
        let mut own: Vec<Option<(Cube, usize)>> = vec![None; table.len()];
        for s in 0..plant.state_count() {
            for (e, t) in plant.out(s).filter(|&(e, _)| !table.is_controllable(e)) {
                let target = vector.cubes[p][t.index()];
                let pins = Cube { mask: target.mask & inputs, value: target.value & inputs };
                match own[e.index()] {
                    None => own[e.index()] = Some((pins, s)),
                    Some((first, from)) if first != pins => {
                        let states = &plant.automaton.states;
                        return Err(refuse(
                            &format!("state.components.{}.states", plant.automaton.name),
                            format!(
                                "the inputs {} sets depend on its source state (from {} it sets {}, from {} {}): \
                                 one write per event cannot stand for it on the firmware (mode = \"state\")",
                                table.name(e),
                                states[from].name,
                                literals(vector, first),
                                states[s].name,
                                literals(vector, pins),
                            ),
                        ));
                    }
                    Some(_) => {}
                }
            }
        }
        for (w, pins) in out.iter_mut().zip(own) {
            if let Some((pins, _)) = pins {
                *w = Cube { mask: w.mask | pins.mask, value: w.value | pins.value };
            }
        }
    }
    Ok(out)
}

/// The literals of `cube` by signal name (`X0 !X1`), `nothing` for none.
fn literals(vector: &Vector, cube: Cube) -> String {
    let names = &vector.signals.signals;
    let words: Vec<String> = cube
        .literals()
        .map(|(i, v)| {
            format!("{}{}", if v { "" } else { "!" }, names.get(i).map_or("?", |s| s.name.as_str()))
        })
        .collect();
    if words.is_empty() {
        String::from("nothing")
    } else {
        words.join(" ")
    }
}

/// The state-based firmware's tables as data: what [`crate::emit::state`] writes and
/// [`StateTables::host`] lends to the runtime compiled for the host (the translation validation runs
/// the firmware's own evaluation on them).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StateTables {
    /// Words of an event bitset.
    pub words: usize,
    /// The word in the initial state.
    pub initial: u32,
    /// Per controllable event (the rungs' order): event and end of its cubes.
    pub rules: Vec<WordRule>,
    /// Every rule's cubes, back to back.
    pub cubes: Vec<WordCube>,
    /// Per event id, its write into the word.
    pub writes: Vec<WordCube>,
    /// Per event id, the components whose plant has it (bit per component).
    pub holders: Vec<u32>,
    /// Per component, the end of its states in `readings`.
    pub ends: Vec<u16>,
    /// Per component state: its label (`Injector.I2B`), formula and the events leaving it (bitset).
    pub readings: Vec<(String, WordCube, Vec<u32>)>,
    /// Per component: the commands it owns (bitset).
    pub plant_events: Vec<Vec<u32>>,
    /// The choice sites, as indices of `readings`.
    pub sites: Vec<u16>,
    /// The controllable events with a rule (bitset).
    pub controllable: Vec<u32>,
    /// Signal names by bit.
    pub signals: Vec<String>,
    /// Component names.
    pub components: Vec<String>,
}

/// A cube over at most [`WORD_BITS`] signals as the word's.
fn word_cube(c: Cube) -> WordCube {
    // `StateTables::build` refused more than WORD_BITS signals: every bit fits.
    WordCube { mask: c.mask as u32, value: c.value as u32 }
}

/// The bitset of `events` in `words` words.
fn bitset(words: usize, events: impl IntoIterator<Item = EventId>) -> Vec<u32> {
    let mut w = vec![0u32; words];
    for e in events {
        w[e.index() / 32] |= 1 << (e.index() % 32);
    }
    w
}

impl StateTables {
    /// The tables of the feedback `f` of `set` with its `rules` (refused: see the module documentation).
    pub fn build(
        set: &PackSet,
        vector: &Vector,
        f: &Sfbc,
        rules: &[Rule],
    ) -> Result<StateTables, FeedbackError> {
        let signals = &vector.signals.signals;
        if signals.len() > WORD_BITS {
            return Err(refuse(
                "state.components",
                format!(
                    "{} signals: the firmware packs at most {WORD_BITS} into its word (mode = \"state\")",
                    signals.len()
                ),
            ));
        }
        if !f.conflicts.is_empty() || f.memory.is_some() {
            let states: std::collections::BTreeSet<_> = f.conflicts.iter().map(|c| &c.state).collect();
            return Err(FeedbackError::Memory(format!(
                "the supervisors' memory decides at {} plant state(s): the state-based firmware keeps no \
                 supervisor state (a [state] memory program is for PLCs only); run this set with mode = \"event\"",
                states.len()
            )));
        }
        let table = set.events();
        if table.len() > usize::from(firmware::link::MAX_EVENT) + 1 {
            return Err(refuse(
                "runtime.mode",
                format!("{} events: the link carries at most 240", table.len()),
            ));
        }
        let words = table.len().div_ceil(32).max(1);
        let plants: Vec<_> = set.members().iter().filter(|m| m.role == Role::Plant).collect();
        if plants.len() > 32 {
            return Err(refuse(
                "plants",
                format!("{} plants: the state-based firmware holds at most 32 components", plants.len()),
            ));
        }
        let mut holders = vec![0u32; table.len()];
        for (p, plant) in plants.iter().enumerate() {
            for e in plant.alphabet() {
                holders[e.index()] |= 1 << p;
            }
        }
        let mut readings = Vec::new();
        let mut ends = Vec::new();
        let mut sites = Vec::new();
        for (p, plant) in plants.iter().enumerate() {
            for s in 0..plant.state_count() {
                let leaving: Vec<EventId> = plant.out(s).map(|(e, _)| e).collect();
                if leaving.iter().filter(|&&e| table.is_controllable(e)).count() >= 2 {
                    sites.push(readings.len() as u16);
                }
                let label = format!("{}.{}", plant.automaton.name, plant.automaton.states[s].name);
                readings.push((label, word_cube(vector.cubes[p][s]), bitset(words, leaving)));
            }
            ends.push(readings.len() as u16);
        }
        let mut word_rules = Vec::new();
        let mut cubes = Vec::new();
        for r in rules {
            cubes.extend(r.cubes.iter().map(|&c| word_cube(c)));
            word_rules.push(WordRule { event: r.event.index() as u8, end: cubes.len() as u16 });
        }
        let plant_events = (0..plants.len())
            .map(|p| {
                let owned =
                    f.controllable.iter().filter(|e| vector.commands[e.index()].is_some_and(|(q, _)| q == p));
                bitset(words, owned.copied())
            })
            .collect();
        Ok(StateTables {
            words,
            initial: vector.initial as u32,
            rules: word_rules,
            cubes,
            writes: writes(set, vector)?.into_iter().map(word_cube).collect(),
            holders,
            ends,
            readings,
            plant_events,
            sites,
            controllable: bitset(words, f.controllable.iter().copied()),
            signals: signals.iter().map(|s| s.name.clone()).collect(),
            components: plants.iter().map(|p| p.automaton.name.clone()).collect(),
        })
    }

    /// The tables lent to the runtime compiled for the host, for `W` = [`StateTables::words`] (else
    /// `None`).
    pub fn host<const W: usize>(&self) -> Option<HostStateTables<'_, W>> {
        let fixed = |w: &Vec<u32>| <[u32; W]>::try_from(w.as_slice()).ok();
        let readings = self
            .readings
            .iter()
            .enumerate()
            .map(|(code, (_, cube, leaving))| {
                Some(Reading { cube: *cube, leaving: fixed(leaving)?, code: code as u16 })
            })
            .collect::<Option<Vec<_>>>()?;
        let plant_events = self.plant_events.iter().map(fixed).collect::<Option<Vec<_>>>()?;
        Some(HostStateTables {
            tables: self,
            controllable: fixed(&self.controllable)?,
            readings,
            plant_events,
        })
    }
}

/// [`StateTables`] lent to the runtime compiled for the host, in its types.
#[derive(Clone, Debug)]
pub struct HostStateTables<'a, const W: usize> {
    tables: &'a StateTables,
    controllable: [u32; W],
    readings: Vec<Reading<W>>,
    plant_events: Vec<[u32; W]>,
}

impl<const W: usize> HostStateTables<'_, W> {
    /// The runtime's view of the tables.
    pub fn tables(&self) -> firmware::state::StateTables<'_, W> {
        firmware::state::StateTables {
            initial: self.tables.initial,
            rules: &self.tables.rules,
            cubes: &self.tables.cubes,
            writes: &self.tables.writes,
            holders: &self.tables.holders,
            components: &self.tables.ends,
            readings: &self.readings,
            controllable: self.controllable,
            plant_events: &self.plant_events,
            sites: &self.tables.sites,
        }
    }
}
