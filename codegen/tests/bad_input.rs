//! The bad-input corpus: every malformed file under `tests/bad_input/<format>/` makes `codegen inspect`
//! (`codegen verify` for a PNML net) exit 2 with one message naming the file and (where there is one) the
//! line, and never panic.

use std::path::Path;
use std::process::Command;

/// (file under tests/bad_input, the message after "error: <path>: ").
const CASES: &[(&str, &str)] = &[
    ("ads/empty.ADS", "line 1: no 'State size' section"),
    ("ads/huge_label.ADS", "line 10: event label '99999999999' is not a number from 0 to 4294967295"),
    ("ads/huge_size.ADS", "line 3: state size 3000000 exceeds TCT's limit of 2000000"),
    ("ads/marker_out_of_range.ADS", "line 5: state 5 is out of range: the state size is 3"),
    ("ads/negative_state.ADS", "line 12: state '-1' is not a number from 0 to 4294967295"),
    ("ads/no_state_size.ADS", "line 2: missing state size before this section"),
    ("ads/nondeterministic.ADS", "line 13: nondeterministic: state '0' has event '1' to both '1' and '2'"),
    ("ads/not_utf8.ADS", "line 1: not UTF-8 text"),
    ("ads/sections_out_of_order.ADS", "line 10: section 'Marker states:' out of order"),
    ("ads/truncated.ADS", "line 11: expected 'source label target', found '1 2'"),
    ("ads/wrong_count.ADS", "line 11: state 2 is out of range: the state size is 2"),
    ("gen/duplicate_state.gen", "line 9: duplicate state name 's1'"),
    ("gen/empty.gen", "line 1: empty file: expected <Generator>"),
    ("gen/huge_consecutive.gen", "line 9: range 3 to 4000000000 has more than 10000000 states"),
    ("gen/huge_number.gen", "line 14: number 999999999999999999999999 is too large"),
    ("gen/nondeterministic.gen", "line 15: nondeterministic: state 's1' has event 'a' to both 's2' and 's1'"),
    ("gen/not_utf8.gen", "line 14: not UTF-8 text"),
    ("gen/truncated.gen", "line 14: quoted name is never closed"),
    ("gen/two_initial.gen", "line 18: second initial state 's2' (the first is 's1'); only one is supported"),
    ("gen/unclosed_quote.gen", "line 18: quoted name is never closed"),
    ("gen/unknown_event.gen", "line 14: unknown event 'c'"),
    ("gen/unknown_index.gen", "line 14: state index 7 is not declared in <States>"),
    ("gen/unknown_state.gen", "line 14: unknown state 's9'"),
    ("gen/xml_entities.gen", "line 2: unsupported: a document type declaration with an internal subset (entities)"),
    ("gen/xml_unknown_state.gen", "line 11: transition refers to unknown state id 3 (x2)"),
    ("gen/xml_variant.gen", "automaton 'xml_variant' has no initial state"),
    ("nadzoru/no_controllable.xml", "line 6: <event> says nothing of 'controllable' (True or False)"),
    ("nadzoru/unnamed_event.xml", "line 7: event 1 has no name: an event is known by its name in every automaton of a set (Nadzoru2 leaves a new event unnamed): name it, or delete it and its transitions"),
    ("nadzoru/unobservable.xml", "line 6: unsupported: event 'start' is unobservable (observable=\"False\"): the supervisors this tool builds observe every event"),
    ("nadzoru/unknown_state.xml", "line 9: transition refers to unknown state '5' (target)"),
    ("wmod/duplicate_component.wmod", "line 25: second component 'M' (first on line 9)"),
    ("wmod/empty.wmod", "line 1: malformed XML: the document does not have a root node"),
    ("wmod/foreach.wmod", "line 9: unsupported: <ForeachComponent Name=\"i\"> (foreach blocks)"),
    (
        "wmod/guard.wmod",
        "line 18: unsupported: <SimpleIdentifier Name=\"y\">: 'y' is not a variable of this module \
         (constants, enumeration values and events in expressions are not supported)",
    ),
    (
        "wmod/mixed_kinds.wmod",
        "line 13: unsupported: spec 'S' assigns 'x', a variable of plant 'M': a specification may \
         read the plant's variables in its guards, not assign them",
    ),
    (
        "wmod/nondeterministic.wmod",
        "line 23: nondeterministic: state 'idle' has event 'go' to both 'busy' and 'idle'",
    ),
    ("wmod/not_utf8.wmod", "line 13: not UTF-8 text"),
    (
        "wmod/other_proposition.wmod",
        "line 13: unsupported: undeclared proposition ':forbidden' on node (only :accepting is supported)",
    ),
    ("wmod/parameter.wmod", "line 25: unsupported: <Instance> (parameters and module instances)"),
    ("wmod/truncated.wmod", "line 21: malformed XML: the root node was opened but never closed"),
    (
        "wmod/two_initial.wmod",
        "line 13: second initial state 'busy' (the first is 'idle'); only one is supported",
    ),
    ("wmod/unknown_event.wmod", "line 20: event 'stop' is not declared in <EventDeclList>"),
    ("wmod/unknown_node.wmod", "line 19: unknown state 'broken'"),
    (
        "wmod/two_initial_values.wmod",
        "line 11: unsupported: <VariableInitial>: the initial predicate of 'x' holds for several values; \
         exactly one is supported",
    ),
    (
        "wmod/unbounded.wmod",
        "line 10: unsupported: <SimpleIdentifier Name=\"N\">: the range of 'x' is unbounded or not constant",
    ),
    ("wmod/variable.wmod", "line 9: variable 'x' has no <VariableRange>"),
    ("xmd/dangling_event.xmd", "line 9: transition 2 refers to unknown event '9'"),
    ("xmd/dangling_state.xmd", "line 9: transition 2 refers to unknown state '7'"),
    ("xmd/duplicate_state_name.xmd", "line 5: duplicate state name 'idle'"),
    ("xmd/empty.xmd", "line 1: malformed XML: the document does not have a root node"),
    ("xmd/entity_bomb.xmd", "line 1: malformed XML: XML with DTD detected"),
    ("xmd/huge_id.xmd", "line 8: transition 1 refers to unknown state '184467440737095516161'"),
    ("xmd/no_initial.xmd", "automaton 'no_initial' has no initial state"),
    (
        "xmd/nondeterministic.xmd",
        "line 10: nondeterministic: state 'idle' has event 'start' to both 'busy' and 'idle'",
    ),
    ("xmd/not_utf8.xmd", "line 5: not UTF-8 text"),
    ("xmd/truncated.xmd", "line 7: malformed XML: unexpected end of stream"),
    (
        "xmd/two_initial.xmd",
        "line 5: second initial state 'busy' (the first is 'idle'); only one is supported",
    ),
    ("xmd/wrong_root.xmd", "line 2: expected a <model> root element, found <automaton>"),
];

