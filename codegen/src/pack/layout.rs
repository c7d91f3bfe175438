//! The layouts by name, for the CLI and the report: the manifest's [`Layout`] (`config`), packed here by
//! the firmware's encoder ([`super::tables`]).

use super::{tables, PackError, PackSet, Size};
pub use crate::config::Layout;

impl Layout {
    /// Every layout, in report order.
    pub const ALL: [Layout; 5] =
        [Layout::MemorySafe, Layout::Offset, Layout::Ranked, Layout::Indexed, Layout::Compact];

    /// The name `--layout` takes.
    pub fn name(self) -> &'static str {
        match self {
            Layout::MemorySafe => "memory-safe",
            Layout::Offset => "offset",
            Layout::Ranked => "ranked",
            Layout::Indexed => "indexed",
            Layout::Compact => "compact",
        }
    }

    /// The layout called `name`.
    pub fn from_name(name: &str) -> Option<Layout> {
        Layout::ALL.into_iter().find(|l| l.name() == name)
    }

    /// The firmware encoder's layout: the one the runtime reads.
    pub fn firmware(self) -> firmware::build::Layout {
        match self {
            Layout::MemorySafe => firmware::build::Layout::MemorySafe,
            Layout::Offset => firmware::build::Layout::Offset,
            Layout::Ranked => firmware::build::Layout::Ranked,
            Layout::Indexed => firmware::build::Layout::Indexed,
            Layout::Compact => firmware::build::Layout::Compact,
        }
    }

    /// The layout of the firmware encoder's `layout`.
    pub fn of_firmware(layout: firmware::build::Layout) -> Layout {
        match layout {
            firmware::build::Layout::MemorySafe => Layout::MemorySafe,
            firmware::build::Layout::Offset => Layout::Offset,
            firmware::build::Layout::Ranked => Layout::Ranked,
            firmware::build::Layout::Indexed => Layout::Indexed,
            firmware::build::Layout::Compact => Layout::Compact,
        }
    }

    /// Packs `set` as the firmware runs it and measures the bytes produced ([`tables::size`]).
    pub fn size(self, set: &PackSet) -> Result<Size, PackError> {
        tables::size(&tables::encode(set, self)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for l in Layout::ALL {
            assert_eq!(Layout::from_name(l.name()), Some(l));
            assert_eq!(Layout::of_firmware(l.firmware()), l);
            // The manifest's and the command line's name is the report's.
            assert_eq!(l.to_string(), l.name());
        }
        assert_eq!(Layout::from_name("dense"), None);
    }
}
