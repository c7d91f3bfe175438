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

use super::dfa::{Dfa, NONE};
use super::{Config, Inputs, SynthError};

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
#[derive(Clone, Copy)]
struct Field {
    word: usize,
    shift: u32,
    mask: u64,
}

/// Packed product tuples with a hash index from tuple to state id.
struct KeyStore {
    width: usize,
    words: Vec<u64>,
    slots: Vec<u32>,
}

impl KeyStore {
    fn new(width: usize) -> Self {
        KeyStore { width, words: Vec::new(), slots: vec![NONE; 1 << 10] }
    }

    fn len(&self) -> usize {
        self.words.len() / self.width
    }

    fn key(&self, id: u32) -> &[u64] {
        &self.words[id as usize * self.width..(id as usize + 1) * self.width]
    }

    fn hash(key: &[u64]) -> u64 {
        let mut h: u64 = 0x243F_6A88_85A3_08D3;
        for &w in key {
            h = (h ^ w).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            h ^= h >> 29;
        }
        h
    }

    /// The id of `key`, inserting it with the next id when new; the flag says whether it was new.
    fn insert(&mut self, key: &[u64]) -> (u32, bool) {
        let mask = self.slots.len() - 1;
        let mut i = Self::hash(key) as usize & mask;
        loop {
            let id = self.slots[i];
            if id == NONE {
                let id = self.len() as u32;
                self.slots[i] = id;
                self.words.extend_from_slice(key);
                if self.len() * 2 > self.slots.len() {
                    self.grow();
                }
                return (id, true);
            }
            if self.key(id) == key {
                return (id, false);
            }
            i = (i + 1) & mask;
        }
    }

    fn grow(&mut self) {
        let cap = self.slots.len() * 2;
        let mut slots = vec![NONE; cap];
        for id in 0..self.len() as u32 {
            let mut i = Self::hash(self.key(id)) as usize & (cap - 1);
            while slots[i] != NONE {
                i = (i + 1) & (cap - 1);
            }
            slots[i] = id;
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
pub(crate) struct Exploration {
    /// The product automaton.
    pub dfa: Dfa,
    keys: KeyStore,
    fields: Vec<Field>,
    /// (state, event) for each state where the plant generates an uncontrollable event the
    /// specification refuses (the first such event in ascending order), ascending by state.
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

    /// Walks the reachable product of `components` (all over the global events of `inputs`).
    pub(crate) fn run(
        components: &[&Dfa],
        inputs: &Inputs,
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
        let mut s = 0u32;
        while (s as usize) < keys.len() {
            key.copy_from_slice(keys.key(s));
            for (c, f) in fields.iter().enumerate() {
                cur[c] = ((key[f.word] >> f.shift) & f.mask) as u32;
            }
            let mut state_bad = false;
            for (i, &e) in union.iter().enumerate() {
                next.copy_from_slice(&key);
                let mut refused_by = None;
                for &(c, l) in &participants[i] {
                    let t = lookups[c].next[cur[c] as usize * lookups[c].width + l];
                    if t == NONE {
                        refused_by = Some(c);
                        break;
                    }
                    set(&mut next, fields[c], t);
                }
                match refused_by {
                    None => {
                        let (t, new) = keys.insert(&next);
                        if new {
                            if keys.len() > cfg.state_limit {
                                return Err(SynthError::StateLimit {
                                    what: what.to_owned(),
                                    limit: cfg.state_limit,
                                });
                            }
                            marked.push(components.iter().enumerate().all(|(c, d)| {
                                d.marked
                                    [((next[fields[c].word] >> fields[c].shift) & fields[c].mask) as usize]
                            }));
                            if options.parents {
                                parents.push((s, e));
                            }
                            if let Some(o) = &cfg.observer {
                                if keys.len() % (1 << 16) == 0 {
                                    o.states(what, keys.len());
                                }
                            }
                        }
                        events.push(e);
                        targets.push(t);
                    }
                    Some(c) => {
                        let plant_enables = c >= options.plants && participants[i][0].0 < options.plants;
                        if check_bad && !state_bad && plant_enables && !inputs.controllable[e as usize] {
                            state_bad = true;
                            bad.push((s, e));
                        }
                    }
                }
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
    if sources.len() == 1 {
        return sources[0].states[x.component_state(s, 0) as usize].name.clone();
    }
    let mut name = String::from("(");
    for (c, a) in sources.iter().enumerate() {
        if c > 0 {
            name.push(',');
        }
        name.push_str(&a.states[x.component_state(s, c) as usize].name);
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
    let x = Exploration::run(&dfas, &inputs, Options { plants: dfas.len(), parents: false }, cfg, &name)?;
    let kind = if automata.iter().all(|a| a.kind == Kind::Plant) { Kind::Plant } else { Kind::Unknown };
    let sources: Vec<&Automaton> = automata.iter().collect();
    Ok(x.dfa.to_automaton(&name, kind, &inputs.table, |s| tuple_name(&x, &sources, s)))
}
