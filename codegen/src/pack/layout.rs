//! The layouts by name, for the CLI and the report: the manifest's [`Layout`] (`config`), packed here.

use super::{compact, memory_safe, offset, ranked, Measure, PackError, PackSet, Size};
pub use crate::config::Layout;

impl Layout {
    /// Every layout, in report order.
    pub const ALL: [Layout; 5] =
        [Layout::MemorySafe, Layout::Offset, Layout::Ranked, Layout::Indexed, Layout::Compact];

    /// The name `--layout` takes.
    pub fn name(self) -> &'static str {
        match self {
            Layout::MemorySafe => memory_safe::NAME,
            Layout::Offset => offset::NAME,
            Layout::Ranked => ranked::NAME,
            Layout::Indexed => ranked::INDEXED_NAME,
            Layout::Compact => compact::NAME,
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

    /// Packs `set` and measures the bytes produced.
    pub fn size(self, set: &PackSet) -> Result<Size, PackError> {
        Ok(match self {
            Layout::MemorySafe => memory_safe::encode(set)?.size(),
            Layout::Offset => offset::encode(set)?.size(),
            Layout::Ranked => ranked::encode(set)?.size(),
            Layout::Indexed => ranked::encode_indexed(set)?.size(),
            Layout::Compact => compact::encode(set)?.size(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for l in Layout::ALL {
            assert_eq!(Layout::from_name(l.name()), Some(l));
            // The manifest's and the command line's name is the report's.
            assert_eq!(l.to_string(), l.name());
        }
        assert_eq!(Layout::from_name("dense"), None);
    }
}
