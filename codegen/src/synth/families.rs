//! Generated synthesis instances of any size, for benchmarks and differential tests against the reference
//! tools: the classic transfer line, the small factory generalised to n machines with breakdown and repair,
//! cat and mouse with k cats, dining philosophers and seeded random systems.
//!
//! Every generator is deterministic: the same family and size give the same automata, so the Rust benches
//! and the scripts that run libFAUDES and TCT on files written from here see identical inputs.

use crate::model::{Automaton, Kind, StateId};

/// Plants and specifications of one generated instance.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Instance {
    /// Name, such as `factory-5`.
    pub name: String,
    /// Plant subsystems.
    pub plants: Vec<Automaton>,
    /// Specifications.
    pub specs: Vec<Automaton>,
}

/// The families [`generate`] knows, by name.
pub const FAMILIES: [&str; 7] =
    ["transfer-line", "transfer-line-k3", "factory", "cat-mouse", "philosophers", "random", "interlock"];

/// The instance of `family` (one of [`FAMILIES`]) with size parameter `n`, or `None` for an unknown family.
pub fn generate(family: &str, n: usize) -> Option<Instance> {
    let (plants, specs) = match family {
        "transfer-line" => transfer_line(n, 1),
        "transfer-line-k3" => transfer_line(n, 3),
        "factory" => factory(n),
        "cat-mouse" => cat_mouse(n),
        "philosophers" => philosophers(n),
        "random" => random(n),
        "interlock" => interlock(n),
        _ => return None,
    };
    Some(Instance { name: format!("{family}-{n}"), plants, specs })
}

/// Builds an automaton from (name, marked) states (the first is initial), (name, controllable) events and
/// (source, event, target) transitions by index.
fn build(
    name: &str,
    kind: Kind,
    states: &[(String, bool)],
    events: &[(String, bool)],
    delta: &[(usize, usize, usize)],
) -> Automaton {
    let mut a = Automaton::new(name, kind);
    for (s, m) in states {
        a.states.push(crate::model::State { name: s.clone(), marked: *m });
    }
    for (e, c) in events {
        a.events.push(crate::model::Event { name: e.clone(), controllable: *c });
    }
    a.initial = Some(StateId::from_u32(0));
    for &(s, e, t) in delta {
        a.add_transition(
            StateId::from_u32(s as u32),
            crate::model::EventId::from_u32(e as u32),
            StateId::from_u32(t as u32),
        );
    }
    a.canonicalize();
    a
}

fn states(n: usize) -> Vec<(String, bool)> {
    (0..n).map(|i| (i.to_string(), i == 0)).collect()
}

/// `n` stations in a row, each a cycle go (controllable, the output on) → done (uncontrollable, the
/// sensor on) → ret (controllable, the output off) → back (uncontrollable, the sensor off) like the
/// distribution station's injector, and between neighbours an interlock: never both busy (between go
/// and back). The interlock's state is a function of the stations' states, so its state feedback needs
/// no memory; with [`state_section`] it is the state-based program's instance whose closed loop
/// (about 2.3^n plant states) outgrows explicit listing.
fn interlock(n: usize) -> (Vec<Automaton>, Vec<Automaton>) {
    let plants = (1..=n)
        .map(|i| {
            let ev = [
                (format!("go{i}"), true),
                (format!("done{i}"), false),
                (format!("ret{i}"), true),
                (format!("back{i}"), false),
            ];
            build(
                &format!("S{i}"),
                Kind::Plant,
                &states(4),
                &ev,
                &[(0, 0, 1), (1, 1, 2), (2, 2, 3), (3, 3, 0)],
            )
        })
        .collect();
    let specs = (1..n)
        .map(|i| {
            let j = i + 1;
            let users = [format!("go{i}"), format!("back{i}"), format!("go{j}"), format!("back{j}")];
            exclusion(&format!("E{i}"), users)
        })
        .collect();
    (plants, specs)
}

