//! The encoder of the `ranked` layout and of its `indexed` variant ([`crate::table`] describes both):
//! how a set is cut into records, which masks the pool holds, and which field width and scales are
//! chosen.
//!
//! * The pool holds each distinct out-mask once, in first-appearance order: automata in set order, each
//!   automaton's states in index order.
//! * An automaton's records come in its block with the initial state's first (handle 0), then the
//!   others in state-index order. In the `indexed` layout a record holds a target per event of the
//!   alphabet, 0 for those that do not leave the state, and masks take whole words.
//! * The field width is one for the whole set, so that the runtime is compiled for it: the encoder picks
//!   the smaller blocks of two candidates (1-byte fields on a tie) — 1-byte fields, when every mask id is
//!   below [`NARROW_IDS`] and every automaton has a scale in 1..=255 that puts every record start at a
//!   handle ≤ [`NARROW_HANDLE`] (each automaton with its smallest such scale); 2-byte fields, each
//!   automaton with the smallest scale that puts every record start at a handle ≤ [`WIDE_HANDLE`].
//!
//! Side tables of the layout itself: the mask pool (⌈e/8⌉ bytes per mask, then padding to read a whole
//! last word), per automaton a descriptor of [`DESCRIPTOR_BYTES`] and its alphabet (⌈e/32⌉ words), and
//! the controllability bitset (⌈e/32⌉ words). The side tables of the runtime's hot path are
//! [`super::SideTables`].

use alloc::collections::BTreeMap;
use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use super::bitset;
use super::{BuildError, ReadError};
use crate::table::{MAX_EVENTS, MAX_MASKS};

/// Mask ids a 1-byte field numbers.
pub const NARROW_IDS: usize = 256;
/// Most states of one automaton: a handle is at most 2 bytes.
pub const MAX_STATES: usize = 65_536;
/// Largest scale (a byte).
pub const MAX_SCALE: u8 = 255;
/// Bytes of an automaton's descriptor besides its alphabet: the start of its records (u16), scale (u8)
/// and a byte of padding, as [`crate::table::Automaton`] lays them out.
pub const DESCRIPTOR_BYTES: usize = 4;
/// Largest handle of 1-byte targets.
pub const NARROW_HANDLE: usize = 255;
/// Largest handle of 2-byte targets.
pub const WIDE_HANDLE: usize = 65_535;
/// Most handle units a block may span (the runtime's check: `⌈len / scale⌉ ≤ 65 536`).
const MAX_UNITS: usize = 65_536;

/// A set to build tables for: plants then supervisors over one global event numbering.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Source {
    /// Event names by global id (kept for logs; the tables hold none).
    pub event_names: Vec<String>,
    /// Whether each global event is controllable.
    pub controllable: Vec<bool>,
    /// How many of the automata, the first ones, are plants.
    pub plants: usize,
    /// Plants first, then supervisors.
    pub automata: Vec<SourceAutomaton>,
}

/// One automaton of a [`Source`]: states `0..out.len()`, transitions over global event ids.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceAutomaton {
    /// Automaton name.
    pub name: String,
    /// Index of the initial state.
    pub initial: usize,
    /// Global ids of the events of its alphabet.
    pub alphabet: Vec<usize>,
    /// Per state (by index): outgoing `(global event, target state)` pairs in increasing event order, one
    /// per event.
    pub out: Vec<Vec<(usize, usize)>>,
}

/// The record layouts of [`crate::table`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// A target per event of the state's out-mask, masks of `⌈events / 8⌉` bytes: the smaller.
    Ranked,
    /// A target per event of the automaton's alphabet, masks of whole words: no rank and aligned mask
    /// loads in a step, for cores without unaligned loads or a bit-scan instruction (Cortex-M0+).
    Indexed,
    /// The reference tool's vector, to the byte ([`crate::table::records`]).
    MemorySafe,
    /// The reference tool's records with targets as offsets ([`crate::table::records`]).
    Offset,
    /// Bit-packed over local alphabets ([`crate::table::compact`]).
    Compact,
}

