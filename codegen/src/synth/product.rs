//! On-the-fly synchronous product of n automata: only the reachable part is built.
//!
//! Shared events synchronise (every automaton that has the event in its alphabet must take it), the others
//! interleave. A product state is the tuple of component states, bit-packed into one or a few `u64` words
//! and kept in one flat array; an open-addressing table of `u32` ids finds a tuple again. States are numbered
//! in breadth-first order of discovery, events are tried in ascending global order, so the result is
//! deterministic and state ids double as shortest-trace order.
//!
//! The same walk serves supC: when the leading components are the plant and the rest the specification,
//! it records the states where the plant can generate an uncontrollable event that the specification
//! refuses (see [`Exploration::bad`]).

use crate::model::{Automaton, Kind};

use super::memory::admit;
use super::{Config, Inputs, SynthError};
use crate::model::{Dfa, NONE};

/// Dense next-state table of one component over its own alphabet.
struct Lookup {
    width: usize,
    next: Vec<u32>,
}

impl Lookup {
    fn new(d: &Dfa) -> Self {
        let width = d.alphabet.len();
        let mut next = vec![NONE; d.state_count() * width];
        for s in 0..d.state_count() as u32 {
            for (e, t) in d.edges(s) {
                let local = d.alphabet.binary_search(&e).unwrap_or_default();
                next[s as usize * width + local] = t;
            }
        }
        Lookup { width, next }
    }
}

/// Where one component's state lives in a packed key.
#[derive(Clone, Copy, Debug)]
struct Field {
    word: usize,
    shift: u32,
    mask: u64,
}

/// One slot of the index: the first word of a key (so most probes touch no other memory) and its id.
#[derive(Clone, Copy)]
struct Slot {
    first: u64,
    id: u32,
}

const EMPTY: Slot = Slot { first: 0, id: NONE };

/// New states between two looks at the process's resident size, besides the look before each new
/// index (for the memory the flat arrays take as they fill).
const MEMORY_CHECK_EVERY: usize = 1 << 14;

/// Packed product tuples with a hash index from tuple to state id (open addressing, linear probing, load
/// at most one half).
#[derive(Clone)]
struct KeyStore {
    width: usize,
    words: Vec<u64>,
    slots: Vec<Slot>,
}

impl KeyStore {
    fn new(width: usize) -> Self {
        KeyStore { width, words: Vec::new(), slots: vec![EMPTY; 1 << 10] }
    }

    fn len(&self) -> usize {
        self.words.len() / self.width
    }

    fn key(&self, id: u32) -> &[u64] {
        &self.words[id as usize * self.width..(id as usize + 1) * self.width]
    }

    /// A well-mixed hash (murmur3's 64-bit finaliser per word); callers take its high bits.
    fn hash(key: &[u64]) -> u64 {
        let mut h: u64 = 0x243F_6A88_85A3_08D3;
        for &w in key {
            h ^= w;
            h ^= h >> 33;
            h = h.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
            h ^= h >> 33;
            h = h.wrapping_mul(0xC4CE_B9FE_1A85_EC53);
            h ^= h >> 33;
        }
        h
    }

    /// The first slot to probe for a key with hash `h` in a table of `cap` (a power of two) slots.
    fn slot(h: u64, cap: usize) -> usize {
        (h >> (64 - cap.trailing_zeros())) as usize
    }

    /// The id of `key` when it is stored, else the empty slot where it belongs.
    fn probe(&self, key: &[u64]) -> Result<u32, usize> {
        let mask = self.slots.len() - 1;
        let mut i = Self::slot(Self::hash(key), self.slots.len());
        loop {
            let slot = self.slots[i];
            if slot.id == NONE {
                return Err(i);
            }
            if slot.first == key[0] && (self.width == 1 || self.key(slot.id)[1..] == key[1..]) {
                return Ok(slot.id);
            }
            i = (i + 1) & mask;
        }
    }

    /// The bytes the next insertion of a new key takes at once: a new index of twice the slots, written
    /// whole while the old one is still held, when the load would pass one half. (The flat arrays grow
    /// by reallocation too, but their new pages become resident only as they are written; the periodic
    /// look covers them.)
    fn growth(&self) -> u64 {
        if (self.len() + 1) * 2 > self.slots.len() {
            (self.slots.len() * 2 * std::mem::size_of::<Slot>()) as u64
        } else {
            0
        }
    }

