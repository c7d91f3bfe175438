//! TCT `.ADS` (Wonham's tool): a name line, then `State size`, `Marker states`, `Vocal states` and
//! `Transitions` sections; `#` starts a comment line.
//!
//! States are the numbers `0 .. size-1` and state 0 is initial. Marker states are listed one per line
//! (several per line are accepted too), or `*` marks every state; the list may or may not end with a
//! blank line. Vocal states are ignored. Transitions are `source label target` triples. TCT events are
//! numbers: odd labels are controllable, even ones uncontrollable.
//!
//! An optional **event map** gives labels names: one `label name` pair per line (`#` comments and
//! blank lines allowed). With a map, the alphabet is the map's events (in its order) followed by any
//! label the transitions use that the map lacks; without one, it is the labels the transitions use,
//! in increasing order, named by their numbers. [`write()`] produces a map whenever the labels alone
//! would lose information (names that are not TCT labels, or events no transition uses).

use std::collections::{BTreeSet, HashMap};
use std::fmt::Write as _;
use std::path::Path;

use super::builder::Builder;
use super::{file_stem, ParseError, WriteError};
use crate::model::{Automaton, EventId, Kind, StateId};

/// The largest state size TCT accepts (its own prompt says "in range 0 to 2000000").
pub const MAX_STATES: usize = 2_000_000;
/// The largest event label TCT accepts.
pub const MAX_LABEL: u32 = 999;

/// The sections of an `.ADS` file, in the order they appear.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Section {
    Name,
    Size,
    Markers,
    Vocal,
    Transitions,
}

/// Reads one automaton from the text of an `.ADS` file, naming events through `event_map` (the text
/// of a map file and its path) when given.
pub fn read(file: &Path, text: &str, event_map: Option<(&Path, &str)>) -> Result<Automaton, ParseError> {
    let map = event_map.map(|(path, text)| read_event_map(path, text)).transpose()?;
    let mut b = Builder::new(file, file_stem(file), Kind::Unknown);
    let mut events: HashMap<u32, EventId> = HashMap::new();
    if let Some(map) = &map {
        for (label, name, line) in map {
            let id = b.event(name, label % 2 == 1, *line)?;
            events.insert(*label, id);
        }
    }
    let mut section = Section::Name;
    let mut size: Option<usize> = None;
    let mut name_seen = false;
    let mut unnamed: BTreeSet<u32> = BTreeSet::new();
    let mut transitions: Vec<(StateId, u32, StateId, usize)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.trim();
        if content.starts_with('#') {
            continue;
        }
        if let Some(next) = header(content) {
            if next <= section {
                return Err(ParseError::syntax(file, line, format!("section '{content}' out of order")));
            }
            if next > Section::Size && size.is_none() {
                return Err(ParseError::syntax(file, line, "missing state size before this section"));
            }
            section = next;
            continue;
        }
        if content.is_empty() {
            continue;
        }
        match section {
            Section::Name if name_seen => {
                return Err(ParseError::syntax(
                    file,
                    line,
                    format!("unexpected '{content}' before the state size"),
                ));
            }
            Section::Name => name_seen = true,
            Section::Size => {
                if size.is_some() {
                    return Err(ParseError::syntax(
                        file,
                        line,
                        format!("unexpected '{content}' after the state size"),
                    ));
                }
                let n = number(file, line, content, "state size")?;
                if n as usize > MAX_STATES {
                    return Err(ParseError::syntax(
                        file,
                        line,
                        format!("state size {n} exceeds TCT's limit of {MAX_STATES}"),
                    ));
                }
                for s in 0..n {
                    b.state(s.to_string(), false, line)?;
                }
                if n > 0 {
                    b.initial(StateId::from_u32(0), line)?;
                }
                size = Some(n as usize);
            }
            Section::Markers if content == "*" => b.mark_all(),
            Section::Markers => {
                for word in content.split_whitespace() {
                    let s = state(file, line, word, b.state_count())?;
                    b.mark(s);
                }
            }
            Section::Vocal => {}
            Section::Transitions => {
                let words: Vec<&str> = content.split_whitespace().collect();
                let [source, label, target] = words[..] else {
                    return Err(ParseError::syntax(
                        file,
                        line,
                        format!("expected 'source label target', found '{content}'"),
                    ));
                };
                let source = state(file, line, source, b.state_count())?;
                let label = number(file, line, label, "event label")?;
                let target = state(file, line, target, b.state_count())?;
                if !events.contains_key(&label) {
                    unnamed.insert(label);
                }
                transitions.push((source, label, target, line));
            }
        }
    }
    if size.is_none() {
        return Err(ParseError::syntax(file, text.lines().count().max(1), "no 'State size' section"));
    }
    for label in unnamed {
        events.insert(label, b.event(&label.to_string(), label % 2 == 1, 1)?);
    }
    for (source, label, target, line) in transitions {
        b.transition(source, events[&label], target, line);
    }
    b.finish()
}

