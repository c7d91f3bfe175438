//! The state-based firmware's tables (`[runtime] mode = "state"`) checked on the firmware's own code
//! compiled for the host (`firmware::state`): on every reachable plant state of the distribution station
//! and every signal valuation that reads as it, the firmware's cube evaluation enables exactly the events
//! f allows (translation validation of the tables); a property test runs the runtime closed loop against
//! the plant automata under every choice policy, every command f-allowed and the word always reading as
//! the plant's state; and the refusals (memory, an input effect that depends on the source state) name
//! the manifest and why.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use codegen::feedback::tables::StateTables;
use codegen::feedback::{analyse, rules, Sfbc, Vector};
use codegen::project::Project;
use firmware::choice::Choose;
use firmware::choice::{First, GlobalQueue, LocalQueue, Random, RandomGlobalQueue, RandomLocalQueue};
use firmware::fault::FaultPolicy;
use firmware::rng::{Rng, SeedEntropy};
use firmware::runtime::{Applied, Config, Decide, Decision};
use firmware::state::StateRuntime;
use proptest::prelude::*;

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// The station's set, state vectors, feedback and firmware tables.
fn station() -> (Project, Vector, Sfbc, StateTables) {
    let project = Project::load(&repo("examples/distribution/distribution-state.toml")).unwrap();
    let signals = project.state.as_ref().unwrap().check().unwrap();
    let (vector, f) = analyse(&project.set, signals, false, &[]).unwrap();
    let rules = rules(&vector, &f, &Default::default(), false);
    let tables = StateTables::build(&project.set, &vector, &f, &rules).unwrap();
    (project, vector, f, tables)
}

#[test]
fn the_firmware_enables_exactly_f_on_every_reachable_state_and_every_valuation_reading_as_it() {
    let (_, vector, f, tables) = station();
    let host = tables.host::<1>().unwrap();
    let t = host.tables();
    let all = (1u32 << tables.signals.len()) - 1;
    let mut checked = 0;
    for e in &f.entries {
        let x = vector.cube(&e.state);
        let free = all & !(x.mask as u32);
        let mut sub = free;
        loop {
            let word = x.value as u32 | sub;
            let enabled = t.enabled(word);
            for (k, ev) in f.controllable.iter().enumerate() {
                assert_eq!(
                    enabled.contains(ev.index() as u8),
                    e.allowed[k],
                    "{ev:?} at {:?}, word {word:#b}",
                    e.state
                );
            }
            // Every component reads as its state (the local policies' sites).
            for (c, &s) in e.state.iter().enumerate() {
                let start = if c == 0 { 0 } else { usize::from(tables.ends[c - 1]) };
                assert_eq!(t.reading(c, word).map(|r| usize::from(r.code)), Some(start + s as usize));
            }
            checked += 1;
            if sub == 0 {
                break;
            }
            sub = (sub - 1) & free;
        }
    }
    // 52 reachable plant states, each read on every value of the signals its formula leaves free.
    assert_eq!(f.entries.len(), 52);
    assert!(checked >= 52, "{checked}");
}

#[test]
fn on_every_word_the_firmware_evaluates_the_rungs_codegen_wrote() {
    // Beyond the reachable states: all 2^11 values of the station's signals, the firmware's evaluation
    // of its (mask, value) cubes against codegen's rungs (the PLC program's F_σ) evaluated on 64 bits.
    let (_, vector, f, tables) = station();
    let rules = rules(&vector, &f, &Default::default(), false);
    let host = tables.host::<1>().unwrap();
    let t = host.tables();
    for word in 0..1u32 << tables.signals.len() {
        let enabled = t.enabled(word);
        for r in &rules {
            let holds = r.cubes.iter().any(|c| c.holds(u64::from(word)));
            assert_eq!(enabled.contains(r.event.index() as u8), holds, "{:?} at {word:#b}", r.event);
        }
    }
}

#[test]
fn the_tables_are_the_same_bytes_every_time() {
    let a = Project::load(&repo("examples/distribution/distribution-state.toml")).unwrap().emit().unwrap();
    let b = Project::load(&repo("examples/distribution/distribution-state.toml")).unwrap().emit().unwrap();
    assert_eq!(a, b);
    assert!(a.contains("pub static TABLES: firmware::state::StateTables"), "{a}");
    assert!(!a.contains("static BLOCK"), "no supervisor tables: {a}");
}

