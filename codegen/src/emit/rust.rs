//! The writer of the emitted Rust file (see [`emit`] for what it defines).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use firmware::build::{bitset, unowned, SideTables};

use super::header;
use super::policy::{fault_value, ram_bytes, rust_type};
use super::{EmitError, DIGEST_ITEM};
use crate::config::{BoardSpec, ChoicePolicy, RuntimeConfig, SamplingSpec};
use crate::pack::tables::Packed;
use crate::provenance::Provenance;
use firmware::table::layout::name as layout_name;

/// Rust source for `firmware`'s applications (`include!`d inside a module): constants `NAME`,
/// `EVENT_WORDS`, `AUTOMATA`, `SITES`, `INPUT_SLOTS`, `SEED`, `WIDE`, `MASK_BYTES`, `LAYOUT`, `CONFIG`,
/// the types `Policy` and `Runtime<P, E>` (the runtime built for these tables), a module `event` with
/// one `u8` constant per event, the names `EVENT_NAMES` and `AUTOMATON_NAMES` (for logs; the tables
/// hold none), the tables `packed` in their layout (private statics: `BLOCK` with every automaton's
/// records, `MASKS`, `DESCRIPTORS`, `HOLDER_LISTS`, `HOLDERS`, `PLANT_EVENTS`, `CHOICE_SITES`) under
/// `pub static SET: firmware::table::SupervisorSet<'static, EVENT_WORDS>`, the same set checked at compile
/// time as `pub static CHECKED: firmware::table::CheckedSet`, a module `m0plus` with the same constants,
/// `Runtime`, `SET` and `CHECKED` for the Cortex-M0+ (the tables `m0plus` of the same set, `indexed`
/// by default, when it is `Ok`, else the top level's, with the reason it gives), and the board tables
/// `BOARD`, `INPUT_PINS`, `INPUT_PULLS`, `OUTPUT_PINS` (empty without a `[board]`).
/// `name` names the set, `runtime` is the run-time configuration the tables carry, `board` the pin map
/// (without one the board tables are empty). Deterministic: the same arguments give the same bytes.
pub fn emit(
    packed: &Packed,
    m0plus: Result<&Packed, String>,
    name: &str,
    runtime: &RuntimeConfig,
    board: Option<&BoardSpec>,
    provenance: &Provenance,
) -> Result<String, EmitError> {
    let side = side_tables(packed)?;
    if runtime.input_buffer == 0 || runtime.input_buffer > usize::from(u16::MAX) {
        return Err(EmitError::InputBuffer { capacity: runtime.input_buffer });
    }
    let mut out = String::new();
    header(&mut out, packed, &m0plus, &side, name, runtime, provenance);
    body(&mut out, packed, &side, name, runtime)?;
    m0plus_module(&mut out, packed, &m0plus)?;
    let none = BoardSpec {
        name: String::from("none"),
        sampling: SamplingSpec::Interrupt,
        sample_period_us: None,
        inputs: Vec::new(),
        outputs: Vec::new(),
        internal: Vec::new(),
    };
    out.push('\n');
    out.push_str(&super::board::rust(board.unwrap_or(&none), packed)?);
    Ok(out)
}

/// The side tables of `packed`, refusing a controllable event no plant generates.
fn side_tables(packed: &Packed) -> Result<SideTables, EmitError> {
    if let Some(e) = unowned(packed) {
        return Err(EmitError::Unowned { event: packed.event_names[e].clone() });
    }
    Ok(SideTables::of(packed)?)
}