/// The section a header line opens, if it is one.
fn header(content: &str) -> Option<Section> {
    [
        ("State size", Section::Size),
        ("Marker states", Section::Markers),
        ("Vocal states", Section::Vocal),
        ("Transitions", Section::Transitions),
    ]
    .into_iter()
    .find(|(prefix, _)| content.starts_with(prefix))
    .map(|(_, s)| s)
}

fn number(file: &Path, line: usize, word: &str, what: &str) -> Result<u32, ParseError> {
    word.parse::<u32>().map_err(|_| {
        ParseError::syntax(file, line, format!("{what} '{word}' is not a number from 0 to {}", u32::MAX))
    })
}

fn state(file: &Path, line: usize, word: &str, size: usize) -> Result<StateId, ParseError> {
    let n = number(file, line, word, "state")?;
    if n as usize >= size {
        return Err(ParseError::syntax(
            file,
            line,
            format!("state {n} is out of range: the state size is {size}"),
        ));
    }
    Ok(StateId::from_u32(n))
}

/// The `(label, name, line)` entries of an event map.
fn read_event_map(file: &Path, text: &str) -> Result<Vec<(u32, String, usize)>, ParseError> {
    let mut entries = Vec::new();
    let mut seen: HashMap<u32, usize> = HashMap::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        let (label, name) = content.split_once(char::is_whitespace).ok_or_else(|| {
            ParseError::syntax(file, line, format!("expected 'label name', found '{content}'"))
        })?;
        let label = number(file, line, label, "event label")?;
        if let Some(first) = seen.insert(label, line) {
            return Err(ParseError::syntax(
                file,
                line,
                format!("label {label} already named on line {first}"),
            ));
        }
        let name = name.trim().to_owned();
        if let Some(first) = names.insert(name.clone(), line) {
            return Err(ParseError::syntax(
                file,
                line,
                format!("name '{name}' already used on line {first}"),
            ));
        }
        entries.push((label, name, line));
    }
    Ok(entries)
}

/// An automaton written as TCT files: the `.ADS` text and, when needed, the event map.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdsFiles {
    /// The `.ADS` text.
    pub ads: String,
    /// The event map text, when the labels alone would lose names or unused events.
    pub event_map: Option<String>,
}

/// Writes `a` in TCT's format: the initial state becomes state 0, the other states follow in order
/// (state names are lost: TCT states are numbers), and events get labels of the right parity.
pub fn write(a: &Automaton) -> Result<AdsFiles, String> {
    if a.states.len() > MAX_STATES {
        return Err(format!("{} states exceed TCT's limit of {MAX_STATES}", a.states.len()));
    }
    let labels = labels(a)?;
    // State numbering: the initial state first, then the others in their order.
    let mut number: Vec<usize> = (0..a.states.len()).collect();
    if let Some(init) = a.initial {
        for (i, n) in number.iter_mut().enumerate() {
            *n = match i {
                i if i == init.index() => 0,
                i if i < init.index() => i + 1,
                i => i,
            };
        }
    }
    let mut out = format!(
        "# written by codegen\n{}\nState size (State set will be (0,1,...,size-1)):\n{}\nMarker states:\n",
        a.name.replace(['\n', '\r'], " "),
        a.states.len()
    );
    let mut marked: Vec<usize> =
        a.states.iter().enumerate().filter(|(_, s)| s.marked).map(|(i, _)| number[i]).collect();
    marked.sort_unstable();
    for m in marked {
        let _ = writeln!(out, "{m}");
    }
    out.push_str("\nVocal states:\n\nTransitions:\n");
    let mut triples: Vec<(usize, u32, usize)> = a
        .transitions
        .iter()
        .map(|t| (number[t.source.index()], labels[t.event.index()], number[t.target.index()]))
        .collect();
    triples.sort_unstable();
    for (s, e, t) in triples {
        let _ = writeln!(out, "{s} {e} {t}");
    }
    let used: BTreeSet<usize> = a.transitions.iter().map(|t| t.event.index()).collect();
    let plain = used.len() == a.events.len()
        && a.events.iter().zip(&labels).all(|(e, l)| e.name == l.to_string())
        && labels.windows(2).all(|w| w[0] < w[1]);
    let event_map = (!plain).then(|| {
        let mut map = String::from("# TCT event labels and their names\n");
        for (e, l) in a.events.iter().zip(&labels) {
            let _ = writeln!(map, "{l} {}", e.name);
        }
        map
    });
    Ok(AdsFiles { ads: out, event_map })
}

