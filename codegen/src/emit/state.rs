//! The state feedback as firmware tables (`[runtime] mode = "state"`, docs/state-based.md): what
//! `codegen emit` writes instead of the supervisor tables for `firmware::state::StateRuntime` — the
//! signal word's layout (bit `i`: signal `i`, at most 32), per controllable event its F_σ cubes as
//! `(mask, value)` pairs over the word, per event what it writes into the word (a command its outputs, a
//! sensor event its *virtual pins*: the input literals of its target state), and per component its
//! states' formulas for the local choice policies. No supervisor table.
//!
//! Refused with a [`StateError`]: more than 32 signals; an uncontrollable event whose input effect
//! depends on its source state (two transitions to targets fixing different inputs: one write per event
//! cannot stand for it); a feedback where the supervisors' memory decides (the firmware keeps no
//! supervisor state; a `[state] memory` program is PLC-only).

use std::fmt::Write as _;

use firmware::state::{Cube as WordCube, Reading, Rule};
use firmware::table::SupervisorSet;

use crate::config::{Cube, RuntimeConfig, Signals};
use crate::model::EventId;
use crate::pack::{PackSet, Role};
use crate::plc::state_based::{analyse, memory, rungs, EventRung, Sfbc, StateError, Vector};
use crate::provenance::Provenance;

use super::rust::{preamble, Const};

/// Most signals in the packed word.
pub const WORD_BITS: usize = 32;

fn refuse(key: &str, message: impl Into<String>) -> StateError {
    StateError::Vector { key: key.into(), message: message.into() }
}