impl Layout {
    /// Every layout, in the size report's order.
    pub const ALL: [Layout; 5] =
        [Layout::MemorySafe, Layout::Offset, Layout::Ranked, Layout::Indexed, Layout::Compact];

    /// The layout whose runtime id ([`crate::table::layout`]) is `id`.
    pub fn of_id(id: u8) -> Option<Layout> {
        Layout::ALL.into_iter().find(|l| l.id() == id)
    }

    /// The runtime's id of the layout ([`crate::table::layout`]).
    pub fn id(self) -> u8 {
        use crate::table::layout;
        match self {
            Layout::Ranked => layout::RANKED,
            Layout::Indexed => layout::INDEXED,
            Layout::MemorySafe => layout::MEMORY_SAFE,
            Layout::Offset => layout::OFFSET,
            Layout::Compact => layout::COMPACT,
        }
    }

    /// Whether the records name masks of a pool (`ranked`, `indexed`).
    pub fn has_pool(self) -> bool {
        crate::table::layout::has_pool(self.id())
    }
}

/// A set in one of the layouts: what [`crate::table::SupervisorSet`] holds, with names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Packed {
    /// Event names by global id.
    pub event_names: Vec<String>,
    /// Bitset over global event ids (⌈e/32⌉ words): the controllable ones.
    pub controllable: Vec<u32>,
    /// How many of the automata, the first ones, are plants.
    pub plants: usize,
    /// The pool of distinct out-masks (`ranked`) or allowed sets (`indexed`: the out-mask and every
    /// event outside the automaton's alphabet), each ⌈e/32⌉ words, in first-appearance order; empty in
    /// the layouts without a pool.
    pub masks: Vec<Vec<u32>>,
    /// Wide fields: mask ids and target handles take 2 bytes (little-endian) instead of 1 in every block
    /// (`ranked`, `indexed`), record targets 4 bytes instead of 2 (`offset`).
    pub wide: bool,
    /// Bytes of a position in the runtime ([`crate::table::Position`]): 2 while every state's position
    /// (a record's byte offset in the blocks back to back, a mask's bit offset in `compact`) is below
    /// 65 536, else 4.
    pub position_bytes: usize,
    /// The layout of the blocks.
    pub layout: Layout,
    /// Plants first, then supervisors.
    pub automata: Vec<Block>,
}

/// One automaton: the runtime's [`crate::table::Automaton`] and its block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    /// Automaton name.
    pub name: String,
    /// Index of the initial state (whose record comes first, handle 0, in `ranked` and `indexed`).
    pub initial: usize,
    /// The initial state's handle ([`crate::table::SupervisorSet::initials`]; 0 in `ranked` and
    /// `indexed`).
    pub handle: usize,
    /// Bytes per handle unit: a record starts at byte `handle · scale` of the block (≥ 1; 1 in the
    /// layouts without a pool).
    pub scale: u8,
    /// The records (see [`crate::table`]).
    pub block: Vec<u8>,
    /// Bitset over global event ids (⌈e/32⌉ words): the automaton's alphabet.
    pub alphabet: Vec<u32>,
}

/// One state's record, read back from a block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Record {
    /// The state's index in its automaton.
    pub state: usize,
    /// The state's handle.
    pub handle: u16,
    /// Byte offset of the record in its block.
    pub at: usize,
    /// Id of the state's out-mask in [`Packed::masks`].
    pub mask: usize,
    /// Target handles, one per event of the mask in increasing id order.
    pub targets: Vec<u16>,
}

impl Packed {
    /// Words of an event bitset in the runtime: enough for the events, and one for a set without any.
    pub fn words(&self) -> usize {
        self.controllable.len().max(1)
    }

    /// Bytes of a mask id or a target handle (`ranked`, `indexed`).
    pub fn field_bytes(&self) -> usize {
        if self.wide {
            2
        } else {
            1
        }
    }

    /// Bytes of one mask in the runtime's pool: enough for the events (at least one), whole words in
    /// the `indexed` layout, 0 in the layouts without a pool.
    pub fn mask_width(&self) -> usize {
        match self.layout {
            Layout::Indexed => 4 * self.words().max(1),
            Layout::Ranked => self.event_names.len().div_ceil(8).max(1),
            _ => 0,
        }
    }

