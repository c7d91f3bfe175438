//! Nadzoru2 `.xml` (GASR-UDESC/Nadzoru2, the reference tool of the local modular microcontroller paper):
//! `<model type="FSA">` with its automaton as attributes inside `<data>`.
//!
//! ```xml
//! <model version="0.0" type="FSA" id="Untitled">
//! <data>
//!     <state id="0" name="idle" initial="True" marked="True" x="100" y="100" />
//!     <event id="0" name="start" controllable="True" observable="True"/>
//!     <transition source="0" target="1" event="0"/>
//! </data>
//! </model>
//! ```
//!
//! States and events are known by their `id` (transitions name them by it) and named by `name` (a state
//! without a name is named by its id). The flags are Python's `True` / `False` (any case), as Nadzoru2
//! writes them; `x`, `y` are layout and skipped. Every event must say `controllable`, and be
//! `observable="True"`: the supervisors this tool builds observe every event, so an unobservable one is
//! refused rather than silently observed (every event read back is observable, and is written so). An
//! event without a name (Nadzoru2's editor leaves new ones unnamed) is refused: an event is known by its
//! name in every other automaton of a set. The automaton is named after the file stem, as for `.xmd` —
//! the same root element, whose other dialect (IDES3's `<name>` and `<properties>` children) [`super::xmd`]
//! reads; `is_nadzoru` tells them apart.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use roxmltree::{Document, Node};

use super::builder::Builder;
use super::xml::{self, escape};
use super::{file_stem, ParseError};
use crate::model::{Automaton, EventId, Kind, StateId};

/// Whether the `<data>` of a `<model>` document is Nadzoru2's: its states or events carry their name
/// (or flags) as attributes.
pub(crate) fn is_nadzoru(data: Node) -> bool {
    data.children()
        .filter(|n| n.has_tag_name("state") || n.has_tag_name("event"))
        .any(|n| n.attribute("name").is_some() || n.attribute("initial").is_some())
}

/// Reads the automaton of a Nadzoru2 document whose `<data>` element is `data`.
pub(crate) fn read_data(file: &Path, doc: &Document, data: Node) -> Result<Automaton, ParseError> {
    let line = |n: Node| xml::line(doc, n);
    let mut b = Builder::new(file, file_stem(file), Kind::Unknown);
    let mut states: HashMap<&str, StateId> = HashMap::new();
    let mut events: HashMap<&str, EventId> = HashMap::new();
    let elements: Vec<Node> = data.children().filter(Node::is_element).collect();
    for &n in &elements {
        let at = line(n);
        let flag = |name: &str, default: Option<bool>| flag(file, at, n, name, default);
        match n.tag_name().name() {
            "state" => {
                let id = required(file, at, n, "id")?;
                let name = n.attribute("name").map(str::trim).filter(|s| !s.is_empty()).unwrap_or(id);
                let s = b.state(name, flag("marked", Some(false))?, at)?;
                if states.insert(id, s).is_some() {
                    return Err(ParseError::syntax(file, at, format!("second state with id '{id}'")));
                }
                if flag("initial", Some(false))? {
                    b.initial(s, at)?;
                }
            }
            "event" => {
                let id = required(file, at, n, "id")?;
                let name = n.attribute("name").map(str::trim).unwrap_or_default();
                if name.is_empty() {
                    return Err(ParseError::syntax(
                        file,
                        at,
                        format!(
                            "event {id} has no name: an event is known by its name in every automaton of a \
                             set (Nadzoru2 leaves a new event unnamed): name it, or delete it and its \
                             transitions"
                        ),
                    ));
                }
                let controllable = flag("controllable", None)?;
                if !flag("observable", None)? {
                    return Err(ParseError::unsupported(
                        file,
                        at,
                        format!(
                            "event '{name}' is unobservable (observable=\"False\"): the supervisors this \
                             tool builds observe every event"
                        ),
                    ));
                }
                let e = b.event(name, controllable, at)?;
                if events.insert(id, e).is_some() {
                    return Err(ParseError::syntax(file, at, format!("second event with id '{id}'")));
                }
            }
            "transition" => {}
            other => return Err(ParseError::unsupported(file, at, format!("<{other}> inside <data>"))),
        }
    }
    for &n in elements.iter().filter(|n| n.has_tag_name("transition")) {
        let at = line(n);
        let id = |attr: &str| required(file, at, n, attr);
        let state = |attr: &str| -> Result<StateId, ParseError> {
            let key = id(attr)?;
            states.get(key).copied().ok_or_else(|| {
                ParseError::syntax(file, at, format!("transition refers to unknown state '{key}' ({attr})"))
            })
        };
        let (source, target) = (state("source")?, state("target")?);
        let key = id("event")?;
        let event = events.get(key).copied().ok_or_else(|| {
            ParseError::syntax(file, at, format!("transition refers to unknown event '{key}'"))
        })?;
        b.transition(source, event, target, at);
    }
    b.finish()
}

/// The attribute `name` of `n`, or an error at `line`.
fn required<'a>(file: &Path, line: usize, n: Node<'a, '_>, name: &str) -> Result<&'a str, ParseError> {
    n.attribute(name).ok_or_else(|| {
        ParseError::syntax(file, line, format!("<{}> has no '{name}' attribute", n.tag_name().name()))
    })
}