/// Runs the state runtime closed loop against the plant automata for `steps` steps drawn from `seed`,
/// with policy `policy`: the plant sends one of its possible sensor events half of the time, else the
/// runtime decides. Returns the (plant state, command) pairs fired.
fn walk<P: Choose<1>>(policy: P, seed: u32, steps: usize) -> std::collections::BTreeSet<(Vec<u32>, u8)> {
    let (project, vector, f, tables) = station();
    let host = tables.host::<1>().unwrap();
    let t = host.tables();
    let config = Config { guard: false, on_fault: FaultPolicy::Continue, reseed_every: 0 };
    let mut rt: StateRuntime<'_, P, SeedEntropy, 1, 4> =
        StateRuntime::new(&t, config, policy, SeedEntropy::new(u64::from(seed)));
    let by_state: HashMap<&[u32], &_> = f.entries.iter().map(|e| (e.state.as_slice(), e)).collect();
    let plants = &project.set.members()[..f.plants];
    let table = project.set.events();
    let mut x: Vec<u32> = plants.iter().map(|p| p.initial().index() as u32).collect();
    let mut dice = Rng::new(SeedEntropy::new(u64::from(seed) ^ 0x5EED), 0);
    let mut fired = std::collections::BTreeSet::new();
    for _ in 0..steps {
        assert!(vector.cube(&x).holds(u64::from(rt.word())), "word {:#b} does not read as {x:?}", rt.word());
        let entry =
            by_state.get(x.as_slice()).unwrap_or_else(|| panic!("{x:?} is not a reachable plant state"));
        let sensors: Vec<(usize, _, _)> = plants
            .iter()
            .enumerate()
            .flat_map(|(p, m)| {
                m.out(x[p] as usize).filter(|(e, _)| !table.is_controllable(*e)).map(move |(e, t)| (p, e, t))
            })
            .collect();
        if !sensors.is_empty() && dice.next_u32() & 1 == 0 {
            let (p, e, t) = sensors[dice.next_u32() as usize % sensors.len()];
            assert_eq!(rt.apply(e.index() as u8), Applied::Taken, "{} at {x:?}", table.name(e));
            x[p] = t.index() as u32;
            continue;
        }
        match rt.decide(|| false) {
            Decision::Fired(c) => {
                let k = f.controllable.iter().position(|ev| ev.index() == usize::from(c)).unwrap();
                assert!(
                    entry.allowed[k],
                    "{} fired at {x:?}, where f disables it",
                    table.name(f.controllable[k])
                );
                let p = vector.commands[usize::from(c)].unwrap().0;
                let (_, t) = plants[p].out(x[p] as usize).find(|(e, _)| e.index() == usize::from(c)).unwrap();
                fired.insert((x.clone(), c));
                x[p] = t.index() as u32;
            }
            Decision::Idle => {
                assert!(entry.allowed.iter().all(|a| !a), "idle at {x:?} where f allows a command");
                if sensors.is_empty() {
                    break;
                }
            }
            other => panic!("{other:?}"),
        }
    }
    fired
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn the_runtime_fires_only_what_f_allows_and_its_word_reads_as_the_plant(seed in any::<u32>(), policy in 0..6u8) {
        match policy {
            0 => { walk(First, seed, 400); }
            1 => { walk(Random, seed, 400); }
            2 => { walk(GlobalQueue::default(), seed, 400); }
            3 => { walk(RandomGlobalQueue::<1>::default(), seed, 400); }
            4 => { walk(LocalQueue::<0>::default(), seed, 400); }
            _ => { walk(RandomLocalQueue::<1, 0>::default(), seed, 400); }
        }
    }
}

#[test]
fn the_random_policy_fires_every_pair_f_allows() {
    // f allows 27 (plant state, command) pairs on the reachable states (docs/state-based.md).
    assert_eq!(walk(Random, 7, 20_000).len(), 27);
}

/// A scratch directory for the refusal tests' files.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("state_tables").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_sensor_event_whose_inputs_depend_on_its_source_state_is_refused_naming_it() {
    // `u` ends both moves of the valve: from `opening` it sets X, from `closing` it clears it.
    let dir = scratch("source");
    let gen = r#"<Generator>