/// (PNML file under tests/bad_input, the message after "error: <path>: ").
const PNML_CASES: &[(&str, &str)] = &[
    ("pnml/bad_marking.pnml", "line 5: initial marking 'one' is not a number from 0 to 1048576"),
    ("pnml/dangling_arc.pnml", "line 7: arc target 't9' is no place or transition"),
    ("pnml/duplicate_arc.pnml", "line 8: a second arc between 'p1' and 't1'"),
    ("pnml/duplicate_id.pnml", "line 7: duplicate id 't1' (first on line 6)"),
    ("pnml/empty.pnml", "line 1: malformed XML: the document does not have a root node"),
    ("pnml/entity_bomb.pnml", "line 1: malformed XML: XML with DTD detected"),
    ("pnml/label_without_text.pnml", "line 5: <initialMarking> without <text>"),
    ("pnml/inhibitor_to_place.pnml", "line 6: an inhibitor arc goes from a place to a transition"),
    ("pnml/no_id.pnml", "line 5: <place> without an id"),
    ("pnml/no_net.pnml", "line 2: no <net> in <pnml>"),
    ("pnml/not_utf8.pnml", "line 5: not UTF-8 text"),
    ("pnml/place_to_place.pnml", "line 8: an arc joins a place and a transition"),
    ("pnml/reference_place.pnml", "line 7: unsupported: <referencePlace id=\"r1\"> (reference nodes)"),
    ("pnml/reset_arc.pnml", "line 6: unsupported: <type value=\"reset\"> arcs"),
    (
        "pnml/symmetric_net.pnml",
        "line 3: unsupported: <net type=\"http://www.pnml.org/version-2009/grammar/symmetricnet\"> (only \
         place/transition nets)",
    ),
    (
        "pnml/token_classes.pnml",
        "line 4: unsupported: initial marking 'Red,1' (token classes other than Default)",
    ),
    ("pnml/truncated.pnml", "line 6: malformed XML: the root node was opened but never closed"),
    ("pnml/two_nets.pnml", "line 9: unsupported: a second <net> (the first is on line 3); one net per file"),
    ("pnml/wrong_root.pnml", "line 2: expected a <pnml> root element, found <net>"),
    ("pnml/zero_weight.pnml", "line 7: arc weight '0' is not a number from 1 to 1048576"),
];