    /// The id of `key`, inserting it with the next id when new; the flag says whether it was new.
    fn insert(&mut self, key: &[u64]) -> (u32, bool) {
        match self.probe(key) {
            Ok(id) => (id, false),
            Err(i) => {
                let id = self.len() as u32;
                self.slots[i] = Slot { first: key[0], id };
                self.words.extend_from_slice(key);
                if self.len() * 2 > self.slots.len() {
                    self.grow();
                }
                (id, true)
            }
        }
    }

    /// Reads the first slot `key` would probe, so that a batch of lookups issued back to back overlaps
    /// its cache misses instead of paying them one after the other.
    fn touch(&self, key: &[u64]) -> u32 {
        self.slots[Self::slot(Self::hash(key), self.slots.len())].id
    }

    fn grow(&mut self) {
        let cap = self.slots.len() * 2;
        let mut slots = vec![EMPTY; cap];
        for id in 0..self.len() as u32 {
            let key = self.key(id);
            let mut i = Self::slot(Self::hash(key), cap);
            while slots[i].id != NONE {
                i = (i + 1) & (cap - 1);
            }
            slots[i] = Slot { first: key[0], id };
        }
        self.slots = slots;
    }
}

/// What the walk should record besides the product itself.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Options {
    /// Number of leading components that form the plant; the others are specifications. Bad states are
    /// recorded only when this is less than the number of components.
    pub plants: usize,
    /// Whether to record each state's breadth-first parent (for traces).
    pub parents: bool,
}

/// The reachable product of n components, with the tuples behind its states.
#[derive(Clone)]
pub(crate) struct Exploration {
    /// The product automaton.
    pub dfa: Dfa,
    keys: KeyStore,
    fields: Vec<Field>,
    /// (state, event) for each state where the plant generates an uncontrollable event the
    /// specification refuses (the first such event in ascending order), ascending by state. Such states are
    /// not expanded: they have no transitions in [`Exploration::dfa`].
    pub bad: Vec<(u32, u32)>,
    /// Breadth-first parent (state, event) of each state (the initial state points to itself), if asked.
    pub parents: Vec<(u32, u32)>,
}

impl Exploration {
    /// The state of component `c` in product state `s`.
    pub(crate) fn component_state(&self, s: u32, c: usize) -> u32 {
        let f = self.fields[c];
        ((self.keys.key(s)[f.word] >> f.shift) & f.mask) as u32
    }

    /// The number of the state whose components are in the states `tuple`, if it was reached.
    pub(crate) fn id(&self, tuple: &[u32]) -> Option<u32> {
        if tuple.len() != self.fields.len() {
            return None;
        }
        let mut key = vec![0u64; self.keys.width];
        for (&f, &v) in self.fields.iter().zip(tuple) {
            if u64::from(v) > f.mask {
                return None;
            }
            set(&mut key, f, v);
        }
        self.keys.probe(&key).ok()
    }

    /// The events of the breadth-first (shortest) trace from the initial state to `s`.
    pub(crate) fn trace(&self, mut s: u32) -> Vec<u32> {
        let mut events = Vec::new();
        while let Some(&(p, e)) = self.parents.get(s as usize) {
            if p == s {
                break;
            }
            events.push(e);
            s = p;
        }
        events.reverse();
        events
    }

