//! `codegen pack` and `codegen check` end to end: figures, JSON fields and exit statuses.

use std::path::Path;
use std::process::{Command, Output};

fn codegen(args: &[String]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel).display().to_string()
}

fn cell_files() -> Vec<String> {
    let mut args = vec!["pack".to_owned(), "--plant".to_owned()];
    args.extend(["G1", "G2", "G3", "G4"].iter().map(|g| repo(&format!("examples/cell/plants/{g}.xmd"))));
    args.push("--sup".to_owned());
    args.extend(
        ["S1", "S2_6", "S3", "S4", "S5", "S7"]
            .iter()
            .map(|s| repo(&format!("examples/cell/published/{s}.xmd"))),
    );
    args
}

#[test]
fn pack_json_carries_the_papers_columns_and_every_layout() {
    let mut args = cell_files();
    args.push("--json".to_owned());
    let out = codegen(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let paper = &json["paper"];
    assert_eq!((paper["matrix"].as_u64(), paper["chained_list"].as_u64()), (Some(54_312), Some(3_974)));
    assert_eq!(paper["memory_safe"], 2347);
    let layouts = json["layouts"].as_array().unwrap();
    let names: Vec<_> = layouts.iter().map(|l| l["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["memory-safe", "offset", "ranked", "indexed", "compact"]);
    // Blocks add up to the total with the side tables; ten automata listed.
    for l in layouts {
        let blocks: u64 =
            l["per_automaton"].as_array().unwrap().iter().map(|a| a["bytes"].as_u64().unwrap()).sum();
        let side: u64 =
            l["side_tables"].as_array().unwrap().iter().map(|t| t["bytes"].as_u64().unwrap()).sum();
        assert_eq!(blocks + side, l["bytes"].as_u64().unwrap());
        assert_eq!(l["per_automaton"].as_array().unwrap().len(), 10);
    }
    assert!(layouts[4]["supervisor_bytes"].as_u64().unwrap() <= 2347 / 2);
    // The Cortex-M0+'s layout: a target per event of the alphabet, word masks, a place per event and
    // automaton.
    assert_eq!(layouts[3]["blocks"], 4225);
    // The runtime's layout: under two thirds of the offset layout's bytes, all included.
    assert_eq!(layouts[2]["blocks"], 1028);
    assert!(layouts[2]["bytes"].as_u64().unwrap() * 3 < layouts[1]["bytes"].as_u64().unwrap() * 2);
    assert!(json["floor_bytes"].as_u64().unwrap() > 0);
}

#[test]
fn pack_text_shows_2347_and_refuses_unknown_layouts() {
    let out = codegen(&cell_files());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("controllability vector 23 = 2347 bytes"), "{text}");
    let mut args = cell_files();
    args.extend(["--layout".to_owned(), "dense".to_owned()]);
    assert_eq!(codegen(&args).status.code(), Some(2));
}

#[test]
fn check_finds_the_seed_avalanche_and_exits_1() {
    let out = codegen(&[
        "check".into(),
        repo("codegen/tests/data/TEST.ADS"),
        "--check".into(),
        "avalanche".into(),
        "--json".into(),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let events: Vec<_> =
        json["scopes"][0]["findings"].as_array().unwrap().iter().map(|f| f["events"][0].clone()).collect();
    assert_eq!(events, ["1", "2", "3"]);
    assert_eq!(json["failed"], true);
}

#[test]
fn check_livelock_reports_choice_at_1_and_3_with_traces() {
    let livelock =
        || vec!["check".into(), repo("examples/livelock/livelock.xmd"), "--check".into(), "choice".into()];
    let out = codegen(&livelock());
    assert_eq!(out.status.code(), Some(1));
    // By default: the group (both findings are one-order choices, at two states) and its nearest witness.
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains(
            "  answered at run time:\n    choice one-order: 2 at 2 state(s), 1 event set(s): a/b 2\n"
        ),
        "{text}"
    );
    assert!(text.contains("      e.g. at 1 (trace: ε): a·b reaches 1, b·a is undefined\n"), "{text}");
    // --all lists every finding, as the report did before it grouped them.
    let text = String::from_utf8(codegen(&[livelock(), vec!["--all".into()]].concat()).stdout).unwrap();
    assert!(text.contains("choice at state 1 on a, b: a·b reaches 1, b·a is undefined (trace: ε)"), "{text}");
    assert!(text.contains("choice at state 3 on a, b: a·b is undefined, b·a reaches 3 (trace: a)"), "{text}");
    // A check that finds nothing exits 0.
    let quiet = codegen(&[
        "check".into(),
        repo("examples/livelock/livelock.xmd"),
        "--check".into(),
        "simultaneity".into(),
    ]);
    assert_eq!(quiet.status.code(), Some(0));
}

#[test]
fn check_cell_closed_loop_and_local_scopes() {
    let mut args = vec!["check".to_owned()];
    args.extend(["G1", "G2", "G3", "G4"].iter().map(|g| repo(&format!("examples/cell/plants/{g}.xmd"))));
    args.push("--sup".into());
    args.extend(
        ["S1", "S2_6", "S3", "S4", "S5", "S7"]
            .iter()
            .map(|s| repo(&format!("examples/cell/published/{s}.xmd"))),
    );
    args.push("--json".into());
    let json: serde_json::Value = serde_json::from_slice(&codegen(&args).stdout).unwrap();
    let scopes = json["scopes"].as_array().unwrap();
    assert_eq!(scopes.len(), 7);
    // The closed loop is the monolithic supervisor's size: 3420 states, 11 808 transitions.
    assert_eq!((scopes[0]["states"].as_u64(), scopes[0]["transitions"].as_u64()), (Some(3420), Some(11_808)));
    assert_eq!(scopes[1]["name"], "S1 with local plant G1, G2");
    let avalanche =
        scopes[0]["findings"].as_array().unwrap().iter().filter(|f| f["problem"] == "avalanche").count();
    assert_eq!(avalanche, 0);
}

#[test]
fn pack_manifest_synthesises_and_adds_the_modular_and_monolithic_rows() {
    let out = codegen(&["pack".into(), repo("examples/cell/cell.toml"), "--json".into()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["paper"]["memory_safe"], 2347);
    let rows: Vec<_> = json["comparisons"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["approach"].as_str().unwrap().to_owned(),
                c["states"].as_u64().unwrap(),
                c["memory_safe"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        rows,
        [
            ("local modular".into(), 233, 2347),
            ("modular".into(), 1072, 20_253),
            ("monolithic".into(), 3420, 38_867)
        ]
    );
}

#[test]
fn check_manifest_livelock_and_cell_summary() {
    let out = codegen(&[
        "check".into(),
        repo("examples/livelock/livelock.toml"),
        "--check".into(),
        "choice".into(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    // The cell has choice, inexact-synchronisation and simultaneity findings but no avalanche: by
    // default (`[check] fail_on = ["avalanche"]`) it passes.
    let out = codegen(&["check".into(), repo("examples/cell/cell.toml"), "--json".into()]);
    assert_eq!(out.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let closed = json["scopes"][0]["findings"].as_array().unwrap();
    let count = |p: &str, shape: Option<&str>| {
        closed.iter().filter(|f| f["problem"] == p && shape.is_none_or(|s| f["shape"] == s)).count()
    };
    // No avalanche; every simultaneity is between the exclusive part-type sensors s_c1, s_c2, s_c3.
    assert_eq!(count("avalanche", None), 0);
    assert_eq!(count("simultaneity", None), count("simultaneity", Some("exclusive")));
    assert!(closed
        .iter()
        .filter(|f| f["problem"] == "simultaneity")
        .all(|f| f["events"][0].as_str().unwrap().starts_with("s_c")));
    assert_eq!(
        (count("choice", None), count("inexact-synchronisation", None), count("simultaneity", None)),
        (217, 2624, 2280)
    );
    // Schema 3 added the groups and keeps every finding: the groups' counts add up to them, the
    // one-order races first, the exclusive part-type sensors last, as harmless.
    assert_eq!(json["schema"], 4);
    // Schema 4: each finding names the supervisors it involves. Every race of a command with a sensor
    // is a supervisor's (S1 keeps the conveyor off once a part is at the sensor; S5 holds the robot's
    // jobs to the part seen); the exclusive part-type sensors are the plant's alone.
    let involving =
        |s: &str| closed.iter().filter(|f| f["supervisors"].as_array().unwrap().contains(&s.into())).count();
    assert_eq!((involving("S1"), involving("S5")), (2280, 344));
    assert!(closed
        .iter()
        .filter(|f| f["problem"] == "simultaneity")
        .all(|f| f["supervisors"].as_array().unwrap().is_empty()));
    let e1 = closed
        .iter()
        .find(|f| f["problem"] == "inexact-synchronisation" && f["trace"].as_array().unwrap().is_empty())
        .unwrap();
    assert_eq!(
        (&e1["events"], &e1["supervisors"]),
        (&serde_json::json!(["e1_lig", "s_c1"]), &serde_json::json!(["S1"]))
    );
    let groups = json["scopes"][0]["groups"].as_array().unwrap();
    let summary: Vec<_> = groups
        .iter()
        .map(|g| {
            (
                g["problem"].as_str().unwrap(),
                g["shape"].as_str().unwrap(),
                g["concern"].as_str().unwrap(),
                g["findings"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        summary,
        [
            ("inexact-synchronisation", "one-order", "runtime", 2624),
            ("choice", "one-order", "runtime", 48),
            ("choice", "exclusive", "runtime", 169),
            ("simultaneity", "exclusive", "harmless", 2280)
        ]
    );
    assert_eq!(groups[3]["events"][0], serde_json::json!({"events": ["s_c1", "s_c2"], "findings": 760}));
    // The text says the same on one screen: every group with its count, each supervisor on a line.
    let out = codegen(&["check".into(), repo("examples/cell/cell.toml")]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.lines().count() <= 40, "{text}");
    assert!(text.contains("  5121 finding(s) in 4 group(s); none to act on first\n"), "{text}");
    assert!(text.contains("    simultaneity exclusive: 2280 at 760 state(s), 3 event set(s): s_c1/s_c2 760, s_c1/s_c3 760, s_c2/s_c3 760\n"), "{text}");
    assert!(text.contains("  S5 with local plant G2, G3 (30 states, 74 transitions): inexact-synchronisation one-order 7, choice exclusive 5, simultaneity exclusive 18\n"), "{text}");
    // The closed loop's findings by the supervisors they involve, and the plants' own.
    assert!(text.contains("closed-loop findings by the supervisors whose disablement or state they involve:\n  S1: inexact-synchronisation one-order 2280\n"), "{text}");
    assert!(text.contains("  S2_6: choice one-order 20, choice exclusive 2\n"), "{text}");
    assert!(
        text.contains(
            "  no supervisor (the plants alone): choice exclusive 167, simultaneity exclusive 2280\n"
        ),
        "{text}"
    );
}

/// The cell's model files without a manifest (issue 22: one project loader for every command): plants
/// given without a role and `--spec` synthesise the manifest's supervisors and the same rows.
#[test]
fn pack_model_files_with_specifications_synthesise_as_the_manifest_does() {
    let mut args = vec!["pack".to_owned()];
    args.extend((1..=4).map(|k| repo(&format!("examples/cell/plants/G{k}.xmd"))));
    for k in 1..=7 {
        args.extend(["--spec".to_owned(), repo(&format!("examples/cell/specs/E{k}.xmd"))]);
    }
    args.push("--json".into());
    let out = codegen(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["paper"]["memory_safe"], 2347, "the local modular supervisors, synthesised");
    let states: Vec<u64> =
        json["comparisons"].as_array().unwrap().iter().map(|c| c["states"].as_u64().unwrap()).collect();
    assert_eq!(states, [233, 1072, 3420]);
}
