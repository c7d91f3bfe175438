//! The pass on small manifests over two machines: every mistake of issue 35's trial named with its key
//! and line, all at once.

use std::path::Path;

use super::*;
use crate::model::testing::machine;

/// Two machines: M1 (start1 controllable, done1 not) and M2.
fn models() -> ModelSet {
    ModelSet {
        plants: vec![machine("M1", "start1", "done1"), machine("M2", "start2", "done2")],
        specs: Vec::new(),
        supervisors: Vec::new(),
        sources: Vec::new(),
    }
}

fn problems(text: &str, board: Option<Board>) -> Vec<String> {
    let m = Manifest::parse(Path::new("m.toml"), &format!("name = \"m\"\n{text}")).unwrap();
    match check(&m, &models(), board) {
        Ok(()) => Vec::new(),
        Err(e) => e.problems.iter().map(Problem::to_string).collect(),
    }
}

const BOARD: &str = "[board]\nname = \"pico\"\n\
    [[board.inputs]]\nevent = \"done1\"\npin = 2\nedge = \"rising\"\n\
    [[board.inputs]]\nevent = \"done2\"\npin = 3\nedge = \"rising\"\n\
    [[board.outputs]]\nevent = \"start1\"\npin = 16\naction = \"set\"\n\
    [[board.outputs]]\nevent = \"start2\"\npin = 17\naction = \"clear\"\n";

/// The entry of BOARD that maps start2.
const START2: &str = "[[board.outputs]]\nevent = \"start2\"\npin = 17\naction = \"clear\"\n";

#[test]
fn every_command_drives_a_pin_or_is_internal() {
    let unmapped = BOARD.replace(START2, "");
    let p = problems(&unmapped, None);
    assert_eq!(p.len(), 1, "{p:#?}");
    assert!(
        p[0].ends_with(
            "board.outputs: command 'start2' drives no pin: the supervisors would fire it and the plant \
             never see it; map it in [[board.outputs]] or list it in [board] internal"
        ),
        "{p:#?}"
    );
    let internal = |names: &str| {
        unmapped.replace("name = \"pico\"\n", &format!("name = \"pico\"\ninternal = [{names}]\n"))
    };
    assert_eq!(problems(&internal("\"start2\""), None), Vec::<String>::new());
    let p = problems(&internal("\"start2\", \"start1\", \"done1\""), None);
    assert_eq!(p.len(), 2, "{p:#?}");
    assert!(p.iter().all(|x| x.starts_with("4: board.internal[")), "{p:#?}");
    assert!(
        p.iter().any(|x| x.contains("'start1' is listed in `internal` and drives a pin (board.outputs[0])")),
        "{p:#?}"
    );
    assert!(p.iter().any(|x| x.contains("'done1' is uncontrollable")), "{p:#?}");
}

#[test]
fn a_fitting_map_passes() {
    assert_eq!(problems(BOARD, None), Vec::<String>::new());
    assert_eq!(problems(BOARD, Some(Board::Pico)), Vec::<String>::new());
}

#[test]
fn two_events_on_one_pin_edge_are_refused_naming_both_entries() {
    let text = BOARD.replace("pin = 3", "pin = 2");
    assert_eq!(
        problems(&text, None),
        ["11: board.inputs[1].edge: the rising edge of pin 2 would make both 'done1' (board.inputs[0]) and \
          'done2': one edge, one event (a second sensor needs a pin of its own; one pin may carry one event \
          rising and another falling)"]
    );
    let falling =
        text.replacen("edge = \"rising\"\n[[board.outputs]]", "edge = \"falling\"\n[[board.outputs]]", 1);
    assert_eq!(problems(&falling, None), Vec::<String>::new(), "one event per edge of one pin");
}

#[test]
fn every_board_problem_is_listed_at_once() {
    let text = BOARD
        .replace("event = \"done2\"", "event = \"dne2\"")
        .replace("action = \"set\"", "action = \"pulse\"")
        .replace("pin = 16", "pin = 24");
    let p = problems(&text, None);
    assert_eq!(p.len(), 3, "{p:#?}");
    assert!(
        p[0].starts_with(
            "9: board.inputs[1].event: 'dne2' is not an event of the set (did you mean 'done2'?)"
        ),
        "{p:#?}"
    );
    assert!(
        p[1].starts_with("14: board.outputs[0].pin: pin 24 (GP24) of the pico is not free for an output"),
        "{p:#?}"
    );
    assert_eq!(p[2], "15: board.outputs[0].action: \"pulse\" needs pulse_ms, the pulse's length in ms (> 0)");
}

