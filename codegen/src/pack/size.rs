//! What a packed set costs in bytes: the blocks per automaton and every side table, named.

/// The bytes one layout takes for one set, measured on the image the firmware compiles.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Size {
    /// Layout name.
    pub layout: &'static str,
    /// Per automaton (plants first, then supervisors): its name and the bytes of its block.
    pub per_automaton: Vec<(String, usize)>,
    /// Every other table of the layout (descriptors, mask pool, holder lists, initial states,
    /// controllability), each with its bytes. Event names are not counted: they serve logs, not
    /// decisions.
    pub side_tables: Vec<(&'static str, usize)>,
    /// The runtime's side tables, the same in every layout (per event the automata holding it, per
    /// plant the events it generates, the choice sites), each with its bytes: the firmware holds them
    /// besides the layout's.
    pub shared: Vec<(&'static str, usize)>,
}

impl Size {
    /// Bytes of all blocks.
    pub fn blocks(&self) -> usize {
        self.per_automaton.iter().map(|(_, b)| b).sum()
    }

    /// Bytes of the layout's side tables.
    pub fn side(&self) -> usize {
        self.side_tables.iter().map(|(_, b)| b).sum()
    }

    /// The layout's bytes: blocks and side tables.
    pub fn total(&self) -> usize {
        self.blocks() + self.side()
    }

    /// Bytes of the runtime's side tables every layout adds.
    pub fn shared_bytes(&self) -> usize {
        self.shared.iter().map(|(_, b)| b).sum()
    }
}
