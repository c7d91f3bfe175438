//! This module is the home of which layout each core runs and whether its tables fit: the layout a
//! manifest names, else the defaults — `ranked` on the Cortex-M3, `indexed` on the Cortex-M0+ while it
//! fits the Pico, the M3's layout when it does not — and the [`Refusal`] of a layout that cannot hold a
//! set or whose tables exceed what a board's flash leaves them, naming the layout, the size, the limit
//! and what would fit instead.

use std::fmt;

use super::tables::{self, Packed};
use super::{Layout, PackError, PackSet};
use crate::config::RuntimeConfig;
use crate::target::flash::{Flash, APPLICATION};

/// A core the firmware is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Core {
    /// The Cortex-M3 (and the Cortex-M4 boards, which run its tables): QEMU's lm3s6965.
    CortexM3,
    /// The Cortex-M0+: the Raspberry Pi Pico's RP2040.
    CortexM0Plus,
}

impl Core {
    /// Both cores, the report's order.
    pub const ALL: [Core; 2] = [Core::CortexM3, Core::CortexM0Plus];

    /// The core's name in reports (`cortex-m3`).
    pub fn name(self) -> &'static str {
        match self {
            Core::CortexM3 => "cortex-m3",
            Core::CortexM0Plus => "cortex-m0+",
        }
    }

    /// The board `codegen run` builds for the core: its flash.
    pub fn flash(self) -> Flash {
        match self {
            Core::CortexM3 => Flash::qemu(),
            Core::CortexM0Plus => Flash::pico(),
        }
    }
}

/// A set's tables in a layout, with the flash they take.
#[derive(Clone, Debug)]
pub struct Fitted {
    /// The layout.
    pub layout: Layout,
    /// The tables.
    pub packed: Packed,
    /// Bytes of flash they take: the sections of their image ([`flash_bytes`]).
    pub bytes: usize,
}

/// Why a layout cannot run a set.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Why {
    /// The set breaks a limit of the layout (the encoder's words, naming the number and the limit).
    Limit(String),
    /// The tables take more flash than the board leaves them.
    Flash {
        /// Bytes of the tables.
        bytes: usize,
        /// The board's flash.
        flash: Flash,
    },
}

/// A layout refused for a set: why, and the layouts that would fit (each with its bytes, smallest
/// first).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct Refusal {
    /// The layout refused.
    pub layout: Layout,
    /// Why.
    pub why: Why,
    /// The layouts that hold the set (within the board's flash, when one was named), with their bytes.
    pub fits: Vec<(Layout, usize)>,
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "layout {}: ", self.layout.name())?;
        match &self.why {
            Why::Limit(limit) => write!(f, "{limit}")?,
            Why::Flash { bytes, flash } => write!(
                f,
                "the tables take {bytes} bytes, more than the {} bytes the {}'s {} bytes of flash leave them \
                 ({APPLICATION} kept for the application)",
                flash.for_tables(),
                flash.board,
                flash.bytes
            )?,
        }
        let mut fits = self.fits.iter();
        match fits.next() {
            Some((layout, bytes)) => {
                write!(f, "; --layout {} fits in {bytes} bytes", layout.name())?;
                for (layout, bytes) in fits {
                    write!(f, ", --layout {} in {bytes} bytes", layout.name())?;
                }
            }
            None => write!(f, "; no other layout fits")?,
        }
        write!(f, "; or reduce the supervisors (`codegen synth --reduce`)")
    }
}

/// Bytes of flash `packed` takes: the sections of its image, what the firmware's `SECTIONS` static
/// holds.
pub fn flash_bytes(packed: &Packed) -> Result<usize, PackError> {
    let image = tables::image(packed)?;
    Ok(image.len() - firmware::table::image::header_bytes(packed.words()))
}

/// `set`'s tables in `layout` and their flash, or why they cannot run: a limit of the layout, or more
/// bytes than `flash` leaves the tables.
fn measure(set: &PackSet, layout: Layout, flash: Option<&Flash>) -> Result<Fitted, Why> {
    let packed = tables::encode(set, layout).map_err(|e| Why::Limit(limit(e)))?;
    let bytes = flash_bytes(&packed).map_err(|e| Why::Limit(limit(e)))?;
    match flash {
        Some(flash) if bytes > flash.for_tables() => Err(Why::Flash { bytes, flash: *flash }),
        _ => Ok(Fitted { layout, packed, bytes }),
    }
}

/// The encoder's words for a limit, without the layout's name (the refusal names it).
fn limit(e: PackError) -> String {
    match e {
        PackError::Layout { source, .. } => source.to_string(),
        other => other.to_string(),
    }
}

