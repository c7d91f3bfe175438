//! Issue 35: where a map or a conversion meets the model, every mistake of the trial gets a message
//! naming its cause and a non-zero exit — one test per mistake — and Nadzoru2's files go through
//! `synth`, `emit` and `run`. The model is the press station of `codegen/tests/data/press/` (its README
//! says what it is), written for these tests; each test writes its mistake into a copy.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// A fresh copy of the press station in a scratch folder of this test; the manifest's path.
fn press(tag: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_maps").join(tag);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/press");
    for entry in std::fs::read_dir(&data).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
    }
    dir.join("press.toml")
}

/// The press station with `edit` applied to its manifest (each `(from, to)` replaced once).
fn mistake(tag: &str, edits: &[(&str, &str)]) -> PathBuf {
    let path = press(tag);
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    std::fs::write(&path, text).unwrap();
    path
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The line of `manifest` holding `needle`, after the line `after` (1-based).
fn line_of(manifest: &Path, after: &str, needle: &str) -> usize {
    let text = std::fs::read_to_string(manifest).unwrap();
    let start = text.lines().position(|l| l.contains(after)).unwrap();
    start + text.lines().skip(start).position(|l| l.contains(needle)).unwrap() + 1
}

// See: issue 35, mistake 1.
#[test]
fn two_input_events_on_one_pico_pin_are_refused_by_emit_new_and_run() {
    let m = mistake("pin-twice", &[("pin = 3\n", "pin = 2\n")]);
    let dir = m.parent().unwrap();
    let line = line_of(&m, "event = \"pressed\"", "edge");
    let expected = format!(
        "{line}: board.inputs[1].edge: the rising edge of pin 2 would make both 'fed' (board.inputs[0]) and 'pressed'"
    );
    let project = dir.join("project");
    let tables = dir.join("tables.rs");
    for args in [
        vec!["emit", s(&m), "-o", s(&tables)],
        vec!["new", s(&project), "--board", "pico", "--manifest", s(&m)],
        vec!["run", s(&m), "--target", "rp2040", "--events", "100"],
        vec!["synth", s(&m)],
    ] {
        let out = codegen(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(&expected), "{args:?}: {}", stderr(&out));
    }
    assert!(!tables.exists() && !project.exists(), "nothing written");
    // One event per edge of one pin is fine: fed rising, pressed falling.
    let fine = mistake("pin-edges", &[("pin = 3\nedge = \"rising\"", "pin = 2\nedge = \"falling\"")]);
    let out = codegen(&["emit", s(&fine), "-o", s(&fine.with_file_name("t.rs"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

// See: issue 35, mistake 2.
#[test]
fn plc_addresses_are_read_by_the_standards_grammar_and_every_mistake_is_named_at_once() {
    let m = mistake(
        "addresses",
        &[
            ("address = \"%IX0.0\"", "address = \"garbage\""),
            ("address = \"%IX0.1\"", "address = \"%IX0.9\""),
            ("address = \"%IX0.2\"", "address = \"QX0.0\""),
            ("address = \"%QX0.0\"", "address = \"%QW0\""),
            ("address = \"%QX0.1\"", "address = \"%IX5.0\""),
        ],
    );
    let out = codegen(&["plc", s(&m), "-o", s(&m.with_file_name("plc"))]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("press.toml: 5 problems where the maps meet the model:"), "{err}");
    for want in [
        "plc.inputs[0].address: 'garbage' is no located address: it does not start with '%'",
        "plc.inputs[1].address: '%IX0.9': bit 9 of a byte; a byte has bits 0 to 7",
        "plc.inputs[2].address: 'QX0.0' is no located address: it does not start with '%': did you mean '%QX0.0'?",
        "plc.outputs[0].address: '%QW0' is a word (16 bits): a BOOL variable sits at a bit",
        "plc.outputs[1].address: '%IX5.0' is a physical input, and this is an output: its address is %QX (or %MX)",
    ] {
        assert!(err.contains(want), "{want}: {err}");
    }
    let line = line_of(&m, "garbage", "garbage");
    assert!(err.contains(&format!("  {line}: plc.inputs[0].address")), "lines named: {err}");
    assert!(!m.with_file_name("plc").exists(), "nothing written");
}

// See: issue 35, mistake 2 ("both bound to %IX0.0" was an internal error).
#[test]
fn two_entries_on_one_address_or_an_input_address_on_an_output_name_the_entries() {
    let m = mistake(
        "same-address",
        &[("address = \"%IX0.1\"", "address = \"%IX0.0\""), ("address = \"%QX0.2\"", "address = \"%IX0.2\"")],
    );
    let out = codegen(&["plc", s(&m), "-o", s(&m.with_file_name("plc"))]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(!err.contains("internal error"), "{err}");
    assert!(
        err.contains("plc.inputs[1].address: %IX0.0 is already the address of 'part_fed' (plc.inputs[0]): one address, one variable"),
        "{err}"
    );
    assert!(
        err.contains("plc.outputs[2].address: '%IX0.2' is a physical input, and this is an output"),
        "{err}"
    );
}

// See: issue 35, mistake 3.
#[test]
fn convert_never_invents_controllability_or_a_role() {
    let m = press("convert");
    let dir = m.parent().unwrap();
    let spec = dir.join("E_feed_press.gen");
    for (out_file, want) in [
        ("E.ADS", "E.ADS: TCT .ADS says every event's controllability, and 'E_feed_press' leaves unsaid its events' controllability"),
        ("E.xmd", "IDES3 .xmd says every event's controllability"),
        ("E.xml", "Nadzoru2 .xml says every event's controllability"),
        ("E.wmod", "'E_feed_press' leaves unsaid its role (plant, specification or supervisor) and its events' controllability: give the role with --kind plant|spec|supervisor, and controllability with --plant FILE…"),
    ] {
        let out = codegen(&["convert", s(&spec), s(&dir.join(out_file))]);
        assert_eq!(out.status.code(), Some(2), "{out_file}: {}", stderr(&out));
        assert!(stderr(&out).contains(want), "{out_file}: {}", stderr(&out));
        assert!(!dir.join(out_file).exists());
    }
    // Taken from the plants: feed and press controllable (odd TCT labels), fed not.
    let ads = dir.join("E.ADS");
    let plants = [dir.join("G_feed.xml"), dir.join("G_press.xml")];
    let out = codegen(&["convert", s(&spec), s(&ads), "--plant", s(&plants[0]), s(&plants[1])]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let back = codegen(&["inspect", s(&ads), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&back.stdout).unwrap();
    let said: Vec<(String, bool)> = json[0]["alphabet"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| (e["name"].as_str().unwrap().to_owned(), e["controllable"].as_bool().unwrap()))
        .collect();
    assert_eq!(said, [("feed".into(), true), ("fed".into(), false), ("press".into(), true)]);
    // A plant that lacks an event: said for the rest by --assume.
    let out = codegen(&["convert", s(&spec), s(&ads), "--plant", s(&plants[0])]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("event 'press'"), "{}", stderr(&out));
    let wmod = dir.join("E.wmod");
    let out = codegen(&["convert", s(&spec), s(&wmod), "--kind", "spec", "--assume", "uncontrollable"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = std::fs::read_to_string(&wmod).unwrap();
    assert!(text.contains("Kind=\"SPEC\"") && !text.contains("Kind=\"PLANT\""), "{text}");
    // inspect and dot show unsaid as unsaid.
    let out = codegen(&["inspect", s(&spec)]);
    assert!(stdout(&out).contains("3 events (controllability unsaid)"), "{}", stdout(&out));
    assert!(stdout(&out)
        .contains("controllability unsaid (taken from the plants it is used with): feed, fed, press"));
    let json: serde_json::Value =
        serde_json::from_slice(&codegen(&["inspect", s(&spec), "--json"]).stdout).unwrap();
    assert!(json[0]["controllable"].is_null() && json[0]["alphabet"][0]["controllable"].is_null(), "{json}");
    let dot = stdout(&codegen(&["dot", s(&spec)]));
    assert!(dot.contains("(controllability unsaid)") && dot.contains("style=dotted"), "{dot}");
    assert!(!dot.contains("style=dashed"), "{dot}");
}

// See: issue 35, mistake 5.
#[test]
fn a_specification_listed_twice_is_refused_naming_both_entries() {
    let m = mistake(
        "spec-twice",
        &[(
            "specs = [\"E_feed_press.gen\", \"E_press_eject.gen\"]",
            "specs = [\"E_feed_press.gen\", \"E_feed_press.gen\"]",
        )],
    );
    let out = codegen(&["synth", s(&m), "-o", s(&m.with_file_name("out"))]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("specs[1] (E_feed_press.gen): a second automaton called 'E_feed_press' (the first: specs[0] (E_feed_press.gen))"),
        "{}",
        stderr(&out)
    );
    let dir = m.parent().unwrap();
    let spec = dir.join("E_feed_press.gen");
    let out = codegen(&[
        "synth",
        "--plant",
        s(&dir.join("G_feed.xml")),
        s(&dir.join("G_press.xml")),
        "--spec",
        s(&spec),
        s(&spec),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("automaton 'E_feed_press' a second time (the file is given twice?)"),
        "{}",
        stderr(&out)
    );
}

// See: issue 35, mistake 6 (an empty plant blamed a specification; an empty component printed "(plant )").
#[test]
fn an_empty_automaton_is_named_as_empty() {
    let m = press("empty");
    let dir = m.parent().unwrap();
    std::fs::write(
        dir.join("G_eject.xml"),
        "<?xml version=\"1.0\"?>\n<model version=\"0.0\" type=\"FSA\" id=\"x\">\n<data>\n</data>\n</model>\n",
    )
    .unwrap();
    let out = codegen(&["synth", s(&m)]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("plants[2] (G_eject.xml): plant 'G_eject' is empty (no states)"), "{err}");
    assert!(!err.contains("no supervisor exists"), "{err}");
    let module = dir.join("m.wmod");
    std::fs::write(
        &module,
        "<Module Name=\"m\"><EventDeclList><EventDecl Kind=\"CONTROLLABLE\" Name=\"a\"/></EventDeclList><ComponentList>\
         <SimpleComponent Kind=\"PLANT\" Name=\"G\"><Graph><NodeList><SimpleNode Initial=\"true\" Name=\"s\"/></NodeList>\
         <EdgeList><Edge Source=\"s\" Target=\"s\"><LabelBlock><SimpleIdentifier Name=\"a\"/></LabelBlock></Edge></EdgeList></Graph></SimpleComponent>\
         <SimpleComponent Kind=\"SPEC\" Name=\"Z4\"><Graph/></SimpleComponent></ComponentList></Module>",
    )
    .unwrap();
    let out = codegen(&["synth", s(&module)]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("specification 'Z4' is empty (no states)"), "{}", stderr(&out));
    assert!(!stderr(&out).contains("(plant )") && !stderr(&out).contains("modules[0]"), "{}", stderr(&out));
    let unnamed = std::fs::read_to_string(&module).unwrap().replace("Name=\"Z4\"", "Name=\"\"");
    std::fs::write(&module, unnamed).unwrap();
    let out = codegen(&["inspect", s(&module)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("<SimpleComponent Name=\"\"> has an empty name"), "{}", stderr(&out));
}

// See: issue 35, mistake 6 (a module on the command line was called `modules[0]`).
#[test]
fn a_module_given_alone_is_named_by_its_file() {
    let dir = press("module").parent().unwrap().to_path_buf();
    let module = dir.join("bad.wmod");
    std::fs::write(&module, "<Module Name=\"m\">\n<ComponentList>\n<Broken/>\n</ComponentList>\n</Module>\n")
        .unwrap();
    let out = codegen(&["synth", s(&module)]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.contains("bad.wmod: line 3:") && !err.contains("modules[0]"), "{err}");
}

// See: issue 35, mistake 6 (a libFAUDES XML generator got "unexpected <Event> in <Alphabet>").
#[test]
fn libfaudes_xml_generators_are_read() {
    let dir = press("faudes-xml").parent().unwrap().to_path_buf();
    let out = codegen(&["inspect", s(&dir.join("E_press_eject.gen"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("E_press_eject (unknown): 2 states, 3 transitions, 3 events (controllability unsaid), 1 marked, initial 'free'"), "{}", stdout(&out));
}

// See: issue 35, mistake 6 (`board: action 'pulse' with pulse_ms None`).
#[test]
fn a_pulse_without_its_length_names_the_key() {
    let m = mistake("pulse", &[("pulse_ms = 50\n", "")]);
    let out = codegen(&["emit", s(&m), "-o", s(&m.with_file_name("t.rs"))]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("board.outputs[0].action: \"pulse\" needs pulse_ms, the pulse's length in ms (> 0)"),
        "{err}"
    );
    assert!(!err.contains("None"), "{err}");
}

// See: issue 35, mistake 6 (`--no-merge` said "conflicting" and nothing else).
#[test]
fn a_conflict_without_merging_names_the_supervisors_and_a_blocking_trace() {
    let manifest = repo("examples/cell/cell.toml");
    let out = codegen(&["synth", s(&manifest), "--no-merge"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("conflicting\n  S2 and S6 block together: after "), "{text}");
    assert!(text.contains("from which no marked state can be reached"), "{text}");
    let json: serde_json::Value =
        serde_json::from_slice(&codegen(&["synth", s(&manifest), "--no-merge", "--json"]).stdout).unwrap();
    assert_eq!(json["conflict"]["supervisors"], serde_json::json!(["S2", "S6"]));
    assert!(!json["conflict"]["trace"].as_array().unwrap().is_empty());
}

// See: issue 35, mistake 6 (`plc` without `[plc] policy` failed though `--help` promises a default), and
// issue 36 (the default is `random`, the scan-cycle form of the runtime's random queues: a fixed rule
// kept the EFA buffer out of its marked state).
#[test]
fn plc_without_a_policy_takes_random() {
    let m = mistake("no-policy", &[("policy = \"first\"\n", "")]);
    let dir = m.with_file_name("plc");
    let out = codegen(&["plc", s(&m), "-o", s(&dir)]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let st = std::fs::read_to_string(dir.join("press.st")).unwrap();
    assert!(st.contains("policy=random"), "the header names the policy it took");
}

// See: issue 35, mistake 6 (with `[net]`, `plc` demanded a variable for every signal).
#[test]
fn with_a_net_only_the_signals_it_reads_need_a_variable() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_maps").join("net");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let source = repo("examples/station-rtpn");
    let text = std::fs::read_to_string(source.join("net1.toml")).unwrap();
    let text = text
        .replace("\"plants/", &format!("\"{}/plants/", source.display()))
        .replace("\"specs/", &format!("\"{}/specs/", source.display()))
        .replace("pnml = \"net1.pnml\"", &format!("pnml = {:?}", source.join("net1.pnml")))
        .replace("t6 = \"sl AND sb\"", "t6 = \"sl\"");
    // No condition reads sb now: its variable goes.
    let sb = "[[plc.inputs]]\nevent = \"sb1\"\nvariable = \"sb\"\nedge = \"rising\"\naddress = \"%IX0.0\"\n\n\
              [[plc.inputs]]\nevent = \"sb0\"\nvariable = \"sb\"\nedge = \"falling\"\naddress = \"%IX0.0\"\n\n";
    assert!(text.contains(sb));
    let m = dir.join("net1.toml");
    std::fs::write(&m, text.replace(sb, "")).unwrap();
    let out = codegen(&["plc", s(&m), "-o", s(&dir.join("plc"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // A sensor a condition reads still needs one.
    let sg = std::fs::read_to_string(&m)
        .unwrap()
        .replace("variable = \"sg\"", "variable = \"sg_x\"")
        .replace(
        "[[plc.inputs]]\nevent = \"sg0\"\nvariable = \"sg_x\"\nedge = \"falling\"\naddress = \"%IX0.4\"\n",
        "",
    );
    std::fs::write(
        &m,
        sg.replace(
            "[[plc.inputs]]\nevent = \"sg1\"\nvariable = \"sg_x\"\nedge = \"rising\"\naddress = \"%IX0.4\"\n",
            "",
        ),
    )
    .unwrap();
    let out = codegen(&["plc", s(&m), "-o", s(&dir.join("plc2"))]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("net: signal 'sg' has no variable in [plc]; it is a sensor"),
        "{}",
        stderr(&out)
    );
}

// See: issue 35, mistake 7 (the Pico map built for the Nucleo put inputs on PA13/PA14, the SWD pins).
#[test]
fn the_pico_map_for_the_nucleo_is_refused_naming_the_reserved_pins() {
    let m = mistake("nucleo", &[("pin = 2\n", "pin = 13\n"), ("pin = 3\n", "pin = 14\n")]);
    let project = m.with_file_name("project");
    let out = codegen(&["new", s(&project), "--board", "nucleo-f401re", "--manifest", s(&m)]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    for want in [
        "board.name: the map is written for the pico and the project is built for the nucleo-f401re",
        "board.inputs[0].pin: pin 13 (PA13) of the nucleo-f401re is not free for an input: SWD (PA13 SWDIO, PA14 SWCLK)",
        "board.inputs[1].pin: pin 14 (PA14) of the nucleo-f401re is not free for an input",
        "board.outputs[0].pin: pin 16 (PB0)",
    ] {
        if want.contains("PB0") {
            assert!(!err.contains(want), "PB0 is free: {err}");
        } else {
            assert!(err.contains(want), "{want}: {err}");
        }
    }
    assert!(!project.exists());
    // The same map named for the board it is written for is fine as far as pins go.
    let out = codegen(&["emit", s(&m), "-o", s(&m.with_file_name("t.rs"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // A pin the chip does not have.
    let absent = mistake("absent", &[("pin = 18\n", "pin = 30\n")]);
    let out = codegen(&["emit", s(&absent), "-o", s(&absent.with_file_name("t.rs"))]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("the pico has no pin 30 (GP30): the RP2040 has GPIO 0 to 29"),
        "{}",
        stderr(&out)
    );
}

// See: issue 35, item 8: a Nadzoru2 user brings their model.
#[test]
fn nadzoru2_files_go_through_synth_emit_and_run() {
    let m = press("nadzoru");
    let dir = m.parent().unwrap();
    let out = codegen(&["inspect", s(&dir.join("G_feed.xml"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains(
        "G_feed (unknown): 2 states, 2 transitions, 2 events (1 controllable), 1 marked, initial 'idle'"
    ));
    let sups = dir.join("sups");
    let out = codegen(&["synth", s(&m), "-o", s(&sups), "--format", "nadzoru2"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("total                                              12           16"),
        "{}",
        stdout(&out)
    );
    let written = std::fs::read_to_string(sups.join("S_feed_press.xml")).unwrap();
    assert!(written.contains("<model version=\"0.0\" type=\"FSA\" id=\"S_feed_press\">"), "{written}");
    assert!(written.contains("name=\"feed\" controllable=\"True\" observable=\"True\""), "{written}");
    // The supervisors written read back as ready supervisors of the same plants.
    let plants: Vec<String> =
        ["G_feed.xml", "G_press.xml", "G_eject.xml"].iter().map(|f| s(&dir.join(f)).to_owned()).collect();
    let mut args = vec!["check", "--plant"];
    args.extend(plants.iter().map(String::as_str));
    let sup_files = [sups.join("S_feed_press.xml"), sups.join("S_press_eject.xml")];
    args.push("--sup");
    args.extend(sup_files.iter().map(|p| s(p)));
    let out = codegen(&args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = codegen(&["convert", s(&dir.join("G_feed.xml")), s(&dir.join("copy.xml"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let tables = dir.join("tables.rs");
    let out = codegen(&["emit", s(&m), "-o", s(&tables)]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(std::fs::read_to_string(&tables).unwrap().contains("G_feed.xml"), "the header names the input");
    let out = codegen(&["run", s(&m), "--events", "300", "--json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((json["name"].as_str(), json["violations"].as_u64()), (Some("press"), Some(0)));
    assert!(json["events"].as_u64().unwrap() >= 300);
}

// See: issue 35, mistake 7 (a state-based scan-time estimate past the task's cycle went unremarked).
#[test]
fn a_state_based_scan_longer_than_the_cycle_is_a_finding() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_maps").join("scan");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let source = repo("examples/distribution");
    let text = std::fs::read_to_string(source.join("distribution-state.toml")).unwrap();
    let text = text
        .replace("\"plants/", &format!("\"{}/plants/", source.display()))
        .replace("\"specs/", &format!("\"{}/specs/", source.display()));
    let m = dir.join("d.toml");
    let run = |plc: &str| {
        std::fs::write(&m, format!("{text}\n[plc]\n{plc}\n")).unwrap();
        codegen(&["plc", s(&m), "--encoding", "state", "-o", s(&dir.join("plc"))])
    };
    let out = run("cycle_ms = 1\ninstruction_ns = 100000");
    assert_eq!(out.status.code(), Some(1), "a finding is a failed check: {}", stderr(&out));
    assert!(dir.join("plc").read_dir().is_ok_and(|mut d| d.next().is_some()), "the files are written");
    assert!(stdout(&out).contains("finding: the scan ("), "{}", stdout(&out));
    assert!(
        stdout(&out).contains("is longer than the task's cycle (1 ms, [plc] cycle_ms)"),
        "{}",
        stdout(&out)
    );
    let out = run("cycle_ms = 10");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(!stdout(&out).contains("finding: the scan"), "{}", stdout(&out));
}

// Found trying the press station as a user: a command with no output pin was emitted (exit 0), so the
// firmware would fire it and the plant never see it; `plc` refused the same gap.
#[test]
fn a_command_without_a_pin_is_refused_unless_internal() {
    let eject = "[[board.outputs]]\nevent = \"eject\"\npin = 18\naction = \"pulse\"\npulse_ms = 50\n";
    let m = mistake("unmapped", &[(eject, "")]);
    let out = codegen(&["emit", s(&m), "-o", s(&m.with_file_name("t.rs"))]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("board.outputs: command 'eject' drives no pin"), "{}", stderr(&out));
    let m = mistake(
        "internal",
        &[(eject, ""), ("name = \"pico\"\n", "name = \"pico\"\ninternal = [\"eject\"]\n")],
    );
    let out = codegen(&["emit", s(&m), "-o", s(&m.with_file_name("t.rs"))]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// `codegen bench`: the LED/button bench's `[board]`, written from the press station's events, takes the
/// place of the hand-written one and `emit` builds the pin tables from it (the maps pass finds nothing);
/// every event is on a pin of its own, buttons (falling edge, pull-up) then LEDs, debounced by 20 ms
/// timer sampling.
#[test]
fn the_bench_board_written_from_the_events_replaces_the_hand_written_one() {
    let m = press("bench");
    let bench = m.with_file_name("bench.toml");
    let out = codegen(&["bench", s(&m), "-o", s(&bench)]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let section = std::fs::read_to_string(&bench).unwrap();
    let text = std::fs::read_to_string(&m).unwrap();
    let (head, rest) = text.split_once("[board]\n").unwrap();
    let plc = &rest[rest.find("[plc]").unwrap()..];
    std::fs::write(&m, format!("{head}{section}\n{plc}")).unwrap();
    let tables = m.with_file_name("t.rs");
    let out = codegen(&["emit", s(&m), "-o", s(&tables)]);
    assert_eq!(out.status.code(), Some(0), "{}\n{section}", stderr(&out));
    let spec: toml::Value = toml::from_str(&section).unwrap();
    let (inputs, outputs) =
        (spec["board"]["inputs"].as_array().unwrap(), spec["board"]["outputs"].as_array().unwrap());
    assert_eq!((inputs.len(), outputs.len()), (3, 3), "{section}");
    let pins: Vec<i64> = inputs.iter().chain(outputs).map(|e| e["pin"].as_integer().unwrap()).collect();
    assert_eq!(pins, [0, 1, 2, 3, 4, 5]);
    assert!(section.contains("sampling = \"timer\"\nsample_period_us = 20000\n"), "{section}");
    // Twice the same bytes.
    let again = codegen(&["bench", s(&m)]);
    assert_eq!(stdout(&again), section);
}