    /// The runtime's initial handles ([`crate::table::SupervisorSet::initials`]): one per automaton,
    /// none in the layouts with a pool.
    pub fn initials(&self) -> Vec<usize> {
        if self.layout.has_pool() {
            return Vec::new();
        }
        self.automata.iter().map(|b| b.handle).collect()
    }

    /// Whether the records hold a target per event of the alphabet (`indexed` layout).
    pub fn indexed(&self) -> bool {
        self.layout == Layout::Indexed
    }

    /// Units of a position per byte of the block: 8 in `compact` (bit offsets), else 1.
    pub fn position_unit(&self) -> usize {
        if self.layout == Layout::Compact {
            8
        } else {
            1
        }
    }

    /// The handle of every state of automaton `a`, by state index ([`crate::table`] says what a handle
    /// is in each layout).
    pub fn handles(&self, a: usize) -> Result<Vec<usize>, ReadError> {
        let positions = self.state_positions(a)?;
        Ok(match self.layout {
            Layout::Ranked | Layout::Indexed => {
                let mut handles = vec![0; positions.len()];
                for r in self.records(a)? {
                    if let Some(h) = handles.get_mut(r.state) {
                        *h = usize::from(r.handle);
                    }
                }
                handles
            }
            Layout::Compact => {
                let base = positions.first().map_or(0, |p| p.0);
                positions.iter().map(|p| p.0 - base).collect()
            }
            Layout::MemorySafe | Layout::Offset => positions.iter().map(|p| p.0).collect(),
        })
    }

    /// Bytes of one transition of a `memory-safe` or `offset` record: the event and the target (4 bytes
    /// with wide fields, else 2).
    pub fn transition_bytes(&self) -> usize {
        if self.wide {
            5
        } else {
            3
        }
    }

    /// Every state of automaton `a`: its position from the automaton's start (in
    /// [`Packed::position_unit`]s) and its out-events, in block order.
    pub fn state_positions(&self, a: usize) -> Result<Vec<(usize, Vec<u32>)>, ReadError> {
        let words = self.words();
        match self.layout {
            Layout::Ranked | Layout::Indexed => {
                let b = self.automata.get(a);
                Ok(self
                    .records(a)?
                    .into_iter()
                    .map(|r| (r.at, b.and_then(|b| self.out_mask(b, r.mask)).unwrap_or_default()))
                    .collect())
            }
            Layout::Compact => Ok(self
                .automata
                .get(a)
                .map(|b| super::compact::states(&b.block, &b.alphabet, words))
                .unwrap_or_default()),
            Layout::MemorySafe | Layout::Offset => Ok(self
                .automata
                .get(a)
                .map(|b| super::records::states(&b.block, self.transition_bytes(), words))
                .unwrap_or_default()),
        }
    }

    /// The runtime's mask pool ([`crate::table::SupervisorSet::masks`]): every mask in
    /// [`Packed::mask_width`] bytes, little-endian, then the padding that lets the runtime read whole
    /// words from the last, packed little-endian into words.
    pub fn mask_pool(&self) -> Vec<u32> {
        if !self.layout.has_pool() {
            return Vec::new();
        }
        let width = self.mask_width();
        // A mask of a set without events has no words: its byte is 0.
        let mut pool: Vec<u8> = self
            .masks
            .iter()
            .flat_map(|m| m.iter().flat_map(|w| w.to_le_bytes()).chain(core::iter::repeat(0)).take(width))
            .collect();
        // A set without events still has one word per bitset in the runtime.
        pool.resize((pool.len() + 4 * self.words().max(1) - width).next_multiple_of(4), 0);
        pool.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect()
    }

    /// Bytes of the mask pool.
    pub fn mask_bytes(&self) -> usize {
        4 * self.mask_pool().len()
    }