/// `set`'s tables in `layout`, refused when the layout cannot hold the set or when they exceed what
/// `flash` leaves the tables (no flash: the layout's own limits only), the refusal listing the other
/// layouts that would fit.
pub fn fit(set: &PackSet, layout: Layout, flash: Option<&Flash>) -> Result<Fitted, Refusal> {
    measure(set, layout, flash).map_err(|why| {
        let mut fits: Vec<(Layout, usize)> = Layout::ALL
            .into_iter()
            .filter(|&l| l != layout)
            .filter_map(|l| measure(set, l, flash).ok().map(|f| (l, f.bytes)))
            .collect();
        fits.sort_by_key(|&(l, bytes)| (bytes, l));
        Refusal { layout, why, fits }
    })
}

/// The layout `core` runs for `config` and its tables: the manifest's layout, else the core's default
/// (`ranked` on the Cortex-M3; `indexed` on the Cortex-M0+, or the Cortex-M3's when `indexed` does not
/// fit), refused as [`fit`] refuses within `flash`.
pub fn choose(
    set: &PackSet,
    config: &RuntimeConfig,
    core: Core,
    flash: Option<&Flash>,
) -> Result<Fitted, Refusal> {
    let (m3, m0) = config.layouts();
    match core {
        Core::CortexM3 => fit(set, m3, flash),
        Core::CortexM0Plus => fit(set, m0, flash).or_else(|refusal| {
            // A default that does not fit falls back to the Cortex-M3's; a manifest's layout never does.
            match config.layout {
                None if m0 != m3 => fit(set, m3, flash).map_err(|_| refusal),
                _ => Err(refusal),
            }
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Automaton, Kind, StateId};

    /// A ring of `n` states over one event, with `k` self-loops on state 0 (a state of `k + 1`
    /// transitions).
    fn ring(n: u32, k: u32) -> Automaton {
        let mut g = Automaton::new("R", Kind::Plant);
        let e = g.add_event("e", false).unwrap();
        for i in 0..n {
            g.add_state(i.to_string(), i == 0).unwrap();
        }
        g.initial = Some(StateId::from_u32(0));
        for i in 0..n {
            g.add_transition(StateId::from_u32(i), e, StateId::from_u32((i + 1) % n));
        }
        for j in 0..k {
            let x = g.add_event(format!("x{j}"), false).unwrap();
            g.add_transition(StateId::from_u32(0), x, StateId::from_u32(0));
        }
        g
    }

    #[test]
    fn a_refusal_names_the_layout_the_limit_and_what_fits() {
        // 250 events leave state 0: more than a record's count byte holds in memory-safe and offset.
        let set = PackSet::new(vec![ring(4, 255)], vec![]).unwrap();
        let refusal = fit(&set, Layout::MemorySafe, None).unwrap_err();
        assert_eq!(refusal.layout, Layout::MemorySafe);
        assert!(refusal.fits.iter().all(|(l, _)| !matches!(l, Layout::MemorySafe | Layout::Offset)));
        let text = refusal.to_string();
        assert!(text.starts_with("layout memory-safe: state 0 of 'R' has 256 outgoing transitions, more than the limit of 255; --layout "), "{text}");
        assert!(text.ends_with("; or reduce the supervisors (`codegen synth --reduce`)"), "{text}");
    }

    #[test]
    fn a_board_without_room_refuses_every_layout_and_says_so() {
        let set = PackSet::new(vec![ring(100, 0)], vec![]).unwrap();
        let tiny = Flash { board: "tiny", bytes: APPLICATION + 200 };
        let refusal = fit(&set, Layout::Ranked, Some(&tiny)).unwrap_err();
        let Why::Flash { bytes, .. } = refusal.why else { panic!("{refusal}") };
        assert!(bytes > 200);
        // The compact ring (8 bits a state) fits in 200 bytes; no other does.
        assert_eq!(refusal.fits.iter().map(|f| f.0).collect::<Vec<_>>(), [Layout::Compact]);
        assert!(refusal.to_string().contains("more than the 200 bytes the tiny's"), "{refusal}");
    }

    #[test]
    fn the_cortex_m0_plus_default_falls_back_to_the_cortex_m3s_and_a_manifests_layout_never_does() {
        let set = PackSet::new(vec![ring(3000, 40)], vec![]).unwrap();
        let small = Flash { board: "small", bytes: APPLICATION + 14_000 };
        let indexed = fit(&set, Layout::Indexed, None).unwrap().bytes;
        let ranked = fit(&set, Layout::Ranked, None).unwrap().bytes;
        assert!(ranked <= 14_000 && indexed > 14_000, "{ranked} {indexed}");
        let default = RuntimeConfig::default();
        assert_eq!(choose(&set, &default, Core::CortexM0Plus, Some(&small)).unwrap().layout, Layout::Ranked);
        assert_eq!(choose(&set, &default, Core::CortexM0Plus, None).unwrap().layout, Layout::Indexed);
        let manifest = RuntimeConfig { layout: Some(Layout::Indexed), ..RuntimeConfig::default() };
        let refusal = choose(&set, &manifest, Core::CortexM0Plus, Some(&small)).unwrap_err();
        assert_eq!(refusal.layout, Layout::Indexed);
    }
}