fn header(
    out: &mut String,
    packed: &Packed,
    m0plus: &Result<&Packed, String>,
    side: &SideTables,
    name: &str,
    runtime: &RuntimeConfig,
    provenance: &Provenance,
) {
    let plants = packed.plants;
    let blocks: usize = packed.automata.iter().map(|b| b.block.len()).sum();
    let words = packed.words();
    let set = format!(
        "Set '{}': {} plants, {} supervisors, {} events; layout {}, {} bytes of blocks + {} bytes of masks ({} masks).",
        name,
        plants,
        packed.automata.len() - plants,
        packed.event_names.len(),
        layout_name(packed.layout.id()),
        blocks,
        packed.mask_bytes(),
        packed.masks.len()
    );
    let m0 = match m0plus {
        Ok(m0) => format!(
            "Cortex-M0+ tables (`m0plus`): layout {}, {} bytes of blocks + {} bytes of masks + {} bytes of holder lists.",
            layout_name(m0.layout.id()),
            m0.automata.iter().map(|b| b.block.len()).sum::<usize>(),
            m0.mask_bytes(),
            2 * m0.holder_lists().len()
        ),
        Err(e) => format!("Cortex-M0+ tables (`m0plus`): layout {} ({e}).", layout_name(packed.layout.id())),
    };
    let layout = format!("layout={}", runtime.layout.map_or(String::from("default"), |l| l.to_string()));
    header::write(out, &[set, m0], provenance, runtime, (&[], &[layout]));
    let ram: Vec<String> =
        ChoicePolicy::ALL.iter().map(|&p| format!("{p} {}", ram_bytes(p, words, side.sites.len()))).collect();
    let _ = writeln!(
        out,
        "// Choice-policy RAM in bytes ({} choice sites): {}",
        side.sites.len(),
        ram.join(", ")
    );
    let _ = writeln!(out);
}

fn body(
    out: &mut String,
    packed: &Packed,
    side: &SideTables,
    name: &str,
    runtime: &RuntimeConfig,
) -> Result<(), EmitError> {
    let words = packed.words();
    let consts = [
        Const::size("Words of an event bitset.", "EVENT_WORDS", words),
        Const::size("Automata in the set (plants first).", "AUTOMATA", packed.automata.len()),
        Const::size("Choice sites with two or more controllable out-events.", "SITES", side.sites.len()),
        Const::size("Slots of the input queue (capacity + 1).", "INPUT_SLOTS", runtime.input_buffer + 1),
    ];
    let controllable = |e: usize| bitset::contains(&packed.controllable, e);
    preamble(out, name, &packed.event_names, &controllable, &consts, runtime);
    let automata: Vec<String> = packed.automata.iter().map(|b| format!("{:?}", b.name)).collect();
    let _ = writeln!(out, "/// Automaton names, plants first, for logs.");
    let _ =
        writeln!(out, "pub static AUTOMATON_NAMES: [&str; {}] = [{}];", automata.len(), automata.join(", "));
    let _ = writeln!(out);
    let _ = writeln!(out, "// The tables of cores with unaligned loads (the QEMU board's Cortex-M3).");
    tables(out, packed, side)
}

/// One `pub const` of an emitted file's preamble: its doc line, name, type and value.
pub(crate) struct Const {
    doc: &'static str,
    name: &'static str,
    ty: &'static str,
    value: String,
}

impl Const {
    /// A `usize` size constant.
    pub(crate) fn size(doc: &'static str, name: &'static str, value: usize) -> Self {
        Const { doc, name, ty: "usize", value: value.to_string() }
    }
}