/// A specification that two users never hold one resource at once (a station's busy span, a fork):
/// from free (state 0), the first takes it (controllable) into state 1 and gives it back
/// (uncontrollable), the second likewise through state 2. `events`: take and give back of the first
/// user, then of the second.
fn exclusion(name: &str, events: [String; 4]) -> Automaton {
    let [take_a, give_a, take_b, give_b] = events;
    let ev = [(take_a, true), (give_a, false), (take_b, true), (give_b, false)];
    build(name, Kind::Spec, &states(3), &ev, &[(0, 0, 1), (1, 1, 0), (0, 2, 2), (2, 3, 0)])
}

/// The manifest's `[state]` section of `family`'s instance of size `n`, for the families whose plants
/// have state vectors (`interlock`: station i's output `Yi` and sensor `Xi`; at most 32 stations, the
/// 64 signals of a state-based program); `None` for the others.
pub fn state_section(family: &str, n: usize) -> Option<String> {
    if family != "interlock" || n > crate::config::MAX_SIGNALS / 2 {
        return None;
    }
    let mut toml = String::new();
    for i in 1..=n {
        toml.push_str(&format!(
            "\n[state.components.S{i}]\ninputs = [{{ name = \"X{i}\" }}]\noutputs = [{{ name = \"Y{i}\" }}]\n\
             states = {{ 0 = [\"!Y{i}\", \"!X{i}\"], 1 = [\"Y{i}\", \"!X{i}\"], 2 = [\"Y{i}\", \"X{i}\"], \
             3 = [\"!Y{i}\", \"X{i}\"] }}\ncommands = {{ go{i} = [\"Y{i}\"], ret{i} = [\"!Y{i}\"] }}\n"
        ));
    }
    Some(toml)
}

/// `n` machines (start controllable, finish uncontrollable) in a line with a buffer of `capacity` slots
/// between neighbours: no overflow, no underflow. `transfer-line` has one slot, `transfer-line-k3`
/// three (a product of 2^n·4^(n-1) states: the instance that outgrows explicit synthesis).
fn transfer_line(n: usize, capacity: usize) -> (Vec<Automaton>, Vec<Automaton>) {
    let plants = (1..=n)
        .map(|i| {
            let ev = [(format!("s{i}"), true), (format!("f{i}"), false)];
            build(&format!("M{i}"), Kind::Plant, &states(2), &ev, &[(0, 0, 1), (1, 1, 0)])
        })
        .collect();
    let specs = (1..n)
        .map(|i| {
            let ev = [(format!("f{i}"), false), (format!("s{}", i + 1), true)];
            build(&format!("B{i}"), Kind::Spec, &states(capacity + 1), &ev, &buffer(capacity))
        })
        .collect();
    (plants, specs)
}

/// A buffer of `capacity` slots over (put, take): state k holds k items.
fn buffer(capacity: usize) -> Vec<(usize, usize, usize)> {
    (0..capacity).flat_map(|k| [(k, 0, k + 1), (k + 1, 1, k)]).collect()
}

/// Capacity of each buffer of the small factory.
const FACTORY_BUFFER: usize = 2;

/// The small factory with `n` machines: each starts (controllable), finishes or breaks down
/// (uncontrollable) and is repaired (controllable); two-slot buffers between neighbours (no overflow, no
/// underflow), and a machine is repaired only while the next one is not down.
fn factory(n: usize) -> (Vec<Automaton>, Vec<Automaton>) {
    let plants = (1..=n)
        .map(|i| {
            let ev = [
                (format!("s{i}"), true),
                (format!("f{i}"), false),
                (format!("b{i}"), false),
                (format!("r{i}"), true),
            ];
            build(
                &format!("M{i}"),
                Kind::Plant,
                &states(3),
                &ev,
                &[(0, 0, 1), (1, 1, 0), (1, 2, 2), (2, 3, 0)],
            )
        })
        .collect();
    let mut specs: Vec<Automaton> = (1..n)
        .map(|i| {
            let ev = [(format!("f{i}"), false), (format!("s{}", i + 1), true)];
            build(&format!("B{i}"), Kind::Spec, &states(FACTORY_BUFFER + 1), &ev, &buffer(FACTORY_BUFFER))
        })
        .collect();
    specs.extend((1..n).map(|i| {
        let j = i + 1;
        let ev = [(format!("b{j}"), false), (format!("r{j}"), true), (format!("r{i}"), true)];
        build(&format!("R{i}"), Kind::Spec, &states(2), &ev, &[(0, 0, 1), (1, 1, 0), (0, 2, 0)])
    }));
    (plants, specs)
}