/// Per event id, what it writes into the word: a command its outputs, an uncontrollable event of a
/// plant the inputs its target state fixes (the same from every source, else refused), others nothing.
pub fn writes(set: &PackSet, vector: &Vector) -> Result<Vec<Cube>, StateError> {
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

/// The state-based firmware's tables as data: what [`StateTables::rust`] writes and
/// [`StateTables::host`] lends to the runtime compiled for the host (the translation validation runs
/// the firmware's own evaluation on them).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StateTables {
    /// Words of an event bitset.
    pub words: usize,
    /// The word in the initial state.
    pub initial: u32,
    /// Per controllable event (the rungs' order): event and end of its cubes.
    pub rules: Vec<Rule>,
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
    /// The tables of the feedback `f` of `set` with `rungs` (refused: see the module documentation).
    pub fn build(
        set: &PackSet,
        vector: &Vector,
        f: &Sfbc,
        rungs: &[EventRung],
    ) -> Result<StateTables, StateError> {
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
            return Err(StateError::Memory(format!(
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
        let mut rules = Vec::new();
        let mut cubes = Vec::new();
        for (r, e) in rungs.iter().zip(&f.controllable) {
            cubes.extend(r.cubes.iter().map(|&c| word_cube(c)));
            rules.push(Rule { event: e.index() as u8, end: cubes.len() as u16 });
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
            rules,
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

    /// The tables as Rust source for the firmware applications (see [`tables`]).
    pub fn rust(
        &self,
        set: &PackSet,
        name: &str,
        runtime: &RuntimeConfig,
        provenance: &Provenance,
    ) -> String {
        let table = set.events();
        let hex = |w: &[u32]| w.iter().map(|x| format!("0x{x:08x}")).collect::<Vec<_>>().join(", ");
        let cube = |c: &WordCube| {
            format!("firmware::state::Cube {{ mask: 0x{:08x}, value: 0x{:08x} }}", c.mask, c.value)
        };
        let mut out = String::new();
        let _ = writeln!(
            out,
            "// @generated by codegen {} (`codegen emit`): do not edit.",
            env!("CARGO_PKG_VERSION")
        );
        let _ = writeln!(out, "//");
        let _ = writeln!(
            out,
            "// Set '{name}' state-based (mode = state): {} components, {} signals, {} events, {} rules of {} \
             cubes; no supervisor tables.",
            self.components.len(),
            self.signals.len(),
            table.len(),
            self.rules.len(),
            self.cubes.len()
        );
        for line in provenance.lines() {
            let _ = writeln!(out, "// {line}");
        }
        let _ = writeln!(
            out,
            "// Options: mode=state policy={} seed={} guard={} on_fault={} input_buffer={} reseed_every={}",
            runtime.policy,
            runtime.seed,
            runtime.guard,
            runtime.on_fault,
            runtime.input_buffer,
            runtime.reseed_every
        );
        let layout: Vec<String> = self.signals.iter().enumerate().map(|(i, s)| format!("{i} {s}")).collect();
        let _ = writeln!(out, "// Signal word, bit by bit: {}.", layout.join(", "));
        let _ = writeln!(out);
        let names: Vec<String> = table.ids().map(|e| table.name(e).to_owned()).collect();
        let consts = [
            Const::size("Words of an event bitset.", "EVENT_WORDS", self.words),
            Const::size("State-vector components (the plants).", "COMPONENTS", self.components.len()),
            Const::size(
                "Choice sites: component states with two or more commands leaving.",
                "SITES",
                self.sites.len(),
            ),
            Const::size("Signals in the word.", "SIGNALS", self.signals.len()),
            Const::size("Slots of the input queue (capacity + 1).", "INPUT_SLOTS", runtime.input_buffer + 1),
        ];
        let kinds: Vec<bool> = table.ids().map(|e| table.is_controllable(e)).collect();
        let controllable = |e: usize| kinds.get(e).copied().unwrap_or(false);
        preamble(&mut out, name, &names, &controllable, &consts, runtime);
        let _ = writeln!(
            out,
            "/// The state-based runtime over these tables, choosing with `P` and drawing entropy from `E`."
        );
        let _ = writeln!(
            out,
            "pub type Runtime<P, E> = firmware::state::StateRuntime<'static, P, E, EVENT_WORDS, COMPONENTS>;"
        );
        let quoted = |names: &[String]| names.iter().map(|n| format!("{n:?}")).collect::<Vec<_>>().join(", ");
        let _ = writeln!(out, "/// Component names (the plants), for logs.");
        let _ = writeln!(
            out,
            "pub static AUTOMATON_NAMES: [&str; {}] = [{}];",
            self.components.len(),
            quoted(&self.components)
        );
        let _ = writeln!(out, "/// Signal names by bit of the word, for logs.");
        let _ = writeln!(
            out,
            "pub static SIGNAL_NAMES: [&str; {}] = [{}];",
            self.signals.len(),
            quoted(&self.signals)
        );
        let _ = writeln!(out);
        let _ = writeln!(out, "/// Per controllable event in id order: the end of its cubes in `CUBES`.");
        let _ = writeln!(out, "static RULES: [firmware::state::Rule; {}] = [", self.rules.len());
        for r in &self.rules {
            let _ = writeln!(
                out,
                "    firmware::state::Rule {{ event: {}, end: {} }}, // {}",
                r.event,
                r.end,
                names.get(usize::from(r.event)).map_or("", String::as_str)
            );
        }
        let _ = writeln!(out, "];");
        let _ = writeln!(
            out,
            "/// F_σ of every rule, cube after cube: a cube holds when `word & mask == value`."
        );
        let _ = writeln!(out, "static CUBES: [firmware::state::Cube; {}] = [", self.cubes.len());
        let mut start = 0;
        for r in &self.rules {
            let event = names.get(usize::from(r.event)).map_or("", String::as_str);
            for c in self.cubes.get(start..usize::from(r.end)).unwrap_or_default() {
                let _ = writeln!(out, "    {}, // {event}", cube(c));
            }
            start = usize::from(r.end);
        }
        let _ = writeln!(out, "];");
        let _ = writeln!(
            out,
            "/// Per event id: what it writes into the word (a command its outputs, a sensor event its virtual \
             pins)."
        );
        let _ = writeln!(out, "static WRITES: [firmware::state::Cube; {}] = [", self.writes.len());
        for (w, n) in self.writes.iter().zip(&names) {
            let _ = writeln!(out, "    {}, // {n}", cube(w));
        }
        let _ = writeln!(out, "];");
        let holders: Vec<String> = self.holders.iter().map(|h| format!("0x{h:x}")).collect();
        let _ = writeln!(out, "/// Per event id, the components whose plant has it (bit per component).");
        let _ = writeln!(out, "static HOLDERS: [u32; {}] = [{}];", holders.len(), holders.join(", "));
        let ends: Vec<String> = self.ends.iter().map(u16::to_string).collect();
        let _ = writeln!(out, "/// Per component, the end of its states in `READINGS`.");
        let _ = writeln!(out, "static COMPONENT_ENDS: [u16; {}] = [{}];", ends.len(), ends.join(", "));
        let _ = writeln!(out, "/// Every component's states: formula, events leaving, code.");
        let _ = writeln!(
            out,
            "static READINGS: [firmware::state::Reading<EVENT_WORDS>; {}] = [",
            self.readings.len()
        );
        for (code, (label, c, leaving)) in self.readings.iter().enumerate() {
            let _ = writeln!(
                out,
                "    firmware::state::Reading {{ cube: {}, leaving: [{}], code: {code} }}, // {label}",
                cube(c),
                hex(leaving)
            );
        }
        let _ = writeln!(out, "];");
        let owned: Vec<String> = self.plant_events.iter().map(|w| format!("[{}]", hex(w))).collect();
        let _ = writeln!(out, "/// Per component: the commands it owns.");
        let _ = writeln!(
            out,
            "static PLANT_EVENTS: [[u32; EVENT_WORDS]; {}] = [{}];",
            owned.len(),
            owned.join(", ")
        );
        let sites: Vec<String> = self.sites.iter().map(u16::to_string).collect();
        let _ = writeln!(out, "/// The choice sites, as reading codes.");
        let _ = writeln!(out, "static CHOICE_SITES: [u16; {}] = [{}];", sites.len(), sites.join(", "));
        let _ = writeln!(out);
        let _ = writeln!(out, "/// The tables the state-based runtime takes.");
        let _ = writeln!(
            out,
            "pub static TABLES: firmware::state::StateTables<'static, EVENT_WORDS> = firmware::state::StateTables {{"
        );
        let _ = writeln!(out, "    initial: 0x{:08x},", self.initial);
        for field in [
            "rules: &RULES",
            "cubes: &CUBES",
            "writes: &WRITES",
            "holders: &HOLDERS",
            "components: &COMPONENT_ENDS",
        ] {
            let _ = writeln!(out, "    {field},");
        }
        let _ = writeln!(out, "    readings: &READINGS,");
        let _ = writeln!(out, "    choice: firmware::table::SupervisorSet {{");
        let _ = writeln!(out, "        controllable: [{}],", hex(&self.controllable));
        let _ = writeln!(out, "        plants: {},", self.components.len());
        let _ = writeln!(out, "        plant_events: &PLANT_EVENTS,");
        let _ = writeln!(out, "        sites: &CHOICE_SITES,");
        let _ = writeln!(out, "        ..firmware::state::no_tables()");
        let _ = writeln!(out, "    }},");
        let _ = writeln!(out, "}};");
        let _ = writeln!(out, "/// What the applications hand the runtime (the event-based tables' name).");
        let _ = writeln!(
            out,
            "pub static CHECKED: &firmware::state::StateTables<'static, EVENT_WORDS> = &TABLES;"
        );
        out
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
            choice: SupervisorSet {
                controllable: self.controllable,
                plants: self.tables.components.len() as u8,
                plant_events: &self.plant_events,
                sites: &self.tables.sites,
                ..firmware::state::no_tables()
            },
        }
    }
}

/// The firmware tables of the feedback `f` with `rungs`, as Rust source: the names the applications use
/// are those of the event-based tables — `NAME`, `event`, `EVENT_WORDS`, `INPUT_SLOTS`, `SEED`, `Policy`,
/// `CONFIG`, `EVENT_NAMES`, `AUTOMATON_NAMES` (the components), `Runtime<P, E>` and `CHECKED` (here the
/// `firmware::state::StateTables` the runtime takes) — with `SIGNAL_NAMES`, `COMPONENTS`, `SIGNALS` and
/// `TABLES` besides. Deterministic.
pub fn tables(
    set: &PackSet,
    vector: &Vector,
    f: &Sfbc,
    rungs: &[EventRung],
    name: &str,
    runtime: &RuntimeConfig,
    provenance: &Provenance,
) -> Result<String, StateError> {
    if runtime.input_buffer == 0 || runtime.input_buffer > usize::from(u16::MAX) {
        return Err(refuse("runtime.input_buffer", format!("{} slots: 1 to 65535", runtime.input_buffer)));
    }
    Ok(StateTables::build(set, vector, f, rungs)?.rust(set, name, runtime, provenance))
}

/// The tables of the state-based firmware (`[runtime] mode = "state"`) for `set` under the state vectors
/// `signals`: the same f and the same rungs as the PLC program (F_σ exact when `[state] exact`), written
/// by [`tables`]. A feedback the supervisors' memory decides is refused.
pub fn firmware_tables(
    set: &PackSet,
    signals: Signals,
    name: &str,
    runtime: &RuntimeConfig,
    provenance: &Provenance,
) -> Result<String, StateError> {
    let exact = signals.exact;
    let (vector, f) = analyse(set, signals, false)?;
    let rungs = rungs(set, &vector, &f, &memory::Memory::default(), exact);
    tables(set, &vector, &f, &rungs, name, runtime, provenance)
}