    /// Walks the reachable product of `components` (all over the global events of one table, whose
    /// controllable ones `controllable` marks).
    pub(crate) fn run(
        components: &[&Dfa],
        controllable: &[bool],
        options: Options,
        cfg: &Config,
        what: &str,
    ) -> Result<Exploration, SynthError> {
        let lookups: Vec<Lookup> = components.iter().map(|d| Lookup::new(d)).collect();
        let fields = layout(components);
        let width = fields.iter().map(|f| f.word + 1).max().unwrap_or(1);
        let mut union: Vec<u32> = components.iter().flat_map(|d| d.alphabet.iter().copied()).collect();
        union.sort_unstable();
        union.dedup();
        // Participants of each event: (component, local index), plant components first.
        let participants: Vec<Vec<(usize, usize)>> = union
            .iter()
            .map(|&e| {
                components
                    .iter()
                    .enumerate()
                    .filter_map(|(c, d)| d.alphabet.binary_search(&e).ok().map(|l| (c, l)))
                    .collect()
            })
            .collect();
        let check_bad = options.plants < components.len();
        // Events whose refusal can make a state bad: uncontrollable, in the plant and in the specification.
        let guarded: Vec<usize> = (0..union.len())
            .filter(|&i| {
                let p = &participants[i];
                check_bad
                    && !controllable[union[i] as usize]
                    && p.first().is_some_and(|&(c, _)| c < options.plants)
                    && p.last().is_some_and(|&(c, _)| c >= options.plants)
            })
            .collect();

        let mut keys = KeyStore::new(width);
        let mut marked = Vec::new();
        let mut offsets = vec![0usize];
        let mut events = Vec::new();
        let mut targets = Vec::new();
        let mut bad = Vec::new();
        let mut parents = Vec::new();
        let empty = components.iter().any(|d| d.initial.is_none());
        if !empty {
            let mut key = vec![0u64; width];
            for (c, d) in components.iter().enumerate() {
                set(&mut key, fields[c], d.initial.unwrap_or_default());
            }
            keys.insert(&key);
            marked.push(components.iter().all(|d| d.marked[d.initial.unwrap_or_default() as usize]));
            if options.parents {
                parents.push((0, NONE));
            }
        }
        let mut cur = vec![0u32; components.len()];
        let mut key = vec![0u64; width];
        let mut next = vec![0u64; width];
        let mut batch: Vec<u64> = Vec::new();
        let mut batch_events: Vec<u32> = Vec::new();
        let mut s = 0u32;
        while (s as usize) < keys.len() {
            key.copy_from_slice(keys.key(s));
            for (c, f) in fields.iter().enumerate() {
                cur[c] = ((key[f.word] >> f.shift) & f.mask) as u32;
            }
            // A bad state is removed by supC whatever follows it: record it and do not expand it.
            let refused = guarded.iter().copied().find(|&i| {
                let mut plant_enables = true;
                for &(c, l) in &participants[i] {
                    let enabled = lookups[c].next[cur[c] as usize * lookups[c].width + l] != NONE;
                    if c < options.plants {
                        plant_enables &= enabled;
                    } else if !enabled {
                        return plant_enables;
                    }
                }
                false
            });
            if let Some(i) = refused {
                bad.push((s, union[i]));
                offsets.push(events.len());
                s += 1;
                continue;
            }
            // Successor keys first, then one pass touching their slots, then the lookups proper.
            batch.clear();
            batch_events.clear();
            'events: for (i, &e) in union.iter().enumerate() {
                next.copy_from_slice(&key);
                for &(c, l) in &participants[i] {
                    let t = lookups[c].next[cur[c] as usize * lookups[c].width + l];
                    if t == NONE {
                        continue 'events;
                    }
                    set(&mut next, fields[c], t);
                }
                batch.extend_from_slice(&next);
                batch_events.push(e);
            }
            let mut touched = 0u32;
            for next in batch.chunks_exact(width) {
                touched ^= keys.touch(next);
            }
            std::hint::black_box(touched);
            for (next, &e) in batch.chunks_exact(width).zip(&batch_events) {
                if cfg.memory_limit.is_some() {
                    let extra = if keys.probe(next).is_err() { keys.growth() } else { 0 };
                    if extra > 0 || (keys.len() + 1).is_multiple_of(MEMORY_CHECK_EVERY) {
                        admit(cfg, what, keys.len(), extra)?;
                    }
                }
                let (t, new) = keys.insert(next);
                if new {
                    if keys.len() > cfg.state_limit {
                        return Err(SynthError::StateLimit { what: what.to_owned(), limit: cfg.state_limit });
                    }
                    marked.push(components.iter().enumerate().all(|(c, d)| {
                        d.marked[((next[fields[c].word] >> fields[c].shift) & fields[c].mask) as usize]
                    }));
                    if options.parents {
                        parents.push((s, e));
                    }
                    if let Some(o) = &cfg.observer {
                        if keys.len().is_multiple_of(1 << 16) {
                            o.states(what, keys.len());
                        }
                    }
                }
                events.push(e);
                targets.push(t);
            }
            offsets.push(events.len());
            s += 1;
        }
        let mut alphabet = union;
        alphabet.shrink_to_fit();
        let initial = if empty { None } else { Some(0) };
        let dfa = Dfa { alphabet, initial, marked, offsets, events, targets };
        Ok(Exploration { dfa, keys, fields, bad, parents })
    }
}