#[test]
fn the_pico_map_built_for_the_nucleo_names_the_swd_pins() {
    let text = BOARD.replace("pin = 2", "pin = 13").replace("pin = 3", "pin = 14");
    assert_eq!(problems(&text, None), Vec::<String>::new(), "GP13 and GP14 are free on the Pico");
    let p = problems(&text, Some(Board::NucleoF401re));
    assert_eq!(p.len(), 3, "{p:#?}");
    assert!(
        p[0].starts_with(
            "3: board.name: the map is written for the pico and the project is built for the nucleo-f401re"
        ),
        "{p:#?}"
    );
    assert!(
        p[1].starts_with(
            "6: board.inputs[0].pin: pin 13 (PA13) of the nucleo-f401re is not free for an input: SWD"
        ),
        "{p:#?}"
    );
    assert!(p[2].contains("pin 14 (PA14)"), "{p:#?}");
}

const PLC: &str = "[plc]\n\
    [[plc.inputs]]\nevent = \"done1\"\nvariable = \"d1\"\nedge = \"rising\"\naddress = \"%IX0.0\"\n\
    [[plc.inputs]]\nevent = \"done2\"\nvariable = \"d2\"\nedge = \"rising\"\naddress = \"%IX0.1\"\n\
    [[plc.outputs]]\nevent = \"start1\"\nvariable = \"s1\"\naction = \"set\"\naddress = \"%QX0.0\"\n";

#[test]
fn plc_addresses_follow_the_grammar_and_the_role() {
    assert_eq!(problems(PLC, None), Vec::<String>::new());
    for (from, to, why) in [
        ("%IX0.1", "garbage", "12: plc.inputs[1].address: 'garbage' is no located address"),
        ("%QX0.0", "QX0.0", "17: plc.outputs[0].address: 'QX0.0' is no located address: it does not start with '%': did you mean '%QX0.0'?"),
        ("%QX0.0", "%QW0", "17: plc.outputs[0].address: '%QW0' is a word (16 bits)"),
        ("%QX0.0", "%IX5.0", "17: plc.outputs[0].address: '%IX5.0' is a physical input, and this is an output: its address is %QX (or %MX)"),
        ("%IX0.1", "%IX0.9", "12: plc.inputs[1].address: '%IX0.9': bit 9 of a byte"),
        ("%IX0.1", "%IX0.0", "12: plc.inputs[1].address: %IX0.0 is already the address of 'd1' (plc.inputs[0]): one address, one variable"),
    ] {
        let p = problems(&PLC.replace(from, to), None);
        assert_eq!(p.len(), 1, "{to}: {p:#?}");
        assert!(p[0].starts_with(why), "{to}: {p:#?}");
    }
    let p = problems(&PLC.replace("variable = \"d2\"", "variable = \"s1\""), None);
    assert!(p.iter().any(|x| x.contains("'s1' is an input (plc.inputs[1]) and an output here")), "{p:#?}");
}

#[test]
fn state_vectors_meet_the_plants() {
    let text = "[state.components.M1]\ninputs = [{ name = \"X1\", address = \"%QX0.0\" }]\n\
        outputs = [{ name = \"Y1\", address = \"%QX0.1\", pin = 99 }]\n\
        states = { \"0\" = [\"!Y1\"], \"7\" = [\"Y1\"] }\ncommands = { start = [\"Y1\"] }\n";
    let p = problems(text, None);
    let expected = [
        "2: state.components: plant 'M2' has no state vector: add [state.components.M2]",
        "3: state.components.M1.inputs[0].address: '%QX0.0' is a physical output, and this is an input",
        "4: state.components.M1.outputs[0].pin: pin 99 is beyond GPIO 63",
        "5: state.components.M1.states: state '1' of M1 has no formula",
        "5: state.components.M1.states.7: M1 has no state '7'",
        "6: state.components.M1.commands: controllable event 'start1' of M1 has no command",
        "6: state.components.M1.commands.start: M1 has no event 'start' (did you mean 'start1'?)",
    ];
    assert_eq!(p.len(), expected.len(), "{p:#?}");
    for (got, want) in p.iter().zip(expected) {
        assert!(got.starts_with(want) || got.contains(want), "{got} / {want}");
    }
}