    /// The runtime's holder lists ([`crate::table::SupervisorSet::holder_lists`]): per event and one more,
    /// where its list starts; then per event the automata holding it, in index order, each with the
    /// event's place in its alphabet. Empty in the other layouts.
    pub fn holder_lists(&self) -> Vec<u16> {
        if !self.indexed() {
            return Vec::new();
        }
        let events = self.event_names.len();
        let alphabets: Vec<Vec<usize>> =
            self.automata.iter().map(|b| bitset::ids(&b.alphabet).collect()).collect();
        let lists: Vec<Vec<u16>> = (0..events)
            .map(|e| {
                alphabets
                    .iter()
                    .enumerate()
                    // At most 32 automata and 256 events: the automaton and the place fit a byte each.
                    .filter_map(|(a, ids)| ids.iter().position(|&x| x == e).map(|p| (a | p << 8) as u16))
                    .collect()
            })
            .collect();
        let mut starts = Vec::with_capacity(events + 1);
        let mut at = events + 1;
        for list in &lists {
            starts.push(at as u16);
            at += list.len();
        }
        // The table's length: (events + 1) + one entry per holder, at most 257 + 256 · 32.
        starts.push(at as u16);
        starts.into_iter().chain(lists.into_iter().flatten()).collect()
    }

    /// Where each automaton's block starts when the blocks are put back to back in set order.
    pub fn starts(&self) -> Vec<usize> {
        self.automata
            .iter()
            .scan(0, |at, b| {
                let start = *at;
                *at += b.block.len();
                Some(start)
            })
            .collect()
    }

    /// The records of automaton `a`, in block order (the initial state's first), every length, mask id
    /// and padding byte checked (targets are not: they are handles, which only the whole block
    /// resolves).
    pub fn records(&self, a: usize) -> Result<Vec<Record>, ReadError> {
        let b = self.automata.get(a).ok_or_else(|| ReadError::Inconsistent {
            what: String::from("set"),
            detail: format!("no automaton {a} of {}", self.automata.len()),
        })?;
        self.walk(b)
    }

    /// The out-mask of pool entry `id` for an automaton of block `b`: the entry (`ranked`), or its part
    /// within the alphabet (`indexed`, whose pool holds allowed sets).
    pub fn out_mask(&self, b: &Block, id: usize) -> Option<Vec<u32>> {
        let entry = self.masks.get(id)?;
        Some(if self.indexed() {
            entry.iter().zip(&b.alphabet).map(|(m, al)| m & al).collect()
        } else {
            entry.clone()
        })
    }

    /// Padding bytes of automaton `a`'s block (between records).
    pub fn padding(&self, a: usize) -> Result<usize, ReadError> {
        let records = self.records(a)?;
        let t_bytes = self.field_bytes();
        let alphabet = self.automata.get(a).map_or(0, |b| bitset::ids(&b.alphabet).count());
        let targets = |r: &Record| if self.indexed() { alphabet } else { r.targets.len() };
        let used: usize = records.iter().map(|r| (1 + targets(r)) * t_bytes).sum();
        Ok(self.automata.get(a).map_or(0, |b| b.block.len()).saturating_sub(used))
    }

