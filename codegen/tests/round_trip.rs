//! Read → write → read gives the same automaton, for every format, on every model file we have and on
//! random automata.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use codegen::formats::{ads, gen, nadzoru, read_bytes, read_path, wmod, xmd};
use codegen::model::{Automaton, EventId, Kind, StateId};
use proptest::prelude::*;

/// Every model file of the repository, plus the shared models when they sit beside the repository.
fn model_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in [root.join("examples"), root.join("codegen/tests/data"), root.join("../shared/models")] {
        collect(&dir, &mut files);
    }
    files.sort();
    files
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, out);
        } else if matches!(
            path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref(),
            Some("xmd" | "xml" | "ads" | "gen" | "wmod")
        ) {
            out.push(path);
        }
    }
}

/// Modules that use Supremica's extended features; they must be refused by element, not read.
const REFUSED: [(&str, &str); 1] =
    [("mmarques_desmodel.wmod", "unsupported: <ConstantAliasList> (constants)")];

#[test]
fn every_model_file_reads_or_is_refused_by_element() {
    let files = model_files();
    assert!(files.len() >= 27, "found only {} model files", files.len());
    for file in &files {
        let name = file.file_name().unwrap().to_str().unwrap();
        match (read_path(file), REFUSED.iter().find(|(f, _)| *f == name)) {
            (Ok(automata), None) => {
                assert!(!automata.is_empty(), "{name}");
                for a in &automata {
                    assert_eq!(a.validate(), Ok(()), "{name}");
                    let mut sorted = a.clone();
                    sorted.canonicalize();
                    assert_eq!(&sorted, a, "{name}: transitions not canonical");
                }
            }
            (Err(e), Some((_, msg))) => assert!(e.to_string().ends_with(msg), "{e}"),
            (Ok(_), Some(_)) => panic!("{name} should be refused"),
            (Err(e), None) => panic!("{e}"),
        }
    }
}

/// `b` is `a` written and read back: same states (names and marking), initial state, alphabet and
/// transitions. `renamed` says the format renumbers states (TCT), giving the map from `a`'s states.
fn assert_same(a: &Automaton, b: &Automaton, renumber: Option<&dyn Fn(usize) -> usize>) {
    let map = |s: StateId| renumber.map_or(s.index(), |f| f(s.index()));
    assert_eq!(a.states.len(), b.states.len(), "{}", a.name);
    for (i, s) in a.states.iter().enumerate() {
        let t = &b.states[renumber.map_or(i, |f| f(i))];
        assert_eq!(s.marked, t.marked, "{}: state {}", a.name, s.name);
        if renumber.is_none() {
            assert_eq!(s.name, t.name);
        }
    }
    assert_eq!(a.initial.map(map), b.initial.map(|s| s.index()));
    let events =
        |x: &Automaton| x.events.iter().map(|e| (e.name.clone(), e.controllable)).collect::<BTreeSet<_>>();
    assert_eq!(events(a), events(b));
    let ev = |x: &Automaton, e: EventId| x.events[e.index()].name.clone();
    let ta: BTreeSet<_> =
        a.transitions.iter().map(|t| (map(t.source), ev(a, t.event), map(t.target))).collect();
    let tb: BTreeSet<_> =
        b.transitions.iter().map(|t| (t.source.index(), ev(b, t.event), t.target.index())).collect();
    assert_eq!(ta, tb, "{}", a.name);
}

/// TCT numbering as documented for [`ads::write`]: the initial state is 0, the others follow in order.
fn tct_number(a: &Automaton) -> impl Fn(usize) -> usize {
    let init = a.initial.map(|s| s.index());
    move |i| match init {
        Some(init) if i == init => 0,
        Some(init) if i < init => i + 1,
        _ => i,
    }
}