/// The items every emitted tables file opens with, supervisor tables and state tables alike: `NAME`, the
/// module `event` of event ids, the size constants `consts` then `SEED`, the `Policy` type, `CONFIG`, and
/// `EVENT_NAMES` for logs. One writer, so the applications find the same names in either file.
pub(crate) fn preamble(
    out: &mut String,
    name: &str,
    events: &[String],
    controllable: &dyn Fn(usize) -> bool,
    consts: &[Const],
    runtime: &RuntimeConfig,
) {
    let _ = writeln!(out, "/// Name of the supervisor set.");
    let _ = writeln!(out, "pub const NAME: &str = {name:?};");
    let _ = writeln!(out);
    let _ = writeln!(out, "/// Global event ids.");
    let _ = writeln!(out, "pub mod event {{");
    for ((e, ident), event) in event_idents(events).iter().enumerate().zip(events) {
        let kind = if controllable(e) { "controllable" } else { "uncontrollable" };
        let _ = writeln!(out, "    /// `{event}` ({kind}).");
        let _ = writeln!(out, "    pub const {ident}: u8 = {e};");
    }
    let _ = writeln!(out, "}}");
    let _ = writeln!(out);
    let seed = Const {
        doc: "Entropy seed of the random policies (QEMU; a board reseeds).",
        name: "SEED",
        ty: "u64",
        value: runtime.seed.to_string(),
    };
    for c in consts.iter().chain([&seed]) {
        let _ = writeln!(out, "/// {}\npub const {}: {} = {};", c.doc, c.name, c.ty, c.value);
    }
    let _ = writeln!(out, "/// The choice policy ({}).", runtime.policy);
    let _ = writeln!(out, "pub type Policy = {};", rust_type(runtime.policy));
    let _ = writeln!(out, "/// Run-time configuration.");
    let _ = writeln!(out, "pub const CONFIG: firmware::runtime::Config = firmware::runtime::Config {{");
    let _ = writeln!(out, "    guard: {},", runtime.guard);
    let _ = writeln!(out, "    on_fault: {},", fault_value(runtime.on_fault));
    let _ = writeln!(out, "    reseed_every: {},", runtime.reseed_every);
    let _ = writeln!(out, "}};");
    let _ = writeln!(out);
    let quoted: Vec<String> = events.iter().map(|n| format!("{n:?}")).collect();
    let _ = writeln!(out, "/// Event names by global id, for logs (the tables hold no names).");
    let _ = writeln!(out, "pub static EVENT_NAMES: [&str; {}] = [{}];", quoted.len(), quoted.join(", "));
}

/// The module `m0plus`: the tables the Cortex-M0+ runs — `m0plus` (the set in the `indexed` layout by
/// default), or, when there is none, the top level's `packed` tables with the reason.
fn m0plus_module(
    out: &mut String,
    packed: &Packed,
    m0plus: &Result<&Packed, String>,
) -> Result<(), EmitError> {
    let _ = writeln!(out);
    let _ = writeln!(out, "/// The tables the Cortex-M0+ runs (the Pico's firmware).");
    let _ = writeln!(out, "pub mod m0plus {{");
    match m0plus {
        Ok(packed) => {
            let side = side_tables(packed)?;
            let mut inner = String::new();
            let _ = writeln!(inner, "use super::{{AUTOMATA, EVENT_WORDS}};");
            let _ = writeln!(inner);
            tables(&mut inner, packed, &side)?;
            for line in inner.lines() {
                let _ = if line.is_empty() { writeln!(out) } else { writeln!(out, "    {line}") };
            }
        }
        Err(e) => {
            let _ = writeln!(out, "    // The `{}` tables: {e}.", layout_name(packed.layout.id()));
            let _ = writeln!(
                out,
                "    pub use super::{{Position, Runtime, CHECKED, DIGEST, LAYOUT, MASK_BYTES, SET, WIDE}};"
            );
        }
    }
    let _ = writeln!(out, "}}");
    Ok(())
}

