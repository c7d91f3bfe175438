//! What a packed set costs in bytes: the blocks per automaton and every side table, named; and
//! [`Measure`], which every layout's tables implement.

/// The bytes one layout takes for one set, measured on the bytes actually produced.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Size {
    /// Layout name.
    pub layout: &'static str,
    /// Per automaton (plants first, then supervisors): its name and the bytes of its block.
    pub per_automaton: Vec<(String, usize)>,
    /// Every other table the runtime needs (offsets, initial states, alphabets, controllability, …),
    /// each with its bytes. Event names are not counted: they serve logs, not decisions.
    pub side_tables: Vec<(&'static str, usize)>,
}

impl Size {
    /// Bytes of all blocks.
    pub fn blocks(&self) -> usize {
        self.per_automaton.iter().map(|(_, b)| b).sum()
    }

    /// Bytes of all side tables.
    pub fn side(&self) -> usize {
        self.side_tables.iter().map(|(_, b)| b).sum()
    }

    /// Everything: blocks and side tables.
    pub fn total(&self) -> usize {
        self.blocks() + self.side()
    }
}

/// A packed set measures itself: every layout's tables implement this, so the report treats them alike.
pub trait Measure {
    /// Bytes per automaton and of each side table, measured on the bytes produced.
    fn size(&self) -> Size;
}
