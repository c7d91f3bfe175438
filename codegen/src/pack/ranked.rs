//! This module is the home of the `ranked` layout: the runtime's table (`firmware/src/table/`).
//!
//! A state's *out-mask* is the bitset over global event ids of the events leaving it. The set keeps one
//! pool of distinct out-masks ([`Packed::masks`]; ⌈e/8⌉ bytes each in the runtime's pool,
//! [`Packed::mask_pool`]), shared by all automata and in a fixed order: first appearance, automata in set
//! order (plants first), states in index order.
//!
//! Each automaton is one byte block holding one record per state, the initial state's first, then the
//! others in state-index order; the runtime's tables put the blocks back to back, in set order, in one
//! block (`firmware::table::SupervisorSet::block`), each automaton starting where the previous ends:
//!
//! ```text
//! [mask id][target handle, for every event of the mask in increasing id order]
//! ```
//!
//! Mask ids and target handles take 1 byte each, or 2 bytes little-endian when the set is
//! [`Packed::wide`]. State handle
//! `h` names the record starting at byte `h · scale` of the block ([`Block::scale`]); each record starts
//! at the first multiple of `scale` at or after the end of the previous one, the bytes between are
//! padding (0), and the block ends right after its last record. The target of event `e` is the `r`-th
//! target of the record, `r` the number of mask bits below `e`: a step is a mask test, a rank and one
//! load, whatever the state count.
//!
//! The field width is one for the whole set, so that the runtime is compiled for it and its steps test
//! nothing: the encoder picks the smaller blocks of two candidates (1-byte fields on a tie):
//!
//! * 1-byte fields, when every mask id is below [`NARROW_IDS`] and every automaton has a scale in
//!   1..=255 that puts every record start at a handle ≤ 255 (each automaton with its smallest such
//!   scale);
//! * 2-byte fields, each automaton with the smallest scale that puts every record start at a handle
//!   ≤ 65 535.
//!
//! Side tables: the mask pool (⌈e/8⌉ bytes per mask, then padding to read a whole last word), per
//! automaton a descriptor of [`DESCRIPTOR_BYTES`] (start offset u16, scale u8, padding) and its alphabet
//! (⌈e/32⌉ words), and the controllability bitset (⌈e/32⌉ words). The per-event holder masks, per-plant
//! event sets and choice sites `codegen emit` adds for the runtime's hot path are not part of the layout.
//!
//! Limits: at most 256 events, 65 536 states per automaton and a block whose records fit 2-byte handles
//! at some scale up to 255, [`MAX_MASKS`] distinct masks, and records starting in the first
//! [`MAX_BLOCK_BYTES`] of the blocks back to back (the runtime holds a state as its record's 16-bit
//! offset in them).

use std::collections::HashMap;

use super::{bitset, decoded::Recovered, DecodeError, PackError, PackSet, Role, Size};
use crate::model::Automaton;

/// Layout name, as given to `--layout`.
pub const NAME: &str = "ranked";
/// Most events: an event id is one byte.
pub const MAX_EVENTS: usize = 256;
/// Most distinct out-masks (2-byte ids).
pub const MAX_MASKS: usize = firmware::table::MAX_MASKS;
/// Bytes of the blocks back to back in which records may start (16-bit record offsets).
pub const MAX_BLOCK_BYTES: usize = firmware::table::MAX_BLOCK;
/// Mask ids a 1-byte field numbers.
pub const NARROW_IDS: usize = 256;
/// Most states of one automaton: a handle is at most 2 bytes.
pub const MAX_STATES: usize = 65_536;
/// Largest scale (a byte).
pub const MAX_SCALE: u8 = 255;
/// Bytes of an automaton's descriptor besides its alphabet: the start of its records (u16), scale (u8)
/// and a byte of padding, as the runtime's `table::Automaton` lays them out.
pub const DESCRIPTOR_BYTES: usize = 4;