fn corpus() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_input")
}

#[test]
fn every_bad_file_exits_2_with_its_message() {
    for (rel, msg) in CASES {
        let path = corpus().join(rel);
        let out = Command::new(env!("CARGO_BIN_EXE_codegen")).arg("inspect").arg(&path).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{rel}");
        assert!(out.stdout.is_empty(), "{rel}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!("error: {}: {msg}\n", path.display()),
            "{rel}"
        );
    }
}

#[test]
fn the_library_gives_the_same_message_with_the_line() {
    for (rel, msg) in CASES {
        let path = corpus().join(rel);
        let err = codegen::formats::read_path(&path).unwrap_err();
        assert_eq!(err.to_string(), format!("{}: {msg}", path.display()));
        let line = msg.strip_prefix("line ").and_then(|m| m.split(':').next()).map(|n| n.parse().unwrap());
        assert_eq!(err.line(), line, "{rel}");
        assert_eq!(err.file(), path);
    }
}

#[test]
fn every_file_of_the_corpus_has_a_case() {
    for format in std::fs::read_dir(corpus()).unwrap() {
        for file in std::fs::read_dir(format.unwrap().path()).unwrap() {
            let path = file.unwrap().path();
            let rel = path.strip_prefix(corpus()).unwrap().to_str().unwrap().to_owned();
            let known = CASES.iter().chain(PNML_CASES).any(|(r, _)| *r == rel);
            assert!(known, "{rel} has no expected message");
        }
    }
}

#[test]
fn every_bad_net_gives_its_message_with_the_line() {
    for (rel, msg) in PNML_CASES {
        let path = corpus().join(rel);
        let err = codegen::net::read_pnml(&path).unwrap_err();
        assert_eq!(err.to_string(), format!("{}: {msg}", path.display()), "{rel}");
        let line = msg.strip_prefix("line ").and_then(|m| m.split(':').next()).map(|n| n.parse().unwrap());
        assert_eq!(err.line(), line, "{rel}");
    }
}

#[test]
fn verify_exits_2_on_a_bad_net() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bad_input_pnml");
    std::fs::create_dir_all(&dir).unwrap();
    for (rel, msg) in PNML_CASES.iter().step_by(4) {
        let path = corpus().join(rel);
        let manifest = dir.join("m.toml");
        std::fs::write(&manifest, format!("name = \"m\"\n[net]\npnml = {:?}\n", path.display().to_string()))
            .unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_codegen")).arg("verify").arg(&manifest).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{rel}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!("error: {}: {msg}\n", path.display()),
            "{rel}"
        );
    }
}