fn set(key: &mut [u64], f: Field, value: u32) {
    key[f.word] = (key[f.word] & !(f.mask << f.shift)) | (u64::from(value) << f.shift);
}

/// Packs each component's state into a bit field, never splitting a field across two words.
fn layout(components: &[&Dfa]) -> Vec<Field> {
    let mut fields = Vec::with_capacity(components.len());
    let (mut word, mut used) = (0usize, 0u32);
    for d in components {
        let n = d.state_count().max(2) as u64 - 1;
        let bits = 64 - n.leading_zeros();
        if used + bits > 64 {
            word += 1;
            used = 0;
        }
        fields.push(Field {
            word,
            shift: used,
            mask: if bits == 64 { u64::MAX } else { (1u64 << bits) - 1 },
        });
        used += bits;
    }
    fields
}

/// Name of a product state: the component state names in parentheses, or the one name for one component.
pub(crate) fn tuple_name(x: &Exploration, sources: &[&Automaton], s: u32) -> String {
    name_of_tuple(sources, |c| x.component_state(s, c))
}

/// Name of the tuple whose component `c` is in state `state_of(c)` of `sources[c]`: the names in
/// parentheses, or the one name for one component.
pub(crate) fn name_of_tuple(sources: &[&Automaton], state_of: impl Fn(usize) -> u32) -> String {
    if sources.len() == 1 {
        return sources[0].states[state_of(0) as usize].name.clone();
    }
    let mut name = String::from("(");
    for (c, a) in sources.iter().enumerate() {
        if c > 0 {
            name.push(',');
        }
        name.push_str(&a.states[state_of(c) as usize].name);
    }
    name.push(')');
    name
}

/// The reachable synchronous product of `automata`, named by joining their names with `||`.
///
/// States are named by the tuple of component state names; the kind is [`Kind::Plant`] when every
/// component is a plant, [`Kind::Unknown`] otherwise.
pub fn product(automata: &[Automaton], cfg: &Config) -> Result<Automaton, SynthError> {
    let inputs = Inputs::new(automata.iter())?;
    let dfas: Vec<&Dfa> = inputs.dfas.iter().collect();
    let name = automata.iter().map(|a| a.name.as_str()).collect::<Vec<_>>().join("||");
    let x = Exploration::run(
        &dfas,
        &inputs.controllable,
        Options { plants: dfas.len(), parents: false },
        cfg,
        &name,
    )?;
    let kind = if automata.iter().all(|a| a.kind == Kind::Plant) { Kind::Plant } else { Kind::Unknown };
    let sources: Vec<&Automaton> = automata.iter().collect();
    Ok(x.dfa.to_automaton(&name, kind, &inputs.table, |s| tuple_name(&x, &sources, s)))
}

/// The reachable part of the synchronous product of automata over one event table, explored breadth
/// first from the initial state: states numbered in the order they are found, events tried in
/// increasing id, each state with the tuple of its components' states. What the monitor's coverage
/// walks.
#[derive(Clone)]
pub struct Reachable(Exploration);

impl std::fmt::Debug for Reachable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Reachable").field("states", &self.0.dfa.state_count()).finish()
    }
}

impl Reachable {
    /// Explores the product of `components`; stops with [`SynthError::StateLimit`] past `limit` states.
    pub fn explore(components: &[&Dfa], limit: usize) -> Result<Reachable, SynthError> {
        // Every component counts as plant: no state is bad, so controllability is never consulted.
        let events = components.iter().flat_map(|d| d.alphabet()).max().map_or(0, |&e| e as usize + 1);
        let cfg = Config { state_limit: limit, ..Config::default() };
        let options = Options { plants: components.len(), parents: false };
        Exploration::run(components, &vec![false; events], options, &cfg, "reachable product").map(Reachable)
    }

    /// The product: state `s`'s transitions over the global events.
    pub fn dfa(&self) -> &Dfa {
        &self.0.dfa
    }

    /// The state of component `c` in product state `s`.
    pub fn component_state(&self, s: u32, c: usize) -> u32 {
        self.0.component_state(s, c)
    }

    /// The states of every component in product state `s`.
    pub fn tuple(&self, s: u32) -> Vec<u32> {
        (0..self.0.fields.len()).map(|c| self.0.component_state(s, c)).collect()
    }

    /// The number of the product state whose components are in the states `tuple`, if it is reachable.
    pub fn id(&self, tuple: &[u32]) -> Option<u32> {
        self.0.id(tuple)
    }
}
