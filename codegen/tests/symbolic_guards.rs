//! Guards off the BDDs against the explicit feedback (issue 27): the rungs `--engine symbolic` writes,
//! F_σ read off the symbolic supervisor's BDDs, are the rungs the explicit closed loop of the CLI's
//! local modular set gives — the same ON set, the same don't-cares, hence the same minimised cover —
//! with and without don't-cares, on the distribution station and on the `interlock` family; and on an
//! interlock far beyond explicit listing, the exact count of its reachable plant states.

use std::path::{Path, PathBuf};

use codegen::config::ScanPolicy;
use codegen::feedback::memory::Layout;
use codegen::feedback::minimise::Universe;
use codegen::feedback::{self, guards};
use codegen::formats::write_path;
use codegen::plc::state_based::{Engine, StateOptions};
use codegen::plc::Form;
use codegen::project::{Project, Sources};
use codegen::symbolic::{Guards, Options};
use codegen::synth::families::{generate, state_section};
use codegen::synth::Config;
use num_bigint::BigUint;

/// The rungs from guards equal the explicit ones on the manifest at `manifest`.
fn same_rungs(manifest: &Path) {
    let loaded = Sources::project(&[manifest.to_owned()]).load().unwrap();
    let project = Project::load(manifest).unwrap();
    let signals = project.state.as_ref().unwrap().check().unwrap();
    let (vector, f) = feedback::analyse(&project.set, signals, false, &[]).unwrap();
    assert!(f.conflicts.is_empty());
    let (plants, specs) = (&loaded.models.plants, &loaded.models.specs);
    let g = Guards::compute(plants, specs, &Config::default(), &Options::default()).unwrap();
    assert_eq!(g.count(&g.reachable), f.entries.len().into());
    let n = vector.signals.signals.len();
    let u = Universe::new(n);
    let cubes: Vec<_> = f.entries.iter().map(|e| vector.cube(&e.state)).collect();
    let reachable = u.union(&cubes);
    assert!(g.to_signals(&g.reachable, &vector.cubes, n).iff(&reachable).is_true());
    for exact in [false, true] {
        let explicit = feedback::rules(&vector, &f, &Layout::default(), exact);
        let symbolic = guards::rules(&project.set, &vector, &g, exact).unwrap();
        assert_eq!(symbolic.len(), explicit.len());
        for (i, (s, e)) in symbolic.iter().zip(&explicit).enumerate() {
            assert_eq!(s.event, e.event);
            assert_eq!(s.cubes, e.cubes, "{:?} (exact: {exact})", s.event);
            assert_eq!(s.command, e.command, "{:?}", s.event);
            // F_σ separates the reachable states f allows from those it does not.
            let on: Vec<_> =
                f.entries.iter().zip(&cubes).filter(|(x, _)| x.allowed[i]).map(|(_, &c)| c).collect();
            let on = u.union(&on);
            assert!(u.separates(&s.cubes, &on, &reachable.and_not(&on)), "{:?}", s.event);
        }
    }
}

/// Writes the `interlock` instance of `n` stations with its `[state]` section under `dir`, as the
/// `families` example does; returns the manifest.
fn interlock(n: usize, dir: &Path) -> PathBuf {
    let inst = generate("interlock", n).unwrap();
    let mut manifest = format!("name = \"{}\"\n", inst.name);
    for (key, automata) in [("plants", &inst.plants), ("specs", &inst.specs)] {
        std::fs::create_dir_all(dir.join(key)).unwrap();
        let files: Vec<String> = automata.iter().map(|a| format!("\"{key}/{}.xmd\"", a.name)).collect();
        manifest.push_str(&format!("{key} = [{}]\n", files.join(", ")));
        for a in automata {
            write_path(&dir.join(key).join(format!("{}.xmd", a.name)), std::slice::from_ref(a)).unwrap();
        }
    }
    manifest.push_str(&state_section("interlock", n).unwrap());
    let path = dir.join("interlock.toml");
    std::fs::write(&path, manifest).unwrap();
    path
}