/// Doors of the maze: (from room, to room, controllable).
const CAT_DOORS: [(usize, usize, bool); 7] =
    [(0, 1, true), (1, 2, true), (2, 0, true), (1, 3, true), (3, 1, true), (3, 4, true), (4, 3, false)];
const MOUSE_DOORS: [(usize, usize, bool); 6] =
    [(0, 2, true), (2, 1, true), (1, 0, true), (0, 4, true), (4, 3, true), (3, 0, true)];
const CAT_HOME: usize = 2;
const MOUSE_HOME: usize = 4;

fn rooms(home: usize) -> Vec<(String, bool)> {
    // State 0 is the home room (initial and marked), then the others in order.
    let mut order = vec![home];
    order.extend((0..5).filter(|&r| r != home));
    order.iter().map(|r| (format!("room{r}"), *r == home)).collect()
}

fn room_index(home: usize, room: usize) -> usize {
    if room == home {
        0
    } else {
        (0..5).filter(|&r| r != home).position(|r| r == room).unwrap_or(0) + 1
    }
}

/// `k` cats and `k` mice in the five-room maze; for every cat and mouse, a specification that they never
/// share a room, marked when both are home.
fn cat_mouse(k: usize) -> (Vec<Automaton>, Vec<Automaton>) {
    let cat_events = |j: usize| -> Vec<(String, bool)> {
        CAT_DOORS.iter().enumerate().map(|(d, &(_, _, c))| (format!("c{j}_{}", d + 1), c)).collect()
    };
    let mouse_events = |i: usize| -> Vec<(String, bool)> {
        MOUSE_DOORS.iter().enumerate().map(|(d, &(_, _, c))| (format!("m{i}_{}", d + 1), c)).collect()
    };
    let mut plants: Vec<Automaton> = (1..=k)
        .map(|j| {
            let delta: Vec<_> = CAT_DOORS
                .iter()
                .enumerate()
                .map(|(d, &(f, t, _))| (room_index(CAT_HOME, f), d, room_index(CAT_HOME, t)))
                .collect();
            build(&format!("Cat{j}"), Kind::Plant, &rooms(CAT_HOME), &cat_events(j), &delta)
        })
        .collect();
    plants.extend((1..=k).map(|i| {
        let delta: Vec<_> = MOUSE_DOORS
            .iter()
            .enumerate()
            .map(|(d, &(f, t, _))| (room_index(MOUSE_HOME, f), d, room_index(MOUSE_HOME, t)))
            .collect();
        build(&format!("Mouse{i}"), Kind::Plant, &rooms(MOUSE_HOME), &mouse_events(i), &delta)
    }));
    // States of a pair specification: (cat room, mouse room) in different rooms; (home, home) first.
    let mut pairs = vec![(CAT_HOME, MOUSE_HOME)];
    for c in 0..5 {
        for m in 0..5 {
            if c != m && (c, m) != (CAT_HOME, MOUSE_HOME) {
                pairs.push((c, m));
            }
        }
    }
    let id = |c: usize, m: usize| pairs.iter().position(|&p| p == (c, m));
    let mut delta = Vec::new();
    for (s, &(c, m)) in pairs.iter().enumerate() {
        for (d, &(f, t, _)) in CAT_DOORS.iter().enumerate() {
            if let Some(x) = id(t, m).filter(|_| f == c) {
                delta.push((s, d, x));
            }
        }
        for (d, &(f, t, _)) in MOUSE_DOORS.iter().enumerate() {
            if let Some(x) = id(c, t).filter(|_| f == m) {
                delta.push((s, CAT_DOORS.len() + d, x));
            }
        }
    }
    let st: Vec<(String, bool)> =
        pairs.iter().map(|&(c, m)| (format!("c{c}m{m}"), (c, m) == (CAT_HOME, MOUSE_HOME))).collect();
    let mut specs = Vec::new();
    for j in 1..=k {
        for i in 1..=k {
            let mut events = cat_events(j);
            events.extend(mouse_events(i));
            specs.push(build(&format!("Apart{j}_{i}"), Kind::Spec, &st, &events, &delta));
        }
    }
    (plants, specs)
}

