//! A user's own model and a user's ordinary mistakes (issue 22), on a distribution station written for
//! these tests (`codegen/tests/data/station/`, its README says what it is): every mistake gets a message
//! naming its cause and a non-zero exit — 2 for bad input, 1 for a verdict.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn station(file: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/station").join(file).display().to_string()
}

/// A scratch folder for this test's files.
fn scratch(tag: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_station").join(tag);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A manifest in a scratch folder over the station's modules, with `extra` appended.
fn manifest(tag: &str, modules: &[&str], extra: &str) -> String {
    let list: Vec<String> = modules.iter().map(|m| format!("{:?}", station(m))).collect();
    let path = scratch(tag).join("m.toml");
    std::fs::write(&path, format!("name = \"m\"\nmodules = [{}]\n{extra}", list.join(", "))).unwrap();
    path.display().to_string()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", stderr(out)))
}

#[test]
fn a_specification_event_no_plant_has_is_refused_by_every_command_with_file_line_and_suggestion() {
    let (plants, typo) = (station("plants.wmod"), station("specs_typo.wmod"));
    let out_dir = scratch("typo").display().to_string();
    let tables = format!("{out_dir}/tables.rs");
    let project = manifest("typo", &["plants.wmod", "specs_typo.wmod"], "");
    let runs: Vec<Vec<&str>> = vec![
        vec!["synth", &plants, &typo],
        vec!["synth", "--plant", &plants, "--spec", &typo],
        vec!["check", &plants, &typo],
        vec!["pack", &project],
        vec!["emit", &project, "-o", &tables],
        vec!["plc", &project, "-o", &out_dir],
    ];
    for args in runs {
        let out = codegen(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        let err = stderr(&out);
        assert!(
            err.contains(&format!(
                "{typo}:8: event 's11' of specification 'E_grip_at_left' is in no plant (did you mean 'sl1'?)"
            )),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn every_problem_of_a_set_is_listed_and_a_declared_plantless_event_passes() {
    // Two ready supervisors, each with an event of its own: both named in one error.
    let dir = scratch("plantless");
    let sup = |name: &str, event: &str| {
        let path = dir.join(format!("{name}.gen"));
        let text = format!(
            "<Generator>\n{name}\n<Alphabet>\nal +C+ {event}\n</Alphabet>\n<States>\nx\n</States>\n\
             <TransRel>\nx al x\nx {event} x\n</TransRel>\n<InitStates>\nx\n</InitStates>\n\
             <MarkedStates>\nx\n</MarkedStates>\n</Generator>\n"
        );
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    let (k1, k2) = (sup("K1", "tick"), sup("K2", "sr2"));
    let plants = station("plants.wmod");
    let out = codegen(&["check", "--plant", &plants, "--sup", &k1, &k2]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.contains("2 events of specifications or supervisors are in no plant"), "{err}");
    assert!(err.contains(&format!("{k1}:4: event 'tick' of supervisor 'K1' is in no plant\n")), "{err}");
    assert!(err.contains("event 'sr2' of supervisor 'K2' is in no plant (did you mean 'sr1'?)"), "{err}");
    // Declared plant-less in a manifest, the same supervisors are accepted.
    let text = format!(
        "name = \"m\"\nmodules = [{plants:?}]\nsupervisors = [{k1:?}, {k2:?}]\n\
         [events.tick]\nplantless = true\n[events.sr2]\nplantless = true\n"
    );
    let path = dir.join("declared.toml");
    std::fs::write(&path, text).unwrap();
    let out = codegen(&["check", &path.display().to_string(), "--json"]);
    assert_eq!(json(&out)["closed_loop"]["supervisors"], serde_json::json!(["K1", "K2"]));
}

#[test]
fn unknown_events_entries_are_all_named_with_their_line_and_a_suggestion() {
    let project = manifest(
        "events",
        &["plants.wmod", "specs.wmod"],
        "[events.ag2]\ncontrollable = true\n[events.sbb]\nplantless = true\n[events.sl1]\nplantless = true\n",
    );
    let out = codegen(&["synth", &project]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("3: events.ag2: no automaton of the set has this event (did you mean 'ag0' or 'ag1'?)")
    );
    assert!(
        err.contains("5: events.sbb: no automaton of the set has this event (did you mean 'sb'?)"),
        "{err}"
    );
    assert!(err.contains("7: events.sl1: declared plant-less, but plant 'G_arm' has it"), "{err}");
}

#[test]
fn two_modules_on_the_command_line_are_one_project_for_synth_and_check() {
    let (plants, specs) = (station("plants.wmod"), station("specs.wmod"));
    let totals = |out: &Output| {
        let j = json(out);
        (j["total_states"].as_u64().unwrap(), j["total_transitions"].as_u64().unwrap())
    };
    let modules = codegen(&["synth", "--json", &plants, &specs]);
    assert_eq!(totals(&modules), (45, 70));
    assert_eq!(totals(&codegen(&["synth", "--json", &station("station.toml")])), (45, 70));
    // check synthesises and checks the supervised loop: the monolithic supervisor's 28 states and 46
    // transitions, not the free plant's 36 and 108.
    let checked = json(&codegen(&["check", "--json", &plants, &specs]));
    let closed = &checked["closed_loop"];
    assert_eq!((closed["states"].as_u64(), closed["transitions"].as_u64()), (Some(28), Some(46)));
    assert_eq!(closed["plants"], serde_json::json!(["G_piston", "G_arm", "G_gripper"]));
    assert_eq!(closed["supervisors"].as_array().unwrap().len(), 3);
    assert_eq!(
        closed["legend"][1],
        serde_json::json!({"supervisor": "S_grip_at_left", "state": ["G_arm", "G_gripper", "E_grip_at_left"]})
    );
    let mono = json(&codegen(&["synth", "--json", "--monolithic", "--plant", &plants, "--spec", &specs]));
    assert_eq!((mono["total_states"].as_u64(), mono["total_transitions"].as_u64()), (Some(28), Some(46)));
    let free = json(&codegen(&["check", "--json", &plants]));
    assert_eq!(
        (free["closed_loop"]["states"].as_u64(), free["closed_loop"]["supervisors"].as_array().map(Vec::len)),
        (Some(36), Some(0))
    );
    // The text names the loop and gives the legend of its state tuples.
    let text = String::from_utf8(codegen(&["check", &plants, &specs]).stdout).unwrap();
    assert!(
        text.starts_with("checked: plants G_piston, G_arm, G_gripper with supervisors S_pick_after_push"),
        "{text}"
    );
    assert!(text.contains("  S_grip_at_left = (G_arm, G_gripper, E_grip_at_left)\n"), "{text}");
    assert!(text.contains("closed loop: 28 states, 46 transitions; a state is (G_piston, G_arm, G_gripper, S_pick_after_push, "), "{text}");
}

#[test]
fn no_supervisor_exists_is_a_verdict_of_synth_and_of_every_command_after_it() {
    let (plants, estop, project) = (station("plants.wmod"), station("estop.wmod"), station("estop.toml"));
    let out_dir = scratch("estop").display().to_string();
    let tables = format!("{out_dir}/tables.rs");
    let runs: Vec<Vec<&str>> = vec![
        vec!["synth", &plants, &estop],
        vec!["synth", "--monolithic", &project],
        vec!["synth", "--monolithic", "--engine", "symbolic", &project],
        vec!["check", &project],
        vec!["pack", &project],
        vec!["emit", &project, "-o", &tables],
        vec!["plc", &project, "-o", &out_dir],
    ];
    for args in runs {
        let out = codegen(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        let err = stderr(&out);
        // Local modular: against its local plant; monolithic: against all of them.
        let plant =
            if args.contains(&"--monolithic") { "G_piston, G_arm, G_gripper, G_estop" } else { "G_estop" };
        let head = format!("no supervisor exists for specification E_NoEStop (plant {plant})");
        // (after the lines that say which synthesis engine ran, for `synth --monolithic`)
        assert!(err.lines().any(|line| line.starts_with(&head)), "{args:?}: {err}");
        assert!(err.contains("  shortest trace: estop\n"), "{err}");
        if args.contains(&"--monolithic") {
            continue;
        }
        assert!(
            err.contains("at state (armed,running) of (G_estop, E_NoEStop) the plant can generate 'estop'"),
            "{err}"
        );
    }
}

#[test]
fn inspect_shows_the_alphabet_that_finds_the_typo() {
    let out = codegen(&["inspect", "--json", &station("specs_typo.wmod")]);
    let grip = &json(&out)[1];
    assert_eq!(grip["name"], "E_grip_at_left");
    assert_eq!(
        grip["alphabet"],
        serde_json::json!([
            {"name": "s11", "controllable": false},
            {"name": "ag1", "controllable": true},
            {"name": "ar", "controllable": true}
        ])
    );
    let text = String::from_utf8(codegen(&["inspect", &station("specs_typo.wmod")]).stdout).unwrap();
    assert!(text.contains("E_grip_at_left (spec): 2 states, 3 transitions, 3 events (2 controllable), 1 marked, initial 'away'\n  controllable: ag1, ar\n  uncontrollable: s11\n"), "{text}");
}

#[test]
fn a_project_chooses_which_findings_fail_check() {
    // The station has choice findings and no avalanche: it passes by default, fails on choice.
    let default = codegen(&["check", &station("station.toml"), "--json"]);
    assert_eq!(default.status.code(), Some(0), "{}", stderr(&default));
    let j = json(&default);
    assert_eq!(j["fail_on"], serde_json::json!(["avalanche"]));
    // (in the local scopes of S_grip_at_left and of the merged supervisor)
    let scopes = j["scopes"].as_array().unwrap();
    let choices =
        scopes.iter().flat_map(|s| s["findings"].as_array().unwrap()).filter(|f| f["problem"] == "choice");
    assert_eq!(choices.count(), 2);
    let strict = manifest(
        "fail_on",
        &["plants.wmod", "specs.wmod"],
        "[check]\nfail_on = [\"avalanche\", \"choice\"]\n",
    );
    let out = codegen(&["check", &strict]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).ends_with("failed (failing kinds: avalanche, choice)\n"));
    let typo = manifest("fail_on_typo", &["plants.wmod", "specs.wmod"], "[check]\nfail_on = [\"choise\"]\n");
    let out = codegen(&["check", &typo]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("check.fail_on: unknown check 'choise' (did you mean 'choice'?)"),
        "{}",
        stderr(&out)
    );
}