#[test]
fn the_distribution_station_gives_the_explicit_rungs() {
    same_rungs(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/distribution/distribution.toml")));
}

/// `files` without their header's command line, which names the engine.
fn without_command(files: &[(String, String)]) -> Vec<(String, String)> {
    let body = |text: &str| {
        text.lines().filter(|l| !l.contains("Command: codegen plc")).collect::<Vec<_>>().join("\n")
    };
    files.iter().map(|(name, text)| (name.clone(), body(text))).collect()
}

#[test]
fn every_choice_policy_gives_the_explicit_program_from_guards() {
    let manifest =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/distribution/distribution.toml"));
    let project = Project::load(manifest).unwrap();
    let state = |options, engine| project.plc(&Form::State { options, engine }).unwrap();
    let fixed_order = state(StateOptions::default(), Engine::Explicit).into_state().unwrap().files;
    for choice in [ScanPolicy::First, ScanPolicy::GlobalQueue, ScanPolicy::LocalQueue, ScanPolicy::Random] {
        let choices = StateOptions { choice: Some(choice), ..StateOptions::default() };
        let explicit = state(choices, Engine::Explicit).into_state().unwrap();
        let symbolic = Engine::Symbolic { cfg: Config::default(), options: Options::default() };
        let symbolic = state(choices, symbolic).into_symbolic().unwrap();
        let what = choice.name();
        assert_eq!(without_command(&symbolic.files), without_command(&explicit.files), "--choice {what}");
        // The choice is made: the rungs fill `enabled`, and the program is not the fixed-order one.
        let st = &symbolic.files[0].1;
        assert!(st.contains("enabled[0] :="), "--choice {what}: {st}");
        assert!(st.contains(&format!("--choice {what}")), "--choice {what}: {st}");
        assert_ne!(without_command(&symbolic.files), without_command(&fixed_order), "--choice {what}");
    }
}

#[test]
fn the_interlock_gives_the_explicit_rungs() {
    same_rungs(&interlock(5, &scratch("interlock-5")));
}

#[test]
fn the_cli_writes_the_program_from_guards() {
    let manifest = interlock(12, &scratch("interlock-12"));
    let out = scratch("interlock-12-plc");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_codegen"))
        .args(["plc", "--encoding", "state", "--engine", "symbolic", "--json", "-o"])
        .arg(&out)
        .arg(&manifest)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(stderr.contains("engine: the guards were read off the symbolic supervisor's BDDs"), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(json["engine"], "symbolic");
    assert_eq!(json["rungs"].as_array().unwrap().len(), 24);
    // go1: station 1 idle and station 2 idle — one product.
    assert_eq!(json["rungs"][0]["event"], "go1");
    assert_eq!(json["rungs"][0]["products"], 1);
    let st = std::fs::read_to_string(out.join("interlock_12.st")).unwrap();
    assert!(st.contains("--engine symbolic"), "{st}");
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("symbolic_guards").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_large_interlock_has_its_exact_reachable_count_and_local_guards() {
    // 30 stations: a plant state is idle or one of three busy states per station, no two neighbours
    // busy — a(k) = a(k−1) + 3·a(k−2), a(0) = 1, a(1) = 4 — about 10¹¹ states, beyond listing.
    let n = 30;
    let inst = generate("interlock", n).unwrap();
    let g = Guards::compute(&inst.plants, &inst.specs, &Config::default(), &Options::default()).unwrap();
    let (mut a, mut b) = (BigUint::from(1u8), BigUint::from(4u8));
    for _ in 1..n {
        (a, b) = (b.clone(), b + 3u8 * a);
    }
    assert_eq!(g.count(&g.reachable), b);
    assert_eq!(g.guards.len(), 2 * n);
    // go_i is allowed exactly at the states where station i is idle and its neighbours are not busy.
    let mut x = vec![0u32; n];
    assert!(g
        .guards
        .iter()
        .filter(|guard| guard.event.starts_with("go"))
        .all(|guard| g.holds(&guard.allowed, &x)));
    x[9] = 2;
    let allowed = |event: &str, x: &[u32]| {
        let guard = g.guards.iter().find(|g| g.event == event).unwrap();
        g.holds(&guard.allowed, x)
    };
    assert!(!allowed("go9", &x) && !allowed("go11", &x) && !allowed("go10", &x) && allowed("go12", &x));
    assert!(allowed("ret10", &x) && !allowed("ret9", &x));
    assert!(g.guards.iter().all(|g| g.memory.is_false()));
}