"P"
<Alphabet>
"go" +C+ "u" "back" +C+
</Alphabet>
<States>
"closed" "opening" "open" "closing"
</States>
<TransRel>
"closed" "go" "opening"
"opening" "u" "open"
"open" "back" "closing"
"closing" "u" "closed"
</TransRel>
<InitStates>
"closed"
</InitStates>
<MarkedStates>
"closed"
</MarkedStates>
</Generator>
"#;
    std::fs::write(dir.join("P.gen"), gen).unwrap();
    // The supervisor is the plant itself, under a name of its own (one name, one automaton).
    std::fs::write(dir.join("S.gen"), gen).unwrap();
    let manifest = r#"name = "valve"
plants = ["P.gen"]
supervisors = ["S.gen"]
[runtime]
mode = "state"
[state.components.P]
inputs = [{ name = "X" }]
outputs = [{ name = "Y" }]
states = { closed = ["!Y", "!X"], opening = ["Y", "!X"], open = ["Y", "X"], closing = ["!Y", "X"] }
commands = { go = ["Y"], back = ["!Y"] }
"#;
    std::fs::write(dir.join("valve.toml"), manifest).unwrap();
    let err = Project::load(&dir.join("valve.toml")).unwrap().emit().unwrap_err().to_string();
    assert!(err.contains("valve.toml"), "{err}");
    assert!(err.contains("the inputs u sets depend on its source state"), "{err}");
    assert!(err.contains("from opening it sets X, from closing !X"), "{err}");
    // The command line prints it and exits 2.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_codegen"))
        .args(["emit", dir.join("valve.toml").to_str().unwrap(), "-o", dir.join("t.rs").to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("depend on its source state"));
}

#[test]
fn a_feedback_decided_by_supervisor_memory_is_refused_on_the_firmware() {
    let data = repo("codegen/tests/data/sfbc_memory");
    let dir = scratch("memory");
    let text = std::fs::read_to_string(data.join("memory.toml")).unwrap();
    let text = text
        .replace("\"M.gen\"", &format!("{:?}", data.join("M.gen")))
        .replace("\"S.gen\"", &format!("{:?}", data.join("S.gen")))
        .replace("[runtime]\n", "[runtime]\nmode = \"state\"\n");
    std::fs::write(dir.join("memory.toml"), text).unwrap();
    let err = Project::load(&dir.join("memory.toml")).unwrap().emit().unwrap_err().to_string();
    assert!(err.contains("the supervisors' memory decides at 1 plant state(s)"), "{err}");
    assert!(err.contains("mode = \"event\""), "{err}");
}

#[test]
fn more_signals_than_the_word_holds_are_refused_with_the_count() {
    let dir = scratch("wide");
    let gen = "<Generator>\n\"P\"\n<Alphabet>\n\"u\" \"c\" +C+\n</Alphabet>\n<States>\n\"s\"\n</States>\n<TransRel>\n\"s\" \"u\" \"s\"\n\"s\" \"c\" \"s\"\n</TransRel>\n<InitStates>\n\"s\"\n</InitStates>\n<MarkedStates>\n\"s\"\n</MarkedStates>\n</Generator>\n";
    std::fs::write(dir.join("P.gen"), gen).unwrap();
    // The supervisor is the plant itself, under a name of its own (one name, one automaton).
    std::fs::write(dir.join("S.gen"), gen).unwrap();
    let inputs: Vec<String> = (0..33).map(|i| format!("{{ name = \"X{i}\" }}")).collect();
    let manifest = format!(
        "name = \"wide\"\nplants = [\"P.gen\"]\nsupervisors = [\"S.gen\"]\n[runtime]\nmode = \"state\"\n\
         [state.components.P]\ninputs = [{}]\noutputs = [{{ name = \"Y\" }}]\nstates = {{ s = [] }}\ncommands = {{ c = [\"Y\"] }}\n",
        inputs.join(", ")
    );
    std::fs::write(dir.join("wide.toml"), manifest).unwrap();
    let err = Project::load(&dir.join("wide.toml")).unwrap().emit().unwrap_err().to_string();
    assert!(err.contains("wide.toml"), "{err}");
    assert!(err.contains("34 signals: the firmware packs at most 32 into its word"), "{err}");
}