    /// The records of block `b`; see [`Packed::records`].
    pub fn walk(&self, b: &Block) -> Result<Vec<Record>, ReadError> {
        let what = || b.name.clone();
        if b.scale == 0 {
            return Err(ReadError::Inconsistent { what: what(), detail: String::from("scale 0") });
        }
        let scale = usize::from(b.scale);
        let t_bytes = self.field_bytes();
        let id_bytes = t_bytes;
        let bytes = &b.block;
        let truncated = || ReadError::Truncated { what: what(), at: bytes.len() };
        let mut out = Vec::new();
        let mut at = 0usize;
        while at < bytes.len() {
            let handle = u16::try_from(at / scale).map_err(|_| ReadError::Inconsistent {
                what: what(),
                detail: format!("the record at byte {at} has no 16-bit handle at scale {scale}"),
            })?;
            let id = read(bytes, at, id_bytes).ok_or_else(truncated)?;
            let mask = self.masks.get(id).ok_or(ReadError::BadMask { what: what(), at, id })?;
            // Indexed: the allowed set holds every event outside the alphabet (nothing to look for in a
            // ranked set).
            let outside = if self.indexed() { self.event_names.len() } else { 0 };
            let lacking = |e: &usize| !bitset::contains(&b.alphabet, *e) && !bitset::contains(mask, *e);
            if let Some(e) = (0..outside).find(lacking) {
                return Err(ReadError::Inconsistent {
                    what: what(),
                    detail: format!("the allowed set {id} of the record at byte {at} lacks event {e}, outside the alphabet"),
                });
            }
            // The events with a target field: the mask's, or the alphabet's in the `indexed` layout.
            let fields: Vec<usize> = bitset::ids(if self.indexed() { &b.alphabet } else { mask }).collect();
            let first = at + id_bytes;
            let end = first + fields.len() * t_bytes;
            if end > bytes.len() {
                return Err(truncated());
            }
            let mut targets = Vec::new();
            for (r, &e) in fields.iter().enumerate() {
                // Every read lies below `end` ≤ the block's length, and is at most 2 bytes.
                let t = read(bytes, first + r * t_bytes, t_bytes).map_or(0, |t| t as u16);
                if bitset::contains(mask, e) {
                    targets.push(t);
                } else if t != 0 {
                    return Err(ReadError::Inconsistent {
                        what: what(),
                        detail: format!(
                            "the target of event {e} at byte {at}, which does not leave the state, is not 0"
                        ),
                    });
                }
            }
            let r = out.len();
            // The initial state's record first, then the others by index.
            let state = match r {
                0 => b.initial,
                r if r <= b.initial => r - 1,
                r => r,
            };
            out.push(Record { state, handle, at, mask: id, targets });
            let next = end.div_ceil(scale) * scale;
            if end < bytes.len() && next >= bytes.len() {
                return Err(ReadError::Inconsistent {
                    what: what(),
                    detail: format!("{} bytes after the last record", bytes.len() - end),
                });
            }
            if let Some(p) =
                bytes.get(end..next.min(bytes.len())).and_then(|pad| pad.iter().position(|&x| x != 0))
            {
                return Err(ReadError::Inconsistent {
                    what: what(),
                    detail: format!("padding byte {} is not 0", end + p),
                });
            }
            at = next;
        }
        Ok(out)
    }
}

/// The little-endian number of `n` (1 or 2) bytes at `at`, if they are in `bytes`.
fn read(bytes: &[u8], at: usize, n: usize) -> Option<usize> {
    match n {
        1 => bytes.get(at).map(|&b| usize::from(b)),
        _ => Some(usize::from(u16::from_le_bytes([*bytes.get(at)?, *bytes.get(at + 1)?]))),
    }
}

/// Handle of the last record and block length for records of `lens` bytes at `scale`.
pub fn extent(lens: &[usize], scale: usize) -> (usize, usize) {
    let Some((&last, rest)) = lens.split_last() else { return (0, 0) };
    let units: usize = rest.iter().map(|l| l.div_ceil(scale)).sum();
    (units, units * scale + last)
}

