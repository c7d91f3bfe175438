//! The state-based firmware's tables (`[runtime] mode = "state"`, docs/state-based.md) as Rust source:
//! the tables of [`crate::feedback::tables`] written for `firmware::state::StateRuntime`, under the same
//! names the event-based tables give the applications, so `cell-qemu` and `cost-qemu` run either.

use std::fmt::Write as _;

use firmware::state::Cube as WordCube;

use crate::config::{RuntimeConfig, Signals};
use crate::feedback::memory::Layout;
use crate::feedback::tables::StateTables;
use crate::feedback::{analyse, rules, FeedbackError};
use crate::pack::PackSet;
use crate::provenance::Provenance;

use super::{header, DIGEST_ITEM};

use super::rust::{preamble, Const};

/// `tables` as Rust source for the firmware applications: the names the applications use are those of
/// the event-based tables — `NAME`, `event`, `EVENT_WORDS`, `INPUT_SLOTS`, `SEED`, `Policy`, `CONFIG`,
/// `EVENT_NAMES`, `AUTOMATON_NAMES` (the components), `Runtime<P, E>` and `CHECKED` (here the
/// `firmware::state::StateTables` the runtime takes) and `DIGEST` — with `SIGNAL_NAMES`, `COMPONENTS`,
/// `SIGNALS` and `TABLES` besides. Deterministic.
fn rust(
    tables: &StateTables,
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
    let facts = [format!(
        "Set '{name}' state-based (mode = state): {} components, {} signals, {} events, {} rules of {} cubes; \
         no supervisor tables.",
        tables.components.len(),
        tables.signals.len(),
        table.len(),
        tables.rules.len(),
        tables.cubes.len()
    )];
    header::write(&mut out, &facts, provenance, runtime, (&[String::from("mode=state")], &[]));
    // Where the tables begin: their digest covers what follows the header (which names the command).
    let body = out.len();
    let layout: Vec<String> = tables.signals.iter().enumerate().map(|(i, s)| format!("{i} {s}")).collect();
    let _ = writeln!(out, "// Signal word, bit by bit: {}.", layout.join(", "));
    let _ = writeln!(out);
    let names: Vec<String> = table.ids().map(|e| table.name(e).to_owned()).collect();
    let consts = [
        Const::size("Words of an event bitset.", "EVENT_WORDS", tables.words),
        Const::size("State-vector components (the plants).", "COMPONENTS", tables.components.len()),
        Const::size(
            "Choice sites: component states with two or more commands leaving.",
            "SITES",
            tables.sites.len(),
        ),
        Const::size("Signals in the word.", "SIGNALS", tables.signals.len()),
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
        tables.components.len(),
        quoted(&tables.components)
    );
    let _ = writeln!(out, "/// Signal names by bit of the word, for logs.");
    let _ = writeln!(
        out,
        "pub static SIGNAL_NAMES: [&str; {}] = [{}];",
        tables.signals.len(),
        quoted(&tables.signals)
    );
    let _ = writeln!(out);
    let _ = writeln!(out, "/// Per controllable event in id order: the end of its cubes in `CUBES`.");
    let _ = writeln!(out, "static RULES: [firmware::state::Rule; {}] = [", tables.rules.len());
    for r in &tables.rules {
        let _ = writeln!(
            out,
            "    firmware::state::Rule {{ event: {}, end: {} }}, // {}",
            r.event,
            r.end,
            names.get(usize::from(r.event)).map_or("", String::as_str)
        );
    }
    let _ = writeln!(out, "];");
    let _ =
        writeln!(out, "/// F_σ of every rule, cube after cube: a cube holds when `word & mask == value`.");
    let _ = writeln!(out, "static CUBES: [firmware::state::Cube; {}] = [", tables.cubes.len());
    let mut start = 0;
    for r in &tables.rules {
        let event = names.get(usize::from(r.event)).map_or("", String::as_str);
        for c in tables.cubes.get(start..usize::from(r.end)).unwrap_or_default() {
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
    let _ = writeln!(out, "static WRITES: [firmware::state::Cube; {}] = [", tables.writes.len());
    for (w, n) in tables.writes.iter().zip(&names) {
        let _ = writeln!(out, "    {}, // {n}", cube(w));
    }
    let _ = writeln!(out, "];");
    let holders: Vec<String> = tables.holders.iter().map(|h| format!("0x{h:x}")).collect();
    let _ = writeln!(out, "/// Per event id, the components whose plant has it (bit per component).");
    let _ = writeln!(out, "static HOLDERS: [u32; {}] = [{}];", holders.len(), holders.join(", "));
    let ends: Vec<String> = tables.ends.iter().map(u16::to_string).collect();
    let _ = writeln!(out, "/// Per component, the end of its states in `READINGS`.");
    let _ = writeln!(out, "static COMPONENT_ENDS: [u16; {}] = [{}];", ends.len(), ends.join(", "));
    let _ = writeln!(out, "/// Every component's states: formula, events leaving, code.");
    let _ = writeln!(
        out,
        "static READINGS: [firmware::state::Reading<EVENT_WORDS>; {}] = [",
        tables.readings.len()
    );
    for (code, (label, c, leaving)) in tables.readings.iter().enumerate() {
        let _ = writeln!(
            out,
            "    firmware::state::Reading {{ cube: {}, leaving: [{}], code: {code} }}, // {label}",
            cube(c),
            hex(leaving)
        );
    }
    let _ = writeln!(out, "];");
    let owned: Vec<String> = tables.plant_events.iter().map(|w| format!("[{}]", hex(w))).collect();
    let _ = writeln!(out, "/// Per component: the commands it owns.");
    let _ =
        writeln!(out, "static PLANT_EVENTS: [[u32; EVENT_WORDS]; {}] = [{}];", owned.len(), owned.join(", "));
    let sites: Vec<String> = tables.sites.iter().map(u16::to_string).collect();
    let _ = writeln!(out, "/// The choice sites, as reading codes.");
    let _ = writeln!(out, "static CHOICE_SITES: [u16; {}] = [{}];", sites.len(), sites.join(", "));
    let _ = writeln!(out);
    let _ = writeln!(out, "/// The tables the state-based runtime takes.");
    let _ = writeln!(
        out,
        "pub static TABLES: firmware::state::StateTables<'static, EVENT_WORDS> = firmware::state::StateTables {{"
    );
    let _ = writeln!(out, "    initial: 0x{:08x},", tables.initial);
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
    let _ = writeln!(out, "    controllable: [{}],", hex(&tables.controllable));
    let _ = writeln!(out, "    plant_events: &PLANT_EVENTS,");
    let _ = writeln!(out, "    sites: &CHOICE_SITES,");
    let _ = writeln!(out, "}};");
    let _ = writeln!(out, "/// What the applications hand the runtime (the event-based tables' name).");
    let _ =
        writeln!(out, "pub static CHECKED: &firmware::state::StateTables<'static, EVENT_WORDS> = &TABLES;");
    let digest = firmware::build::image::digest_hex(out.get(body..).unwrap_or_default().as_bytes());
    let _ = writeln!(
        out,
        "/// The tables' digest, which the firmware answers the link's TABLES with (`firmware::link`): \
         FNV-1a of this file from below its header up to here (state tables have no image)."
    );
    let _ = writeln!(out, "{DIGEST_ITEM}{digest}\";");
    out
}

/// The tables of the state-based firmware for `set` under the state vectors `signals`: the same f and
/// the same rules as the PLC program (F_σ exact when `[state] exact`), as Rust source. Refused: an
/// input buffer of 0 or more than 65535 slots, a feedback the supervisors' memory decides (the
/// firmware keeps no supervisor state), and what [`StateTables::build`] refuses.
pub fn firmware_tables(
    set: &PackSet,
    signals: Signals,
    name: &str,
    runtime: &RuntimeConfig,
    provenance: &Provenance,
) -> Result<String, FeedbackError> {
    if runtime.input_buffer == 0 || runtime.input_buffer > usize::from(u16::MAX) {
        return Err(FeedbackError::Vector {
            key: "runtime.input_buffer".into(),
            message: format!("{} slots: 1 to 65535", runtime.input_buffer),
        });
    }
    let exact = signals.exact;
    let (vector, f) = analyse(set, signals, false, &[])?;
    let rules = rules(&vector, &f, &Layout::default(), exact);
    Ok(rust(&StateTables::build(set, &vector, &f, &rules)?, set, name, runtime, provenance))
}