/// The Boolean attribute `name` of `n` (`True`/`False`, any case); `default` when absent, an error when
/// absent and there is no default.
fn flag(file: &Path, line: usize, n: Node, name: &str, default: Option<bool>) -> Result<bool, ParseError> {
    match n.attribute(name).map(str::trim) {
        Some(v) if v.eq_ignore_ascii_case("true") => Ok(true),
        Some(v) if v.eq_ignore_ascii_case("false") => Ok(false),
        Some(v) => Err(ParseError::syntax(file, line, format!("{name}=\"{v}\": True or False"))),
        None => default.ok_or_else(|| {
            ParseError::syntax(
                file,
                line,
                format!("<{}> says nothing of '{name}' (True or False)", n.tag_name().name()),
            )
        }),
    }
}

/// Writes `a` as Nadzoru2 writes an automaton: states (laid out on a grid of eight columns), events with
/// their flags, transitions by id.
pub fn write(a: &Automaton) -> String {
    let mut out = String::with_capacity(256 + 100 * (a.states.len() + a.transitions.len()));
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(out, "<model version=\"0.0\" type=\"FSA\" id=\"{}\">\n<data>", escape(&a.name));
    let py = |b: bool| if b { "True" } else { "False" };
    for (i, s) in a.states.iter().enumerate() {
        let initial = a.initial.is_some_and(|x| x.index() == i);
        let (x, y) = (100 + 150 * (i % 8), 100 + 150 * (i / 8));
        let _ = writeln!(
            out,
            "\t<state id=\"{i}\" name=\"{}\" initial=\"{}\" marked=\"{}\" x=\"{x}\" y=\"{y}\" />",
            escape(&s.name),
            py(initial),
            py(s.marked)
        );
    }
    for (i, e) in a.events.iter().enumerate() {
        let _ = writeln!(
            out,
            "\t<event id=\"{i}\" name=\"{}\" controllable=\"{}\" observable=\"True\"/>",
            escape(&e.name),
            py(e.controllable)
        );
    }
    for t in &a.transitions {
        let _ = writeln!(
            out,
            "\t<transition source=\"{}\" target=\"{}\" event=\"{}\"/>",
            t.source, t.target, t.event
        );
    }
    out.push_str("</data>\n</model>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of the form of Nadzoru2's `examples/*.xml` (written here: flags as Python writes them,
    /// the space Nadzoru2 leaves before `=` of `initial`, layout attributes).
    const MACHINE: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<model version="0.0" type="FSA" id="Untitled">
<data>
	<state id="0" name="busy" initial ="False" marked="False" x="203" y="234" />
	<state id="1" name="idle" initial ="True" marked="True" x="100" y="123" />
	<event id="0" name="start" controllable="True" observable="True"/>
	<event id="1" name="done" controllable="False" observable="True"/>
	<transition source="1" target="0" event="0"/>
	<transition source="0" target="1" event="1"/>
</data>
</model>
"#;

    fn read(text: &str) -> Result<Automaton, ParseError> {
        super::super::read_bytes(Path::new("dir/M.xml"), text.as_bytes()).map(|mut v| v.remove(0))
    }

    #[test]
    fn reads_names_flags_and_transitions_by_id() {
        let a = read(MACHINE).unwrap();
        assert_eq!(a.name, "M");
        assert_eq!(a.initial, a.state_id("idle"));
        assert!(a.states[a.state_id("idle").unwrap().index()].marked);
        assert!(a.events[a.event_id("start").unwrap().index()].controllable);
        assert!(!a.events[a.event_id("done").unwrap().index()].controllable);
        assert!(!a.controllability_unsaid);
        assert_eq!(a.transitions.len(), 2);
    }

    #[test]
    fn write_then_read_gives_the_same_automaton_with_its_flags() {
        let a = read(MACHINE).unwrap();
        let text = write(&a);
        assert!(
            text.contains("<event id=\"0\" name=\"start\" controllable=\"True\" observable=\"True\"/>"),
            "{text}"
        );
        assert_eq!(read(&text).unwrap(), a);
    }

    #[test]
    fn what_the_tool_cannot_keep_is_refused_by_name_and_line() {
        let unnamed = MACHINE.replace("name=\"done\"", "name=\"\"");
        let e = read(&unnamed).unwrap_err().to_string();
        assert!(e.starts_with("dir/M.xml: line 7: event 1 has no name"), "{e}");
        let hidden = MACHINE.replace(
            "controllable=\"False\" observable=\"True\"",
            "controllable=\"False\" observable=\"False\"",
        );
        let e = read(&hidden).unwrap_err().to_string();
        assert!(e.contains("line 7: unsupported: event 'done' is unobservable"), "{e}");
        let unsaid = MACHINE.replace(" controllable=\"True\"", "");
        let e = read(&unsaid).unwrap_err().to_string();
        assert!(e.contains("line 6: <event> says nothing of 'controllable' (True or False)"), "{e}");
        let odd = MACHINE.replace("marked=\"True\"", "marked=\"yes\"");
        assert!(read(&odd).unwrap_err().to_string().contains("marked=\"yes\": True or False"));
        let dangling = MACHINE.replace("source=\"0\" target=\"1\"", "source=\"0\" target=\"9\"");
        assert!(read(&dangling)
            .unwrap_err()
            .to_string()
            .contains("line 9: transition refers to unknown state '9'"));
    }
}