/// The smallest scale whose handles stay ≤ `max_handle` for records of `lens` bytes, with the block's
/// length; `None` when no scale up to [`MAX_SCALE`] does. The last handle never grows with the scale,
/// so a binary search finds it.
pub fn smallest_scale(lens: &[usize], max_handle: usize) -> Option<(u8, usize)> {
    let fits = |s: usize| {
        let (h, len) = extent(lens, s);
        h <= max_handle && len.div_ceil(s) <= MAX_UNITS
    };
    let (mut lo, mut hi) = (1usize, usize::from(MAX_SCALE));
    if !fits(hi) {
        return None;
    }
    while lo < hi {
        let mid = (lo + hi) / 2;
        if fits(mid) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    // `lo` ≤ MAX_SCALE: it fits a byte.
    Some((lo as u8, extent(lens, lo).1))
}

/// An automaton's smallest scale, with the block length it gives, for each field width.
struct Scales {
    /// With 1-byte fields, when its mask ids fit a byte.
    narrow: Option<(u8, usize)>,
    /// With 2-byte fields.
    wide: Option<(u8, usize)>,
}

impl Scales {
    /// The scales of automaton `a` whose states have the mask ids `ids`, its records in `order`, in
    /// `layout`.
    fn of(a: &SourceAutomaton, ids: &[usize], order: &[usize], alphabet: &[usize], layout: Layout) -> Scales {
        let lens =
            |t: usize| order.iter().map(|&s| t * (1 + targets(a, s, alphabet, layout))).collect::<Vec<_>>();
        let narrow_ids = ids.iter().all(|&id| id < NARROW_IDS);
        Scales {
            narrow: smallest_scale(&lens(1), NARROW_HANDLE).filter(|_| narrow_ids),
            wide: smallest_scale(&lens(2), WIDE_HANDLE),
        }
    }
}

/// The states of `a` in the order of their records: the initial state first, then the others by index.
fn record_order(a: &SourceAutomaton) -> Vec<usize> {
    core::iter::once(a.initial).chain((0..a.out.len()).filter(|&s| s != a.initial)).collect()
}

/// Target fields of state `s`'s record in `layout`: one per out-event, or per event of `alphabet`
/// (`a`'s, ascending).
fn targets(a: &SourceAutomaton, s: usize, alphabet: &[usize], layout: Layout) -> usize {
    match layout {
        Layout::Indexed => alphabet.len(),
        _ => a.out[s].len(),
    }
}

/// Encodes `source` in the `ranked` layout, or says which limit it breaks.
pub fn encode(source: &Source) -> Result<Packed, BuildError> {
    encode_as(source, Layout::Ranked)
}

/// Encodes `source` in `layout`, or says which limit it breaks.
pub fn encode_as(source: &Source, layout: Layout) -> Result<Packed, BuildError> {
    let events = source.event_names.len();
    if events > MAX_EVENTS {
        return Err(BuildError::TooManyEvents { events, limit: MAX_EVENTS });
    }
    for a in &source.automata {
        if a.out.len() > MAX_STATES {
            return Err(BuildError::TooManyStates {
                automaton: a.name.clone(),
                states: a.out.len(),
                limit: MAX_STATES,
            });
        }
    }
    let packed = |masks, (wide, automata, last): (bool, Vec<Block>, usize)| Packed {
        event_names: source.event_names.clone(),
        controllable: bitset::from_ids(
            (0..events).filter(|&e| source.controllable.get(e).copied().unwrap_or(false)),
            events,
        ),
        plants: source.plants,
        masks,
        wide,
        position_bytes: position_bytes(last),
        layout,
        automata,
    };
    match layout {
        Layout::Ranked | Layout::Indexed => {}
        Layout::MemorySafe | Layout::Offset => {
            return Ok(packed(Vec::new(), super::records::encode(source, layout)?))
        }
        Layout::Compact => return Ok(packed(Vec::new(), super::compact::encode(source)?)),
    }
    // The pool, in first-appearance order, and every state's mask id. Indexed: allowed sets, the
    // out-mask with the events outside the alphabet.
    let mut masks: Vec<Vec<u32>> = Vec::new();
    let mut index: BTreeMap<Vec<u32>, usize> = BTreeMap::new();
    let mut ids: Vec<Vec<usize>> = Vec::with_capacity(source.automata.len());
    for a in &source.automata {
        let mut of_automaton = Vec::with_capacity(a.out.len());
        let outside: Vec<usize> = match layout {
            Layout::Indexed => (0..events).filter(|e| !a.alphabet.contains(e)).collect(),
            _ => Vec::new(),
        };
        for edges in &a.out {
            let mask = bitset::from_ids(edges.iter().map(|&(e, _)| e).chain(outside.iter().copied()), events);
            let id = *index.entry(mask.clone()).or_insert_with(|| {
                masks.push(mask);
                masks.len() - 1
            });
            of_automaton.push(id);
        }
        ids.push(of_automaton);
    }
    if masks.len() > MAX_MASKS {
        return Err(BuildError::TooManyMasks { masks: masks.len(), limit: MAX_MASKS });
    }
    let orders: Vec<Vec<usize>> = source.automata.iter().map(record_order).collect();
    let alphabets: Vec<Vec<usize>> = source
        .automata
        .iter()
        .map(|a| bitset::ids(&bitset::from_ids(a.alphabet.iter().copied(), events)).collect())
        .collect();
    let options: Vec<Scales> = (0..source.automata.len())
        .map(|i| Scales::of(&source.automata[i], &ids[i], &orders[i], &alphabets[i], layout))
        .collect();
    let total = |of: fn(&Scales) -> Option<(u8, usize)>| {
        options.iter().map(|o| of(o).map(|(_, len)| len)).sum::<Option<usize>>()
    };
    let wide = match (total(|o| o.narrow), total(|o| o.wide)) {
        (Some(narrow), Some(wide)) => narrow > wide,
        (Some(_), None) => false,
        (None, _) => true,
    };
    let width = if wide { 2 } else { 1 };
    let mut automata = Vec::with_capacity(source.automata.len());
    // Where the block starts when the blocks are put back to back, and the last record start.
    let (mut start, mut last_record) = (0usize, 0usize);
    for (i, a) in source.automata.iter().enumerate() {
        let (ids, option, order, alphabet) = (&ids[i], &options[i], &orders[i], &alphabets[i]);
        let lens: Vec<usize> = order.iter().map(|&s| width * (1 + targets(a, s, alphabet, layout))).collect();
        let Some((scale, _)) = (if wide { option.wide } else { option.narrow }) else {
            return Err(BuildError::NoScale { automaton: a.name.clone(), bytes: lens.iter().sum() });
        };
        let unit = usize::from(scale);
        let mut handles = vec![0; lens.len()];
        let mut units = 0usize;
        for (&s, l) in order.iter().zip(&lens) {
            handles[s] = units;
            units += l.div_ceil(unit);
        }
        let len = extent(&lens, unit).1;
        let mut block = Vec::with_capacity(len);
        for &s in order {
            block.resize(handles[s] * unit, 0);
            // Checked above: ids and handles within the chosen width.
            block.extend_from_slice(&(ids[s] as u16).to_le_bytes()[..width]);
            let target = |t: usize| handles[t] as u16;
            let fields: Vec<u16> = match layout {
                Layout::Indexed => alphabet
                    .iter()
                    .map(|&e| a.out[s].iter().find(|&&(x, _)| x == e).map_or(0, |&(_, t)| target(t)))
                    .collect(),
                _ => a.out[s].iter().map(|&(_, t)| target(t)).collect(),
            };
            for h in fields {
                block.extend_from_slice(&h.to_le_bytes()[..width]);
            }
        }
        let last = handles.iter().max().map_or(0, |h| h * unit);
        if start + last > MAX_POSITION {
            return Err(BuildError::BlocksTooLarge {
                automaton: a.name.clone(),
                bytes: start + block.len(),
                limit: MAX_POSITION + 1,
            });
        }
        last_record = start + last;
        start += block.len();
        automata.push(Block {
            name: a.name.clone(),
            initial: a.initial,
            handle: 0,
            scale,
            block,
            alphabet: bitset::from_ids(a.alphabet.iter().copied(), events),
        });
    }
    Ok(packed(masks, (wide, automata, last_record)))
}

/// Largest position of 32 bits.
pub const MAX_POSITION: usize = u32::MAX as usize;

/// Bytes of a position for a set whose largest position is `last`: 2 while it is below 65 536, else 4.
pub fn position_bytes(last: usize) -> usize {
    if last <= usize::from(u16::MAX) {
        2
    } else {
        4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_search_is_the_smallest_and_gives_up_beyond_16_bit_handles() {
        let lens = vec![3usize; 200];
        // 199 records before the last: ⌈3/s⌉ units each; ≤ 255 needs s = 3.
        assert_eq!(smallest_scale(&lens, NARROW_HANDLE), Some((3, 600)));
        assert_eq!(smallest_scale(&lens, WIDE_HANDLE), Some((1, 600)));
        // 1-byte handles name 256 records at most, whatever the scale.
        assert_eq!(smallest_scale(&[1; 257], NARROW_HANDLE), None);
        let huge = vec![300usize; 60_000];
        assert_eq!(smallest_scale(&huge, WIDE_HANDLE), None);
        assert_eq!(smallest_scale(&[], NARROW_HANDLE), Some((1, 0)));
    }
}