/// `n` philosophers around a table: each takes the left and the right fork (controllable, either order)
/// and puts both back after eating (uncontrollable); one specification per fork says one holder at a time.
fn philosophers(n: usize) -> (Vec<Automaton>, Vec<Automaton>) {
    let plants = (0..n)
        .map(|i| {
            let ev = [(format!("l{i}"), true), (format!("r{i}"), true), (format!("p{i}"), false)];
            build(
                &format!("P{i}"),
                Kind::Plant,
                &states(4),
                &ev,
                &[(0, 0, 1), (0, 1, 3), (1, 1, 2), (3, 0, 2), (2, 2, 0)],
            )
        })
        .collect();
    let specs = (0..n)
        .map(|j| {
            // Fork j is philosopher j's left fork and philosopher j+1's right fork.
            let k = (j + 1) % n;
            exclusion(&format!("F{j}"), [format!("l{j}"), format!("p{j}"), format!("r{k}"), format!("p{k}")])
        })
        .collect();
    (plants, specs)
}

/// The `random` instance of size `n` drawn from `seed` instead of the family's fixed seed: the
/// differential tests draw fresh instances each run and print the seed that reproduces one.
pub fn random_seeded(n: usize, seed: u64) -> Instance {
    let (plants, specs) = random_from(n, seed);
    Instance { name: format!("random-{n}-s{seed}"), plants, specs }
}

/// The family's own `random` instance of size `n`.
fn random(n: usize) -> (Vec<Automaton>, Vec<Automaton>) {
    random_from(n, 0x9E37_79B9 ^ n as u64)
}

/// A random system: `n` plants of 3–5 states over private events plus a few shared ones, and `n`
/// specifications of 2–4 states over events of two neighbouring plants, all drawn from `seed`.
fn random_from(n: usize, seed: u64) -> (Vec<Automaton>, Vec<Automaton>) {
    // xorshift never leaves 0.
    let mut rng = XorShift(seed.max(1));
    let plant_events = |i: usize| -> Vec<(String, bool)> {
        vec![
            (format!("a{i}"), true),
            (format!("b{i}"), true),
            (format!("u{i}"), false),
            (format!("v{i}"), false),
        ]
    };
    // Plants: a cycle through all states on their first event plus random transitions (two in three
    // defined), half the states marked. Specifications: every state marked, uncontrollable events always
    // defined, controllable ones two in three; so supervisors are rarely empty.
    let mut random_automaton = |name: &str, kind: Kind, events: Vec<(String, bool)>, size: usize| {
        let plant = kind == Kind::Plant;
        let st: Vec<(String, bool)> =
            (0..size).map(|s| (s.to_string(), !plant || s == 0 || rng.below(2) != 0)).collect();
        let mut delta = Vec::new();
        for s in 0..size {
            for (e, (_, controllable)) in events.iter().enumerate() {
                if plant && e == 0 {
                    delta.push((s, e, (s + 1) % size));
                } else if !plant && !controllable || rng.below(3) != 0 {
                    delta.push((s, e, rng.below(size)));
                }
            }
        }
        build(name, kind, &st, &events, &delta)
    };
    let plants: Vec<Automaton> =
        (0..n).map(|i| random_automaton(&format!("G{i}"), Kind::Plant, plant_events(i), 2 + i % 3)).collect();
    let specs = (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            let mut ev = plant_events(i);
            if j != i {
                ev.extend(plant_events(j));
            }
            random_automaton(&format!("E{i}"), Kind::Spec, ev, 2 + i % 3)
        })
        .collect();
    (plants, specs)
}

/// A small deterministic generator (xorshift64), so instances do not depend on a random crate's version.
struct XorShift(u64);

impl XorShift {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_generates_valid_automata() {
        for family in FAMILIES {
            let inst = generate(family, 3).unwrap();
            for a in inst.plants.iter().chain(&inst.specs) {
                a.validate().unwrap_or_else(|e| panic!("{family}: {}: {e}", a.name));
            }
            assert!(crate::model::EventTable::build(inst.plants.iter().chain(&inst.specs)).is_ok());
        }
        assert!(generate("nope", 3).is_none());
    }
}