/// Largest handle of 1-byte targets.
const NARROW_HANDLE: usize = 255;
/// Largest handle of 2-byte targets.
const WIDE_HANDLE: usize = 65_535;
/// Most handle units a block may span (the runtime's check: `⌈len / scale⌉ ≤ 65 536`).
const MAX_UNITS: usize = 65_536;

/// A set in the `ranked` layout: what the firmware's `table::SupervisorSet` holds, with names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Packed {
    /// Event names by global id.
    pub event_names: Vec<String>,
    /// Bitset over global event ids (⌈e/32⌉ words): the controllable ones.
    pub controllable: Vec<u32>,
    /// The pool of distinct out-masks, each ⌈e/32⌉ words, in first-appearance order.
    pub masks: Vec<Vec<u32>>,
    /// Mask ids and target handles take 2 bytes (little-endian) instead of 1, in every block.
    pub wide: bool,
    /// Plants first, then supervisors.
    pub automata: Vec<Block>,
}

/// One automaton in the `ranked` layout: the runtime's `table::Automaton` and its block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    /// Automaton name.
    pub name: String,
    /// Plant or supervisor.
    pub role: Role,
    /// Index of the initial state, whose record comes first (handle 0).
    pub initial: usize,
    /// Bytes per handle unit: a record starts at byte `handle · scale` of the block (≥ 1).
    pub scale: u8,
    /// The records (see the module documentation).
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
    /// Words of an event bitset.
    pub fn words(&self) -> usize {
        self.controllable.len()
    }

    /// Bytes of a mask id or a target handle.
    pub fn field_bytes(&self) -> usize {
        if self.wide {
            2
        } else {
            1
        }
    }

    /// Bytes of one mask in the runtime's pool: enough for the events (at least one).
    pub fn mask_width(&self) -> usize {
        self.event_names.len().div_ceil(8).max(1)
    }

    /// The runtime's mask pool: every mask in [`Packed::mask_width`] bytes, little-endian, then the
    /// padding that lets the runtime read whole words from the last
    /// (`firmware::table::SupervisorSet::masks`).
    pub fn mask_pool(&self) -> Vec<u8> {
        let width = self.mask_width();
        // A mask of a set without events has no words: its byte is 0.
        let mut pool: Vec<u8> = self
            .masks
            .iter()
            .flat_map(|m| m.iter().flat_map(|w| w.to_le_bytes()).chain(std::iter::repeat(0)).take(width))
            .collect();
        // A set without events still has one word per bitset in the runtime.
        pool.resize(pool.len() + 4 * self.words().max(1) - width, 0);
        pool
    }

    /// Bytes of the mask pool.
    pub fn mask_bytes(&self) -> usize {
        self.mask_pool().len()
    }

    /// Bytes per automaton (padding included) and of each side table, bitsets in whole u32 words as the
    /// runtime holds them.
    pub fn size(&self) -> Size {
        let n = self.automata.len();
        Size {
            layout: NAME,
            per_automaton: self.automata.iter().map(|b| (b.name.clone(), b.block.len())).collect(),
            side_tables: vec![
                ("mask pool", self.mask_bytes()),
                ("automaton descriptors", DESCRIPTOR_BYTES * n),
                ("alphabets", self.automata.iter().map(|b| 4 * b.alphabet.len()).sum()),
                ("controllability", 4 * self.controllable.len()),
            ],
        }
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
    /// and padding byte checked (targets are not: see [`decode`]).
    pub fn records(&self, a: usize) -> Result<Vec<Record>, DecodeError> {
        let b = self.automata.get(a).ok_or_else(|| DecodeError::Inconsistent {
            what: String::from("set"),
            detail: format!("no automaton {a} of {}", self.automata.len()),
        })?;
        self.walk(b)
    }

    /// Padding bytes of automaton `a`'s block (between records).
    pub fn padding(&self, a: usize) -> Result<usize, DecodeError> {
        let records = self.records(a)?;
        let t_bytes = self.field_bytes();
        let used: usize = records.iter().map(|r| (1 + r.targets.len()) * t_bytes).sum();
        Ok(self.automata.get(a).map_or(0, |b| b.block.len()).saturating_sub(used))
    }

    fn walk(&self, b: &Block) -> Result<Vec<Record>, DecodeError> {
        let what = || b.name.clone();
        if b.scale == 0 {
            return Err(DecodeError::Inconsistent { what: what(), detail: String::from("scale 0") });
        }
        let scale = usize::from(b.scale);
        let t_bytes = self.field_bytes();
        let id_bytes = t_bytes;
        let bytes = &b.block;
        let truncated = || DecodeError::Truncated { what: what(), at: bytes.len() };
        let mut out = Vec::new();
        let mut at = 0usize;
        while at < bytes.len() {
            let handle = u16::try_from(at / scale).map_err(|_| DecodeError::Inconsistent {
                what: what(),
                detail: format!("the record at byte {at} has no 16-bit handle at scale {scale}"),
            })?;
            let id = read(bytes, at, id_bytes).ok_or_else(truncated)?;
            let mask = self.masks.get(id).ok_or(DecodeError::BadMask { what: what(), at, id })?;
            let n: usize = mask.iter().map(|w| w.count_ones() as usize).sum();
            let first = at + id_bytes;
            let end = first + n * t_bytes;
            if end > bytes.len() {
                return Err(truncated());
            }
            let targets = (0..n)
                // Every read lies below `end` ≤ the block's length, and is at most 2 bytes.
                .map(|r| read(bytes, first + r * t_bytes, t_bytes).map_or(0, |t| t as u16))
                .collect();
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
                return Err(DecodeError::Inconsistent {
                    what: what(),
                    detail: format!("{} bytes after the last record", bytes.len() - end),
                });
            }
            if let Some(p) =
                bytes.get(end..next.min(bytes.len())).and_then(|pad| pad.iter().position(|&x| x != 0))
            {
                return Err(DecodeError::Inconsistent {
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
fn extent(lens: &[usize], scale: usize) -> (usize, usize) {
    let Some((&last, rest)) = lens.split_last() else { return (0, 0) };
    let units: usize = rest.iter().map(|l| l.div_ceil(scale)).sum();
    (units, units * scale + last)
}

/// The smallest scale whose handles stay ≤ `max_handle` for records of `lens` bytes, with the block's
/// length; `None` when no scale up to [`MAX_SCALE`] does. The last handle never grows with the scale,
/// so a binary search finds it.
fn smallest_scale(lens: &[usize], max_handle: usize) -> Option<(u8, usize)> {
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
    /// The scales of member `m` whose states have the mask ids `ids`, its records in `order`.
    fn of(m: &super::Member, ids: &[usize], order: &[usize]) -> Scales {
        let lens = |t: usize| order.iter().map(|&s| t * (1 + m.out[s].len())).collect::<Vec<_>>();
        let narrow_ids = ids.iter().all(|&id| id < NARROW_IDS);
        Scales {
            narrow: smallest_scale(&lens(1), NARROW_HANDLE).filter(|_| narrow_ids),
            wide: smallest_scale(&lens(2), WIDE_HANDLE),
        }
    }
}

/// The states of `m` in the order of their records: the initial state first, then the others by index.
fn record_order(m: &super::Member) -> Vec<usize> {
    let initial = m.initial().index();
    std::iter::once(initial).chain((0..m.state_count()).filter(|&s| s != initial)).collect()
}

/// Packs `set` in the `ranked` layout, or says which limit it breaks.
pub fn encode(set: &PackSet) -> Result<Packed, PackError> {
    let events = set.events();
    if events.len() > MAX_EVENTS {
        return Err(PackError::TooManyEvents { layout: NAME, events: events.len(), limit: MAX_EVENTS });
    }
    for m in set.members() {
        if m.state_count() > MAX_STATES {
            return Err(PackError::TooManyStates {
                layout: NAME,
                automaton: m.name().to_owned(),
                states: m.state_count(),
                limit: MAX_STATES,
            });
        }
    }
    // The pool, in first-appearance order, and every state's mask id.
    let mut masks: Vec<Vec<u32>> = Vec::new();
    let mut index: HashMap<Vec<u32>, usize> = HashMap::new();
    let mut ids: Vec<Vec<usize>> = Vec::with_capacity(set.members().len());
    for m in set.members() {
        let mut of_member = Vec::with_capacity(m.state_count());
        for edges in &m.out {
            let mask = bitset::from_ids(edges.iter().map(|(e, _)| e.index()), events.len());
            let id = *index.entry(mask.clone()).or_insert_with(|| {
                masks.push(mask);
                masks.len() - 1
            });
            of_member.push(id);
        }
        ids.push(of_member);
    }
    if masks.len() > MAX_MASKS {
        return Err(PackError::TooManyMasks { layout: NAME, masks: masks.len(), limit: MAX_MASKS });
    }
    let orders: Vec<Vec<usize>> = set.members().iter().map(record_order).collect();
    let options: Vec<Scales> = set
        .members()
        .iter()
        .zip(&ids)
        .zip(&orders)
        .map(|((m, ids), order)| Scales::of(m, ids, order))
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
    let mut automata = Vec::with_capacity(set.members().len());
    // Where the block starts when the blocks are put back to back.
    let mut start = 0usize;
    for (((m, ids), option), order) in set.members().iter().zip(&ids).zip(&options).zip(&orders) {
        let lens: Vec<usize> = order.iter().map(|&s| width * (1 + m.out[s].len())).collect();
        let Some((scale, _)) = (if wide { option.wide } else { option.narrow }) else {
            return Err(PackError::NoScale {
                layout: NAME,
                automaton: m.name().to_owned(),
                bytes: lens.iter().sum(),
            });
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
            let edges = &m.out[s];
            block.resize(handles[s] * unit, 0);
            // Checked above: ids and handles within the chosen width.
            block.extend_from_slice(&(ids[s] as u16).to_le_bytes()[..width]);
            for &(_, t) in edges {
                let h = handles[t.index()] as u16;
                block.extend_from_slice(&h.to_le_bytes()[..width]);
            }
        }
        let last = handles.iter().max().map_or(0, |h| h * unit);
        if start + last >= MAX_BLOCK_BYTES {
            return Err(PackError::BlocksTooLarge {
                layout: NAME,
                automaton: m.name().to_owned(),
                bytes: start + block.len(),
                limit: MAX_BLOCK_BYTES,
            });
        }
        start += block.len();
        automata.push(Block {
            name: m.name().to_owned(),
            role: m.role,
            initial: m.initial().index(),
            scale,
            block,
            alphabet: bitset::from_ids(m.alphabet().iter().map(|e| e.index()), events.len()),
        });
    }
    Ok(Packed {
        event_names: events.ids().map(|e| events.name(e).to_owned()).collect(),
        controllable: bitset::from_ids(
            events.ids().filter(|&e| events.is_controllable(e)).map(|e| e.index()),
            events.len(),
        ),
        masks,
        wide,
        automata,
    })
}

/// Reads `packed` back into automata (plants first), checking every mask id, target, handle, length
/// and padding byte.
///
/// States are named by index and unmarked: layouts keep no marking, the runtime needs none.
pub fn decode(packed: &Packed) -> Result<Vec<Automaton>, DecodeError> {
    let words = packed.event_names.len().div_ceil(32);
    let wrong = |what: &str, len: usize| DecodeError::Inconsistent {
        what: what.to_owned(),
        detail: format!("{len} words where {} events need {words}", packed.event_names.len()),
    };
    if packed.controllable.len() != words {
        return Err(wrong("controllability", packed.controllable.len()));
    }
    if let Some(m) = packed.masks.iter().find(|m| m.len() != words) {
        return Err(wrong("mask pool", m.len()));
    }
    let mut out = Vec::with_capacity(packed.automata.len());
    for b in &packed.automata {
        if b.alphabet.len() != words {
            return Err(wrong(&b.name, b.alphabet.len()));
        }
        out.push(decode_block(b, packed)?);
    }
    Ok(out)
}

fn decode_block(b: &Block, packed: &Packed) -> Result<Automaton, DecodeError> {
    let what = || b.name.clone();
    let records = packed.walk(b)?;
    if b.initial >= records.len() {
        return Err(DecodeError::BadState { what: what(), at: 0, target: b.initial });
    }
    let handles: Vec<u16> = records.iter().map(|r| r.handle).collect();
    let state_of = |handle: u16, at: usize| {
        handles.binary_search(&handle).map(|r| records[r].state).map_err(|_| DecodeError::BadState {
            what: what(),
            at,
            target: usize::from(handle),
        })
    };
    let t_bytes = packed.field_bytes();
    let mut edges = Vec::new();
    for r in &records {
        // `walk` checked the id.
        let mask = packed.masks.get(r.mask).map_or(&[][..], Vec::as_slice);
        for (i, (e, &t)) in bitset::ids(mask).zip(&r.targets).enumerate() {
            if !bitset::contains(&b.alphabet, e) {
                return Err(DecodeError::BadEvent { what: what(), at: r.at, event: e });
            }
            edges.push((r.state, e, state_of(t, r.at + (1 + i) * t_bytes)?));
        }
    }
    Recovered {
        name: &b.name,
        role: b.role,
        alphabet: bitset::ids(&b.alphabet).collect(),
        states: records.len(),
        initial: b.initial,
        edges,
    }
    .build(&packed.event_names, &packed.controllable)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;
    use crate::model::{Automaton as Model, Kind, StateId};
    use crate::pack::testing::{arb_set, assert_round_trip, corrupt};
    use firmware::table::{Automaton as RtAutomaton, SupervisorSet, TableError};

    /// Runs `f` on the firmware's view of `packed` (one-word bitsets, no automaton holding any event),
    /// the blocks back to back (starts beyond 16 bits wrap, and the check refuses them).
    fn with_runtime_set<R>(packed: &Packed, f: impl FnOnce(&SupervisorSet<'_, 1>) -> R) -> R {
        let word = |v: &[u32]| [v.first().copied().unwrap_or(0)];
        let masks = packed.mask_pool();
        let automata: Vec<RtAutomaton<1>> = packed
            .automata
            .iter()
            .zip(packed.starts())
            .map(|(b, start)| RtAutomaton {
                alphabet: word(&b.alphabet),
                start: start as u16,
                scale: b.scale,
            })
            .collect();
        let block: Vec<u8> = packed.automata.iter().flat_map(|b| b.block.iter().copied()).collect();
        let plants = packed.automata.iter().filter(|b| b.role == Role::Plant).count();
        let width = firmware::table::holder_bytes(automata.len());
        f(&SupervisorSet {
            controllable: word(&packed.controllable),
            plants: plants as u8,
            automata: &automata,
            block: &block,
            wide: packed.wide,
            masks: &masks,
            mask_bytes: packed.mask_width() as u8,
            holders: &vec![0; width * packed.event_names.len()],
            plant_events: &vec![[0]; plants],
            sites: &[],
        })
    }

    /// The firmware's check on `packed`.
    fn runtime_check(packed: &Packed) -> Result<(), TableError> {
        with_runtime_set(packed, |rt| rt.check(rt.automata.len()))
    }

    /// The firmware's check passes on `packed`, and every step it reads is the set's transition, handle
    /// for handle.
    fn assert_runtime_steps(set: &PackSet, packed: &Packed) {
        assert_eq!(runtime_check(packed), Ok(()));
        with_runtime_set(packed, |rt| {
            for (a, m) in set.members().iter().enumerate() {
                let mut handles = vec![0u16; m.state_count()];
                for r in packed.records(a).unwrap() {
                    handles[r.state] = r.handle;
                }
                assert_eq!(handles[m.initial().index()], 0);
                for (s, edges) in m.out.iter().enumerate() {
                    for e in 0..set.events().len() {
                        let want =
                            edges.iter().find(|(ev, _)| ev.index() == e).map(|(_, t)| handles[t.index()]);
                        assert_eq!(rt.step(a, handles[s], e as u8), want, "{} state {s} event {e}", m.name());
                    }
                }
            }
        });
    }

    #[test]
    fn toggle_matches_the_runtime_example() {
        // `firmware/src/runtime.rs`'s example: masks {a} (id 0) and {b} (id 1), records [id][target],
        // so state 1 is handle 2 at scale 1.
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.masks, [vec![0b01], vec![0b10]]);
        let b = &packed.automata[0];
        assert_eq!((b.initial, b.scale, packed.wide), (0, 1, false));
        assert_eq!(b.block, [0, 2, 1, 0]);
        assert_eq!(b.alphabet, [0b11]);
        assert_eq!(packed.controllable, [0b01]);
        assert_eq!(packed.event_names, ["a", "b"]);
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn the_pool_is_shared() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S")]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.masks.len(), 2);
        assert_eq!(packed.automata[1].block, [0, 2, 1, 0]);
        assert_round_trip(&set, &decode(&packed).unwrap());
        let size = packed.size();
        assert_eq!(size.blocks(), 8);
        // Two 1-byte masks and 3 bytes of padding to read a whole word.
        assert_eq!(size.side(), (2 + 3) + 2 * DESCRIPTOR_BYTES + 2 * 4 + 4);
    }

    /// A ring of `n` states over one event: records of 2 bytes (1-byte handles) or 3 (2-byte).
    fn ring(n: u32) -> Model {
        let mut ring = Model::new("R", Kind::Plant);
        let e = ring.add_event("e", false).unwrap();
        for i in 0..n {
            ring.add_state(i.to_string(), i == 0).unwrap();
        }
        ring.initial = Some(StateId::from_u32(0));
        for i in 0..n {
            ring.add_transition(StateId::from_u32(i), e, StateId::from_u32((i + 1) % n));
        }
        ring
    }

    #[test]
    fn the_smaller_of_scaled_narrow_and_wide_handles_is_chosen() {
        // 256 states of 2 bytes: narrow at scale 2 (512 bytes) beats wide at scale 1 (1024).
        let set = PackSet::new(vec![ring(256)], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        let b = &packed.automata[0];
        assert_eq!((b.scale, packed.wide, b.block.len()), (2, false, 512));
        assert_eq!(packed.padding(0), Ok(0));
        assert_runtime_steps(&set, &packed);
        // 1000 states: narrow needs scale 8 (8000 bytes), wide (2-byte ids and handles) takes 4000.
        let set = PackSet::new(vec![ring(1000)], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        let b = &packed.automata[0];
        assert_eq!((b.scale, packed.wide, b.block.len()), (1, true, 4000));
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn the_scale_fits_the_records_with_the_initial_state_first() {
        // States 0..127 each with one 2-byte record (a → next), state 127 with five events back to 0
        // (6 bytes). In index order the last record starts at byte 254, a 1-byte handle at scale 1; with
        // the initial state 127 first it starts at 6 + 126 · 2 = 258, so the scale must be 2.
        let mut m = Model::new("P", Kind::Plant);
        for i in 0..128u32 {
            m.add_state(i.to_string(), false).unwrap();
        }
        m.initial = Some(StateId::from_u32(127));
        let a = m.add_event("a", false).unwrap();
        for i in 0..127u32 {
            m.add_transition(StateId::from_u32(i), a, StateId::from_u32(i + 1));
        }
        for k in 0..5 {
            let e = m.add_event(format!("b{k}"), false).unwrap();
            m.add_transition(StateId::from_u32(127), e, StateId::from_u32(0));
        }
        let set = PackSet::new(vec![m], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!((packed.wide, packed.automata[0].scale), (false, 2));
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn a_set_without_events_still_has_a_mask_byte_per_mask() {
        let mut lone = Model::new("L", Kind::Plant);
        let q = lone.add_state("q", true).unwrap();
        lone.initial = Some(q);
        let set = PackSet::new(vec![lone], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.mask_pool(), [0, 0, 0, 0]);
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn one_automaton_beyond_narrow_handles_makes_every_block_wide() {
        // The ring needs 2-byte handles; the toggle then takes 2-byte fields too: [id][target] × 2.
        let set = PackSet::new(vec![ring(1000), toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert!(packed.wide);
        assert_eq!(packed.automata[1].block, [1, 0, 4, 0, 2, 0, 0, 0]);
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    /// A ring of 150 states with a self-loop on a second event at every odd state: records of 2 and 3
    /// bytes alternately, the last one of 3.
    fn padded_ring() -> PackSet {
        let mut r = ring(150);
        let f = r.add_event("f", true).unwrap();
        for i in (1..150).step_by(2) {
            r.add_transition(StateId::from_u32(i), f, StateId::from_u32(i));
        }
        PackSet::new(vec![r], vec![]).unwrap()
    }

    #[test]
    fn padding_fills_records_up_to_the_scale() {
        // 375 bytes of records: 1-byte handles need scale 2, which pads every 3-byte record but the last
        // (the block ends right after it): 74 bytes. 2-byte fields would take 750.
        let set = padded_ring();
        let packed = encode(&set).unwrap();
        let b = &packed.automata[0];
        assert_eq!((b.scale, packed.wide), (2, false));
        assert_eq!(packed.padding(0), Ok(74));
        assert_eq!(b.block.len(), 375 + 74);
        assert_eq!(packed.records(0).unwrap().last().map(|r| r.handle), Some(223));
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

    #[test]
    fn mask_ids_beyond_a_byte_make_the_set_wide() {
        // One state per subset of 9 events (self-loops on the subset's events), chained by a tenth.
        let mut a = Model::new("P", Kind::Plant);
        let events: Vec<_> = (0..10).map(|i| a.add_event(format!("e{i}"), false).unwrap()).collect();
        for s in 0..512u32 {
            a.add_state(s.to_string(), false).unwrap();
        }
        a.initial = Some(StateId::from_u32(0));
        for s in 0..512u32 {
            for (i, &e) in events[..9].iter().enumerate() {
                if s & (1 << i) != 0 {
                    a.add_transition(StateId::from_u32(s), e, StateId::from_u32(s));
                }
            }
            a.add_transition(StateId::from_u32(s), events[9], StateId::from_u32((s + 1) % 512));
        }
        let set = PackSet::new(vec![a], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        assert_eq!(packed.masks.len(), 512);
        assert!(packed.wide);
        assert_round_trip(&set, &decode(&packed).unwrap());
        assert_runtime_steps(&set, &packed);
    }

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

    #[test]
    fn limits_are_refused_with_numbers() {
        let mut wide = Model::new("W", Kind::Plant);
        let s = wide.add_state("hub", true).unwrap();
        wide.initial = Some(s);
        for i in 0..257 {
            wide.add_event(format!("e{i}"), false).unwrap();
        }
        let err = encode(&PackSet::new(vec![wide], vec![]).unwrap()).unwrap_err();
        assert_eq!(err.to_string(), "layout ranked: the set has 257 events, more than the limit of 256");
        let err = encode(&PackSet::new(vec![ring(65_537)], vec![]).unwrap()).unwrap_err();
        assert_eq!(err.to_string(), "layout ranked: 'R' has 65537 states, more than the limit of 65536");
        // 20 000 wide records of 4 bytes: the last ones start beyond the runtime's 16-bit offsets.
        let err = encode(&PackSet::new(vec![ring(20_000)], vec![]).unwrap()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "layout ranked: the blocks up to 'R' take 80000 bytes back to back, more than the limit of 65536"
        );
        // 16 000 of them still fit (the last starts at 63 996).
        assert!(encode(&PackSet::new(vec![ring(16_000)], vec![]).unwrap()).is_ok());
        // The limit holds for the blocks back to back: two rings of 9 000 (36 000 bytes each) do not fit.
        let mut second = ring(9_000);
        second.name = String::from("Q");
        let err = encode(&PackSet::new(vec![ring(9_000), second], vec![]).unwrap()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "layout ranked: the blocks up to 'Q' take 72000 bytes back to back, more than the limit of 65536"
        );
    }

    #[test]
    fn corruption_is_reported_by_kind() {
        let set = PackSet::new(vec![toggle("T")], vec![]).unwrap();
        let packed = encode(&set).unwrap();
        let with = |f: &dyn Fn(&mut Packed)| {
            let mut p = packed.clone();
            f(&mut p);
            decode(&p).unwrap_err()
        };
        assert_eq!(
            with(&|p| p.automata[0].block[2] = 7),
            DecodeError::BadMask { what: "T".into(), at: 2, id: 7 }
        );
        assert_eq!(
            with(&|p| p.automata[0].block[1] = 1),
            DecodeError::BadState { what: "T".into(), at: 1, target: 1 }
        );
        assert_eq!(
            with(&|p| p.automata[0].block.truncate(3)),
            DecodeError::Truncated { what: "T".into(), at: 3 }
        );
        assert_eq!(
            with(&|p| p.automata[0].initial = 2),
            DecodeError::BadState { what: "T".into(), at: 0, target: 2 }
        );
        // A mask with an event outside the alphabet.
        assert_eq!(
            with(&|p| p.masks[0] = vec![0b100]),
            DecodeError::BadEvent { what: "T".into(), at: 0, event: 2 }
        );
        assert!(matches!(with(&|p| p.automata[0].scale = 0), DecodeError::Inconsistent { .. }));
        assert_eq!(
            with(&|p| p.automata[0].block.push(0)),
            DecodeError::Truncated { what: "T".into(), at: 5 }
        );
        assert!(matches!(with(&|p| p.controllable.push(0)), DecodeError::Inconsistent { .. }));
        // Padding must be 0, and the block ends with its last record.
        let mut padded = encode(&padded_ring()).unwrap();
        padded.automata[0].block[5] = 9;
        assert_eq!(decode(&padded).unwrap_err().to_string(), "R: padding byte 5 is not 0");
        padded.automata[0].block[5] = 0;
        padded.automata[0].block.push(0);
        assert_eq!(decode(&padded).unwrap_err().to_string(), "R: 1 bytes after the last record");
    }

    proptest::proptest! {
        #[test]
        fn corrupted_tables_never_panic(set in arb_set(40), edits in proptest::collection::vec((0usize..4096, proptest::num::u8::ANY), 1..6), scale in proptest::option::of(0u8..5)) {
            let mut packed = encode(&set).unwrap();
            for b in &mut packed.automata {
                corrupt(&mut b.block, &edits);
                if let Some(s) = scale {
                    b.scale = s;
                }
            }
            // Corruption is either reported or still decodes to valid automata, which the runtime's boot
            // check then accepts too; nothing panics.
            let checked = runtime_check(&packed);
            if let Ok(automata) = decode(&packed) {
                proptest::prop_assert_eq!(checked, Ok(()));
                for a in automata {
                    proptest::prop_assert_eq!(a.validate(), Ok(()));
                }
            }
        }
        #[test]
        fn random_sets_round_trip_and_run(set in arb_set(60)) {
            let packed = encode(&set).unwrap();
            assert_round_trip(&set, &decode(&packed).unwrap());
            assert_runtime_steps(&set, &packed);
            for (a, (m, b)) in set.members().iter().zip(&packed.automata).enumerate() {
                // Records plus padding, and no smaller scale would do with the same handle width.
                let records = (m.state_count() + m.transition_count()) * packed.field_bytes();
                proptest::prop_assert_eq!(b.block.len(), records + packed.padding(a).unwrap());
                let last = packed.records(a).unwrap().last().map_or(0, |r| r.handle);
                let max = if packed.wide { WIDE_HANDLE } else { NARROW_HANDLE };
                proptest::prop_assert!(usize::from(last) <= max);
                if b.scale > 1 && !packed.wide {
                    let lens: Vec<usize> = m.out.iter().map(|e| 1 + e.len()).collect();
                    proptest::prop_assert!(extent(&lens, usize::from(b.scale) - 1).0 > NARROW_HANDLE);
                }
            }
        }
    }
}