/// One TCT label per event: its own name when that is a label of the right parity, else the next free
/// odd (controllable) or even (uncontrollable) label.
fn labels(a: &Automaton) -> Result<Vec<u32>, String> {
    for e in &a.events {
        if e.name.is_empty() || e.name.trim() != e.name || e.name.contains(['\n', '\r']) {
            return Err(format!(
                "event name '{}' cannot be written to a TCT event map",
                e.name.escape_debug()
            ));
        }
    }
    let own = |name: &str, controllable: bool| {
        name.parse::<u32>()
            .ok()
            .filter(|&l| l <= MAX_LABEL && (l % 2 == 1) == controllable && name == l.to_string())
    };
    let mut taken: BTreeSet<u32> = a.events.iter().filter_map(|e| own(&e.name, e.controllable)).collect();
    let mut next = [2u32, 1u32];
    let mut labels = Vec::with_capacity(a.events.len());
    for e in &a.events {
        if let Some(l) = own(&e.name, e.controllable) {
            labels.push(l);
            continue;
        }
        let slot = &mut next[usize::from(e.controllable)];
        while taken.contains(slot) {
            *slot += 2;
        }
        if *slot > MAX_LABEL {
            return Err(format!("more events than TCT's labels 0 to {MAX_LABEL} can hold"));
        }
        labels.push(*slot);
        taken.insert(*slot);
    }
    Ok(labels)
}

/// Writes [`AdsFiles`] for `path`: the map goes next to it as `<stem>.events`.
pub(crate) fn write_files(path: &Path, a: &Automaton) -> Result<(), WriteError> {
    let files = write(a).map_err(|msg| WriteError::Unrepresentable { file: path.to_path_buf(), msg })?;
    super::write_file(path, &files.ads)?;
    if let Some(map) = files.event_map {
        super::write_file(&event_map_for(path), &map)?;
    }
    Ok(())
}

/// Where the event map of the `.ADS` file at `path` lives: `<stem>.events` beside it.
pub fn event_map_for(path: &Path) -> std::path::PathBuf {
    path.with_extension("events")
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEST: &str = include_str!("../../tests/data/TEST.ADS");

    #[test]
    fn reads_tct_labels_with_parity_controllability() {
        let a = read(Path::new("TEST.ADS"), TEST, None).unwrap();
        assert_eq!(
            (a.states.len(), a.transitions.len(), a.events.len(), a.controllable_count()),
            (5, 13, 6, 3)
        );
        let names: Vec<_> = a.events.iter().map(|e| (e.name.as_str(), e.controllable)).collect();
        assert_eq!(names, [("1", true), ("2", false), ("3", true), ("4", false), ("5", true), ("6", false)]);
        assert_eq!(a.initial, Some(StateId::from_u32(0)));
        assert_eq!(a.marked_count(), 1);
    }

    #[test]
    fn event_map_names_labels_and_adds_unused_events() {
        let map = "# names\n1 a\n2 b\n7 extra\n";
        let a = read(Path::new("TEST.ADS"), TEST, Some((Path::new("TEST.events"), map))).unwrap();
        let names: Vec<_> = a.events.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["a", "b", "extra", "3", "4", "5", "6"]);
        assert!(a.events[2].controllable);
    }

    #[test]
    fn star_marks_all_and_marker_list_without_blank_line() {
        let text = "X\nState size (State set will be (0,1,...,size-1)):\n3\nMarker states:\n*\nVocal states:\nTransitions:\n0 2 1\n";
        let a = read(Path::new("X.ADS"), text, None).unwrap();
        assert_eq!(a.marked_count(), 3);
        let text = text.replace("*\n", "1\n2\n");
        let a = read(Path::new("X.ADS"), &text, None).unwrap();
        assert_eq!(a.states.iter().map(|s| s.marked).collect::<Vec<_>>(), [false, true, true]);
    }

    #[test]
    fn write_then_read_is_identity_for_tct_automata() {
        let a = read(Path::new("TEST.ADS"), TEST, None).unwrap();
        let files = write(&a).unwrap();
        assert_eq!(files.event_map, None);
        assert_eq!(read(Path::new("TEST.ADS"), &files.ads, None).unwrap(), a);
    }

    #[test]
    fn named_events_get_parity_labels_and_a_map() {
        let mut a = Automaton::new("G", Kind::Plant);
        let s = a.add_state("idle", true).unwrap();
        let t = a.add_state("busy", false).unwrap();
        let go = a.add_event("go", true).unwrap();
        let done = a.add_event("done", false).unwrap();
        a.add_event("3", true).unwrap();
        a.initial = Some(t);
        a.add_transition(s, go, t);
        a.add_transition(t, done, s);
        let files = write(&a).unwrap();
        // busy (initial) is state 0, idle state 1; "3" keeps its own label, go takes the next odd one.
        assert!(files.ads.contains("Transitions:\n0 2 1\n1 1 0\n"), "{}", files.ads);
        assert_eq!(
            files.event_map.as_deref(),
            Some("# TCT event labels and their names\n1 go\n2 done\n3 3\n")
        );
    }

    #[test]
    fn out_of_range_state_and_huge_size_are_named() {
        let bad = TEST.replace("4 6 0", "4 6 9");
        let msg = read(Path::new("T.ADS"), &bad, None).unwrap_err().to_string();
        assert_eq!(msg, "T.ADS: line 34: state 9 is out of range: the state size is 5");
        let bad = TEST.replacen("\n5\n", "\n99999999999\n", 1);
        let msg = read(Path::new("T.ADS"), &bad, None).unwrap_err().to_string();
        assert_eq!(msg, "T.ADS: line 5: state size '99999999999' is not a number from 0 to 4294967295");
    }
}
