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

use crate::config::{Cube, RuntimeConfig};
use crate::emit::policy::{fault_value, rust_type};
use crate::emit::rust::event_idents;
use crate::emit::Provenance;
use crate::model::EventId;
use crate::pack::{PackSet, Role};

use super::{EventRung, Sfbc, StateError, Vector};

/// Most signals in the packed word.
pub const WORD_BITS: usize = 32;

fn refuse(key: &str, message: impl Into<String>) -> StateError {
    StateError::Vector { key: key.into(), message: message.into() }
}

/// A cube over the signals as the word's `(mask, value)`, once the signal count is known to fit.
fn word(c: Cube) -> (u32, u32) {
    (c.mask as u32, c.value as u32)
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

/// The firmware tables of the feedback `f` with `rungs`, as Rust source (see the module documentation;
/// the names the applications use are those of the event-based tables: `NAME`, `event`, `EVENT_WORDS`,
/// `INPUT_SLOTS`, `SEED`, `Policy`, `CONFIG`, `EVENT_NAMES`, `AUTOMATON_NAMES` — the components —,
/// `Runtime<P, E>` and `CHECKED`, here the `StateTables` the runtime takes). Deterministic.
pub fn tables(
    set: &PackSet,
    vector: &Vector,
    f: &Sfbc,
    rungs: &[EventRung],
    name: &str,
    runtime: &RuntimeConfig,
    provenance: &Provenance,
) -> Result<String, StateError> {
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
        return Err(StateError::Memory(format!(
            "the supervisors' memory decides at {} plant state(s): the state-based firmware keeps no supervisor \
             state (a [state] memory program is for PLCs only); run this set with mode = \"event\"",
            f.conflicts.iter().map(|c| &c.state).collect::<std::collections::BTreeSet<_>>().len()
        )));
    }
    if runtime.input_buffer == 0 || runtime.input_buffer > usize::from(u16::MAX) {
        return Err(refuse("runtime.input_buffer", format!("{} slots: 1 to 65535", runtime.input_buffer)));
    }
    let table = set.events();
    if table.len() > usize::from(firmware::link::MAX_EVENT) + 1 {
        return Err(refuse("runtime.mode", format!("{} events: the link carries at most 240", table.len())));
    }
    let writes = writes(set, vector)?;
    let words = table.len().div_ceil(32).max(1);
    let bits = |events: &mut dyn Iterator<Item = EventId>| {
        let mut w = vec![0u32; words];
        for e in events {
            w[e.index() / 32] |= 1 << (e.index() % 32);
        }
        w.iter().map(|x| format!("0x{x:08x}")).collect::<Vec<_>>().join(", ")
    };
    let plants: Vec<_> = set.members().iter().filter(|m| m.role == Role::Plant).collect();

    let mut out = String::new();
    let _ = writeln!(
        out,
        "// @generated by codegen {} (`codegen emit`): do not edit.",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(out, "//");
    let cube_count: usize = rungs.iter().map(|r| r.cubes.len()).sum();
    let _ = writeln!(
        out,
        "// Set '{name}' state-based (mode = state): {} components, {} signals, {} events, {} rules of {} cubes; \
         no supervisor tables.",
        plants.len(),
        signals.len(),
        table.len(),
        rungs.len(),
        cube_count
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
    let layout: Vec<String> = signals.iter().enumerate().map(|(i, s)| format!("{i} {}", s.name)).collect();
    let _ = writeln!(out, "// Signal word, bit by bit: {}.", layout.join(", "));
    let _ = writeln!(out);
    let _ = writeln!(out, "/// Name of the supervisor set.");
    let _ = writeln!(out, "pub const NAME: &str = {name:?};");
    let _ = writeln!(out);
    let _ = writeln!(out, "/// Global event ids.");
    let _ = writeln!(out, "pub mod event {{");
    let names: Vec<String> = table.ids().map(|e| table.name(e).to_owned()).collect();
    for (e, ident) in table.ids().zip(event_idents(&names)) {
        let kind = if table.is_controllable(e) { "controllable" } else { "uncontrollable" };
        let _ = writeln!(out, "    /// `{}` ({kind}).", table.name(e));
        let _ = writeln!(out, "    pub const {ident}: u8 = {};", e.index());
    }
    let _ = writeln!(out, "}}");
    let _ = writeln!(out);
    // Sites: component states with two or more commands leaving; a reading's code is its index.
    let mut readings = Vec::new();
    let mut ends = Vec::new();
    let mut sites = Vec::new();
    for (p, plant) in plants.iter().enumerate() {
        for s in 0..plant.state_count() {
            let offered: Vec<EventId> =
                plant.out(s).map(|(e, _)| e).filter(|&e| table.is_controllable(e)).collect();
            let code = readings.len();
            if offered.len() >= 2 {
                sites.push(code);
            }
            let (mask, value) = word(vector.cubes[p][s]);
            readings.push(format!(
                "    // {}.{}\n    firmware::state::Reading {{ cube: firmware::state::Cube {{ mask: 0x{mask:08x}, value: 0x{value:08x} }}, offered: [{}], code: {code} }},",
                plant.automaton.name,
                plant.automaton.states[s].name,
                bits(&mut offered.into_iter())
            ));
        }
        ends.push(readings.len());
    }
    let consts: [(&str, &str, String, &str); 6] = [
        ("Words of an event bitset.", "EVENT_WORDS", words.to_string(), "usize"),
        ("State-vector components (the plants).", "COMPONENTS", plants.len().to_string(), "usize"),
        (
            "Choice sites: component states with two or more commands leaving.",
            "SITES",
            sites.len().to_string(),
            "usize",
        ),
        ("Signals in the word.", "SIGNALS", signals.len().to_string(), "usize"),
        (
            "Slots of the input queue (capacity + 1).",
            "INPUT_SLOTS",
            (runtime.input_buffer + 1).to_string(),
            "usize",
        ),
        (
            "Entropy seed of the random policies (QEMU; a board reseeds).",
            "SEED",
            runtime.seed.to_string(),
            "u64",
        ),
    ];
    for (doc, name, value, ty) in consts {
        let _ = writeln!(out, "/// {doc}\npub const {name}: {ty} = {value};");
    }
    let _ = writeln!(out, "/// The choice policy ({}).", runtime.policy);
    let _ = writeln!(out, "pub type Policy = {};", rust_type(runtime.policy));
    let _ = writeln!(out, "/// Run-time configuration.");
    let _ = writeln!(out, "pub const CONFIG: firmware::runtime::Config = firmware::runtime::Config {{");
    let _ = writeln!(out, "    guard: {},", runtime.guard);
    let _ = writeln!(out, "    on_fault: {},", fault_value(runtime.on_fault));
    let _ = writeln!(out, "    reseed_every: {},", runtime.reseed_every);
    let _ = writeln!(out, "}};");
    let _ = writeln!(
        out,
        "/// The state-based runtime over these tables, choosing with `P` and drawing entropy from `E`."
    );
    let _ = writeln!(
        out,
        "pub type Runtime<P, E> = firmware::state::StateRuntime<'static, P, E, EVENT_WORDS, COMPONENTS>;"
    );
    let quoted = |names: &mut dyn Iterator<Item = &str>| names.map(|n| format!("{n:?}")).collect::<Vec<_>>();
    let events = quoted(&mut names.iter().map(String::as_str));
    let _ = writeln!(out, "/// Event names by global id, for logs (the tables hold none).");
    let _ = writeln!(out, "pub static EVENT_NAMES: [&str; {}] = [{}];", events.len(), events.join(", "));
    let comps = quoted(&mut plants.iter().map(|p| p.automaton.name.as_str()));
    let _ = writeln!(out, "/// Component names (the plants), for logs.");
    let _ = writeln!(out, "pub static AUTOMATON_NAMES: [&str; {}] = [{}];", comps.len(), comps.join(", "));
    let sig = quoted(&mut signals.iter().map(|s| s.name.as_str()));
    let _ = writeln!(out, "/// Signal names by bit of the word, for logs.");
    let _ = writeln!(out, "pub static SIGNAL_NAMES: [&str; {}] = [{}];", sig.len(), sig.join(", "));
    let _ = writeln!(out);

    let _ = writeln!(out, "/// Per controllable event in id order: the end of its cubes in `CUBES`.");
    let _ = writeln!(out, "static RULES: [firmware::state::Rule; {}] = [", rungs.len());
    let mut end = 0;
    for (r, e) in rungs.iter().zip(&f.controllable) {
        end += r.cubes.len();
        let _ = writeln!(out, "    // {}: {} cube(s)", r.event, r.cubes.len());
        let _ = writeln!(out, "    firmware::state::Rule {{ event: {}, end: {end} }},", e.index());
    }
    let _ = writeln!(out, "];");
    let _ =
        writeln!(out, "/// F_σ of every rule, cube after cube: a cube holds when `word & mask == value`.");
    let _ = writeln!(out, "static CUBES: [firmware::state::Cube; {cube_count}] = [");
    for r in rungs {
        for &c in &r.cubes {
            let (mask, value) = word(c);
            let _ = writeln!(
                out,
                "    firmware::state::Cube {{ mask: 0x{mask:08x}, value: 0x{value:08x} }}, // {}",
                r.event
            );
        }
    }
    let _ = writeln!(out, "];");
    let _ = writeln!(
        out,
        "/// Per event id: what it writes into the word (a command its outputs, a sensor event its virtual pins)."
    );
    let _ = writeln!(out, "static WRITES: [firmware::state::Cube; {}] = [", writes.len());
    for (e, &c) in table.ids().zip(&writes) {
        let (mask, value) = word(c);
        let _ = writeln!(
            out,
            "    firmware::state::Cube {{ mask: 0x{mask:08x}, value: 0x{value:08x} }}, // {}",
            table.name(e)
        );
    }
    let _ = writeln!(out, "];");
    let ends: Vec<String> = ends.iter().map(usize::to_string).collect();
    let _ = writeln!(out, "/// Per component, the end of its states in `READINGS`.");
    let _ = writeln!(out, "static COMPONENT_ENDS: [u16; {}] = [{}];", ends.len(), ends.join(", "));
    let _ = writeln!(out, "/// Every component's states: formula, commands leaving, code.");
    let _ = writeln!(out, "static READINGS: [firmware::state::Reading<EVENT_WORDS>; {}] = [", readings.len());
    for r in &readings {
        let _ = writeln!(out, "{r}");
    }
    let _ = writeln!(out, "];");
    let owned: Vec<String> = (0..plants.len())
        .map(|p| {
            let mut own = f
                .controllable
                .iter()
                .copied()
                .filter(|e| vector.commands[e.index()].is_some_and(|(q, _)| q == p));
            format!("[{}]", bits(&mut own))
        })
        .collect();
    let _ = writeln!(out, "/// Per component: the commands it owns.");
    let _ =
        writeln!(out, "static PLANT_EVENTS: [[u32; EVENT_WORDS]; {}] = [{}];", owned.len(), owned.join(", "));
    let sites: Vec<String> = sites.iter().map(usize::to_string).collect();
    let _ = writeln!(out, "/// The choice sites, as reading codes.");
    let _ = writeln!(out, "static CHOICE_SITES: [u16; {}] = [{}];", sites.len(), sites.join(", "));
    let _ = writeln!(out);
    // At most WORD_BITS signals (checked above): the initial values fit the word.
    let initial = vector.initial as u32;
    let _ = writeln!(out, "/// The tables the state-based runtime takes.");
    let _ = writeln!(out, "pub static TABLES: firmware::state::StateTables<'static, EVENT_WORDS> = firmware::state::StateTables {{");
    let _ = writeln!(out, "    initial: 0x{initial:08x},");
    let _ = writeln!(out, "    rules: &RULES,");
    let _ = writeln!(out, "    cubes: &CUBES,");
    let _ = writeln!(out, "    writes: &WRITES,");
    let _ = writeln!(out, "    components: &COMPONENT_ENDS,");
    let _ = writeln!(out, "    readings: &READINGS,");
    let _ = writeln!(out, "    choice: firmware::table::SupervisorSet {{");
    let _ = writeln!(out, "        controllable: [{}],", bits(&mut f.controllable.iter().copied()));
    let _ = writeln!(out, "        plants: {},", plants.len());
    let _ = writeln!(out, "        automata: &[],");
    let _ = writeln!(out, "        block: &[],");
    let _ = writeln!(out, "        wide: false,");
    let _ = writeln!(out, "        masks: &[],");
    let _ = writeln!(out, "        mask_bytes: 0,");
    let _ = writeln!(out, "        layout: firmware::table::layout::RANKED,");
    let _ = writeln!(out, "        initials: &[],");
    let _ = writeln!(out, "        holder_lists: &[],");
    let _ = writeln!(out, "        holders: &[],");
    let _ = writeln!(out, "        plant_events: &PLANT_EVENTS,");
    let _ = writeln!(out, "        sites: &CHOICE_SITES,");
    let _ = writeln!(out, "    }},");
    let _ = writeln!(out, "}};");
    let _ = writeln!(out, "/// What the applications hand the runtime (the event-based tables' name).");
    let _ =
        writeln!(out, "pub static CHECKED: &firmware::state::StateTables<'static, EVENT_WORDS> = &TABLES;");
    Ok(out)
}
