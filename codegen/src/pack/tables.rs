//! This module is the home of the firmware's tables of a [`PackSet`] in any layout, from the one encoder
//! the firmware ships (`firmware::build`): the bytes `codegen pack` measures are those `codegen emit`
//! writes and the runtime reads — the image's sections ([`firmware::table::image`]), each named.

use firmware::build::image::{self, SECTION_NAMES};
use firmware::build::{SideTables, Source, SourceAutomaton};

use super::{Layout, PackError, PackSet, Role, Size};

pub use firmware::build::{Block, Packed, Record};

/// `set` as the encoder takes it: the members' transitions over global ids, plants first.
pub fn source(set: &PackSet) -> Source {
    let events = set.events();
    Source {
        event_names: events.ids().map(|e| events.name(e).to_owned()).collect(),
        controllable: events.ids().map(|e| events.is_controllable(e)).collect(),
        plants: set.members().iter().filter(|m| m.role == Role::Plant).count(),
        automata: set
            .members()
            .iter()
            .map(|m| SourceAutomaton {
                name: m.name().to_owned(),
                initial: m.initial().index(),
                alphabet: m.alphabet().iter().map(|e| e.index()).collect(),
                out: (0..m.state_count())
                    .map(|s| m.out(s).map(|(e, t)| (e.index(), t.index())).collect())
                    .collect(),
            })
            .collect(),
    }
}

/// The firmware's tables of `set` in `layout`, or the limit of that layout the set breaks (named with
/// the layout).
pub fn encode(set: &PackSet, layout: Layout) -> Result<Packed, PackError> {
    firmware::build::encode_as(&source(set), layout.firmware())
        .map_err(|source| PackError::Layout { layout: layout.name(), source })
}

/// The image the firmware compiles for `packed` (`firmware::table::image`), or the runtime limit its
/// side tables break (more automata than the runtime's holder masks have bits).
pub fn image(packed: &Packed) -> Result<Vec<u8>, PackError> {
    let layout = Layout::of_firmware(packed.layout);
    let side =
        SideTables::of(packed).map_err(|source| PackError::Layout { layout: layout.name(), source })?;
    Ok(image::write(packed, &side))
}

/// The sections of the image that every layout holds alike: the runtime's side tables.
const SHARED: [usize; 3] = [image::PLANT_EVENTS, image::SITES, image::HOLDERS];

/// What the tables of `packed` take, measured on the image the firmware compiles: per automaton its
/// block; the layout's other sections named (with the controllable events' words, which the set holds
/// beside them); the runtime's side tables every layout holds alike, apart.
pub fn size(packed: &Packed) -> Result<Size, PackError> {
    let layout = Layout::of_firmware(packed.layout);
    let bytes = image(packed)?;
    let sections = image::section_bytes(&bytes).unwrap_or_default();
    let named = |keep: &dyn Fn(usize) -> bool| -> Vec<(&'static str, usize)> {
        SECTION_NAMES
            .iter()
            .zip(sections)
            .enumerate()
            .filter(|&(i, _)| keep(i))
            .map(|(_, (&n, (_, b)))| (n, b))
            .collect()
    };
    let mut side_tables = named(&|i| i != image::BLOCKS && !SHARED.contains(&i));
    side_tables.push(("controllability", 4 * packed.words()));
    Ok(Size {
        layout: layout.name(),
        per_automaton: packed.automata.iter().map(|b| (b.name.clone(), b.block.len())).collect(),
        side_tables,
        shared: named(&|i| SHARED.contains(&i)),
    })
}
