//! Bit streams, most significant bit first, for the layouts that pack fields narrower than a byte.

// Field widths are the firmware encoder's own (the `compact` tables it builds are these bit streams).
pub use firmware::build::compact::width;

/// Reads fields written by the firmware's `compact` encoder (`firmware::build::compact::Writer`);
/// `None` past the end.
pub struct Reader<'a> {
    bytes: &'a [u8],
    /// Position in bits.
    pub at: usize,
}

impl<'a> Reader<'a> {
    /// A reader at bit `at` of `bytes`.
    pub fn new(bytes: &'a [u8], at: usize) -> Self {
        Reader { bytes, at }
    }

    /// The next `bits` bits as a number.
    pub fn get(&mut self, bits: u32) -> Option<usize> {
        let mut value = 0usize;
        for _ in 0..bits {
            let byte = self.bytes.get(self.at / 8)?;
            value = (value << 1) | usize::from((byte >> (7 - self.at % 8)) & 1);
            self.at += 1;
        }
        Some(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use firmware::build::compact::Writer;

    #[test]
    fn widths() {
        assert_eq!([0, 1, 2, 3, 4, 5, 121, 256, 257].map(width), [0, 0, 1, 2, 2, 3, 7, 8, 9]);
    }

    proptest::proptest! {
        #[test]
        fn fields_round_trip(fields in proptest::collection::vec((0usize..1 << 20, 0u32..=20), 0..40)) {
            let mut w = Writer::default();
            for &(v, b) in &fields {
                w.put(v, b);
            }
            let total: u32 = fields.iter().map(|f| f.1).sum();
            proptest::prop_assert_eq!(w.bit_len(), total as usize);
            let bytes = w.into_bytes();
            proptest::prop_assert_eq!(bytes.len(), (total as usize).div_ceil(8));
            let mut r = Reader::new(&bytes, 0);
            for &(v, b) in &fields {
                proptest::prop_assert_eq!(r.get(b), Some(v & ((1 << b) - 1)));
            }
        }
    }
}