/// Writes `a` in every format and reads it back, checking each result.
fn round_trip_all(a: &Automaton) {
    // Whether a file said its controllability is not part of the automaton: every writer says it.
    let a = &Automaton { controllability_unsaid: false, ..a.clone() };
    let stem = |ext: &str| PathBuf::from(format!("{}.{ext}", a.name));
    // .xmd and .gen keep everything but the role (the automaton is named after the file); a .gen without
    // a controllable event reads as saying nothing of controllability — all uncontrollable, as written.
    let unknown = Automaton { kind: Kind::Unknown, ..a.clone() };
    assert_eq!(xmd::read(&stem("xmd"), &xmd::write(a)).unwrap(), unknown);
    // Nadzoru2 .xml keeps the same (every event observable, as the supervisors built here need).
    assert_eq!(
        read_bytes(&stem("xml"), nadzoru::write(a).as_bytes()).unwrap(),
        std::slice::from_ref(&unknown)
    );
    let gen_back = gen::read(&stem("gen"), &gen::write(a)).unwrap();
    assert_eq!(gen_back.controllability_unsaid, !a.events.iter().any(|e| e.controllable));
    assert_eq!(Automaton { controllability_unsaid: false, ..gen_back }, unknown);
    // .wmod keeps the role; an unknown role is written as a plant.
    let kind = if a.kind == Kind::Unknown { Kind::Plant } else { a.kind };
    let back = wmod::read(&stem("wmod"), &wmod::write("m", std::slice::from_ref(a)).unwrap()).unwrap();
    assert_eq!(back, [Automaton { kind, ..a.clone() }]);
    // .ADS renumbers states; event names go through the map.
    let files = ads::write(a).unwrap();
    let map = files.event_map.as_deref().map(|m| (Path::new("m.events"), m));
    let back = ads::read(&stem("ads"), &files.ads, map).unwrap();
    assert_same(a, &back, Some(&tct_number(a)));
    // Writing the TCT read again gives the same text: the numbering is stable.
    assert_eq!(ads::write(&back).unwrap().ads, files.ads);
}

#[test]
fn every_readable_model_round_trips_through_every_format() {
    for file in model_files() {
        let Ok(automata) = read_path(&file) else { continue };
        for a in &automata {
            round_trip_all(a);
        }
        // Modules keep all their components.
        let text = wmod::write("m", &automata).unwrap();
        assert_eq!(read_bytes(Path::new("m.wmod"), text.as_bytes()).unwrap().len(), automata.len());
    }
}

/// Names with the characters that need escaping somewhere (quotes, markup, `&`, `%`, spaces, non-ASCII).
fn name() -> impl Strategy<Value = String> {
    "[a-zA-Z0-9_(),.:&<>\"'%+é-]([a-z0-9 ]{0,4}[a-z0-9])?"
}

prop_compose! {
    /// A random deterministic automaton with unique names; `tag` keeps names distinct.
    fn automaton(tag: &'static str)(
        n in 0usize..6,
        events in prop::collection::vec((name(), any::<bool>()), 0..4),
        names in prop::collection::vec(name(), 6),
        marks in prop::collection::vec(any::<bool>(), 6),
        init in 0usize..6,
        delta in prop::collection::vec(prop::option::of(0usize..6), 24),
        kind in prop::sample::select(vec![Kind::Plant, Kind::Spec, Kind::Supervisor, Kind::Unknown]),
    ) -> Automaton {
        let mut a = Automaton::new(format!("A{tag}"), kind);
        for (i, (e, c)) in events.iter().enumerate() {
            a.add_event(format!("{e}{tag}{i}"), *c).unwrap();
        }
        for i in 0..n {
            a.add_state(format!("{}{i}", names[i]), marks[i]).unwrap();
        }
        if n > 0 {
            a.initial = Some(StateId::new(init % n).unwrap());
        }
        for s in 0..n {
            for e in 0..a.events.len() {
                if let Some(t) = delta[s * 4 + e] {
                    a.add_transition(StateId::new(s).unwrap(), EventId::new(e).unwrap(), StateId::new(t % n).unwrap());
                }
            }
        }
        a.validate().unwrap();
        a.canonicalize();
        a
    }
}

proptest! {
    #[test]
    fn random_automata_round_trip_through_every_format(a in automaton("")) {
        round_trip_all(&a);
    }

    #[test]
    fn random_modules_keep_every_component(a in automaton("x"), b in automaton("y")) {
        let mut b = b;
        b.name = "B".into();
        let back = wmod::read(Path::new("m.wmod"), &wmod::write("m", &[a.clone(), b.clone()]).unwrap()).unwrap();
        prop_assert_eq!(back.len(), 2);
        let fix = |x: &Automaton| Automaton { kind: if x.kind == Kind::Unknown { Kind::Plant } else { x.kind }, ..x.clone() };
        prop_assert_eq!(&back[0], &fix(&a));
        prop_assert_eq!(&back[1], &fix(&b));
    }
}