/// The layout's constants, the `Position` and `Runtime` types and the tables of `packed` with their side
/// tables `side`: the image (`IMAGE`, `DIGEST` — public, the firmware reports it —, checked here with the runtime's own check), its sections
/// in flash (`SECTIONS`), `SET` and `CHECKED` over them.
fn tables(out: &mut String, packed: &Packed, side: &SideTables) -> Result<(), EmitError> {
    let layout = layout_name(packed.layout.id());
    let image = firmware::build::image::write(packed, side);
    firmware::build::image::check(&image).map_err(EmitError::Check)?;
    let position = if packed.position_bytes == 2 { "u16" } else { "u32" };
    let _ = writeln!(
        out,
        "/// Wide fields: 2-byte mask ids and handles (`ranked`, `indexed`), 4-byte targets (`offset`)."
    );
    let _ = writeln!(out, "pub const WIDE: bool = {};", packed.wide);
    let _ = writeln!(out, "/// Bytes of one mask in the pool (0: a layout without a pool).");
    let _ = writeln!(out, "pub const MASK_BYTES: usize = {};", packed.mask_width());
    let _ = writeln!(out, "/// The record layout (`{layout}`): the reader the runtime compiles in.");
    let _ = writeln!(out, "pub const LAYOUT: u8 = firmware::table::layout::{};", const_name(layout));
    let _ = writeln!(
        out,
        "/// How the runtime holds a state's position: `u16` while every one is below 65 536, else `u32`."
    );
    let _ = writeln!(out, "pub type Position = {position};");
    let _ =
        writeln!(out, "/// The runtime over these tables, choosing with `P` and drawing entropy from `E`.");
    let _ = writeln!(
        out,
        "pub type Runtime<P, E> = firmware::runtime::Runtime<\n    'static,\n    P,\n    E,\n    EVENT_WORDS,\n    AUTOMATA,\n    WIDE,\n    MASK_BYTES,\n    LAYOUT,\n    Position,\n>;"
    );
    contents(out, packed, &image);
    let _ = writeln!(
        out,
        "/// The tables as one image (`firmware::table::image`): a header, read at compile time only, then the \
         sections. Checked by codegen when it wrote them and by the build script that compiles them \
         (apps/cell/build.rs, `codegen::project::build_script`), with the runtime's own check."
    );
    let _ = writeln!(out, "{}", firmware::build::image::literal(&image, ""));
    let _ = writeln!(
        out,
        "/// The image's digest: the build script hands the compiler those of the images it checked, and the \
         firmware answers the link's TABLES with it (`firmware::link`)."
    );
    let _ = writeln!(out, "{DIGEST_ITEM}{}\";", firmware::build::image::digest_hex(&image));
    let sections = image.len() - firmware::table::image::header_bytes(packed.words());
    let _ = writeln!(out, "/// The image's sections in flash, 4-byte aligned.");
    let _ = writeln!(
        out,
        "static SECTIONS: firmware::table::image::Aligned<[u8; {sections}]> =\n    \
         firmware::table::image::Aligned(*firmware::table::image::sections(IMAGE));"
    );
    let _ = writeln!(
        out,
        "/// The set the runtime runs: the image's header read and its sections sliced, at compile time."
    );
    let _ = writeln!(
        out,
        "pub static SET: firmware::table::SupervisorSet<'static, EVENT_WORDS, Position> =\n    \
         firmware::table::image::set(IMAGE, &SECTIONS);"
    );
    let _ = writeln!(
        out,
        "/// The set, checked by this build's build script: a build that did not check these tables does not \
         compile."
    );
    let _ = writeln!(
        out,
        "pub static CHECKED: firmware::table::CheckedSet<'static, EVENT_WORDS, AUTOMATA, WIDE, MASK_BYTES, LAYOUT, Position> =\n    \
         firmware::table::image::checked(&SET, DIGEST, env!(\"SCT_TABLES_CHECKED\"));"
    );
    Ok(())
}

/// The image's table of contents, as comments: every section's bytes and every automaton's block.
fn contents(out: &mut String, packed: &Packed, image: &[u8]) {
    let head = firmware::table::image::header_bytes(packed.words());
    let _ = writeln!(
        out,
        "// The image: a header of {head} bytes, then {} bytes of sections:",
        image.len() - head
    );
    if let Some(sections) = firmware::build::image::section_bytes(image) {
        let named: Vec<String> = firmware::build::image::SECTION_NAMES
            .iter()
            .zip(sections)
            .map(|(name, (at, bytes))| format!("{name} {bytes} B at {at}"))
            .collect();
        for line in named.chunks(4) {
            let _ = writeln!(out, "//   {}", line.join(", "));
        }
    }
    let fields = match packed.layout {
        firmware::build::Layout::Ranked | firmware::build::Layout::Indexed => {
            format!("{}-byte mask ids and handles", packed.field_bytes())
        }
        firmware::build::Layout::Offset => format!("{}-byte targets", packed.transition_bytes() - 1),
        _ => String::from("as the layout packs them"),
    };
    let blocks: Vec<String> = packed
        .automata
        .iter()
        .zip(packed.starts())
        .map(|(b, start)| format!("{} from byte {start} (scale {})", b.name, b.scale))
        .collect();
    let _ = writeln!(out, "// Blocks ({fields}):");
    for line in blocks.chunks(4) {
        let _ = writeln!(out, "//   {}", line.join(", "));
    }
}

