//! The layouts by name, for the CLI and the report.

use super::{compact, memory_safe, offset, ranked, Measure, PackError, PackSet, Size};

/// One of the byte layouts of this module.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Layout {
    /// The reference tool's vector ([`memory_safe`]).
    MemorySafe,
    /// Records with u16 offsets, the runtime's former table ([`offset`]).
    Offset,
    /// Out-mask pool and rank-addressed targets, the runtime's table ([`ranked`]).
    Ranked,
    /// Targets addressed by the event's place in the alphabet and masks of whole words, the runtime's
    /// table on the Cortex-M0+ ([`ranked`]).
    Indexed,
    /// Bit-packed over local alphabets ([`compact`]).
    Compact,
}

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
        }
        assert_eq!(Layout::from_name("dense"), None);
    }
}