/// The name of `firmware::table::layout`'s constant for the layout called `name`.
fn const_name(name: &str) -> String {
    name.replace('-', "_").to_ascii_uppercase()
}

/// Upper-case identifiers for the event names: non-alphanumerics become `_`, a leading digit gets `E_`,
/// and names that would collide get their id appended.
pub fn event_idents(names: &[String]) -> Vec<String> {
    let base: Vec<String> = names
        .iter()
        .map(|n| {
            let mut id: String = n
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_uppercase() } else { '_' })
                .collect();
            if !id.starts_with(|c: char| c.is_ascii_alphabetic()) {
                id.insert_str(0, "E_");
            }
            id
        })
        .collect();
    let mut count: BTreeMap<&str, usize> = BTreeMap::new();
    for id in &base {
        *count.entry(id.as_str()).or_default() += 1;
    }
    base.iter()
        .enumerate()
        .map(|(e, id)| if count[id.as_str()] > 1 { format!("{id}_{e}") } else { id.clone() })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::pack::{ranked, PackSet};
    use firmware::build::HostTables;

    #[test]
    fn host_tables_pass_the_runtime_check_and_refuse_another_width() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S")]).unwrap();
        let host = HostTables::<1>::new(ranked::encode(&set).unwrap()).unwrap();
        let rt = host.set();
        assert_eq!(rt.check(2), Ok(()));
        assert_eq!(rt.plants, 1);
        assert_eq!((rt.automata[1].start, rt.block.len()), (4, 8));
        let after_a = rt.step(1, 0, 0).unwrap();
        assert_eq!(rt.step(1, after_a, 1), Some(0));
        let err = HostTables::<2>::new(ranked::encode(&set).unwrap()).unwrap_err();
        assert_eq!(err.to_string(), "the set's event bitsets take 1 words, the runtime was built for 2");
    }

    #[test]
    fn a_site_is_a_plant_state_with_two_owned_controllable_events() {
        use crate::model::{Automaton, Kind};
        let mut g = Automaton::new("G", Kind::Plant);
        let s0 = g.add_state("0", true).unwrap();
        let s1 = g.add_state("1", false).unwrap();
        let a = g.add_event("a", true).unwrap();
        let b = g.add_event("b", true).unwrap();
        let u = g.add_event("u", false).unwrap();
        g.initial = Some(s0);
        g.add_transition(s0, a, s1);
        g.add_transition(s0, b, s1);
        g.add_transition(s1, u, s0);
        g.add_transition(s1, a, s1);
        let packed = ranked::encode(&PackSet::new(vec![g.clone()], vec![]).unwrap()).unwrap();
        let side = side_tables(&packed).unwrap();
        assert_eq!(side.sites, [0]);
        assert_eq!(side.plant_events, [vec![0b011]]);
        assert_eq!(side.holders, [1, 1, 1]);
        // Sites are offsets in the blocks back to back (after H's record of 2 bytes); holder masks take a
        // byte per 8 automata.
        let mut h = Automaton::new("H", Kind::Plant);
        let q = h.add_state("0", true).unwrap();
        let x = h.add_event("x", false).unwrap();
        h.initial = Some(q);
        h.add_transition(q, x, q);
        let sups = (0..8)
            .map(|i| {
                let mut s = h.clone();
                s.name = format!("S{i}");
                s
            })
            .collect();
        let set = PackSet::new(vec![h, g], sups);
        let side = side_tables(&ranked::encode(&set.unwrap()).unwrap()).unwrap();
        assert_eq!(side.sites, [2]);
        assert_eq!(side.holders.len(), 2 * 4);
    }

    #[test]
    fn idents_are_valid_and_unique() {
        let names: Vec<String> = ["e1_lig", "2go", "a-b", "a_b", ""].iter().map(|s| s.to_string()).collect();
        assert_eq!(event_idents(&names), ["E1_LIG", "E_2GO", "A_B_2", "A_B_3", "E_"]);
    }
}
