//! IDES3 `.xmd`: `<model type="FSA">` with `<state>`, `<event>` and `<transition>` elements inside
//! `<data>`. Nadzoru2 writes the same root with its automaton in attributes (`<state id name initial
//! marked/>`); a document in that dialect is read by [`super::nadzoru`], whatever its extension.
//!
//! States and events carry an `id` attribute that transitions refer to and a `<name>` child (the id
//! stands in when the name is missing or empty). Flags live in `<properties>`: `<initial/>`,
//! `<marked/>` on states, `<controllable/>` on events (`<observable/>` is accepted and ignored: every
//! event is observed by the controller this tool builds). The `<meta>` blocks hold layout and are
//! skipped. The automaton is named after the file stem: the model's `id` attribute is usually a tool
//! expression such as `supcon(Ga,K1)`.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use roxmltree::{Document, Node};

use super::builder::Builder;
use super::nadzoru;
use super::xml::{self, escape};
use super::{file_stem, ParseError};
use crate::model::{Automaton, EventId, Kind, StateId};

/// Reads one automaton from the text of an `.xmd` file; `file` names it in errors and gives its name.
pub fn read(file: &Path, text: &str) -> Result<Automaton, ParseError> {
    let doc = xml::parse(file, text)?;
    let root = doc.root_element();
    let line = |n: Node| xml::line(&doc, n);
    if root.tag_name().name() != "model" {
        return Err(ParseError::syntax(
            file,
            line(root),
            format!("expected a <model> root element, found <{}>", root.tag_name().name()),
        ));
    }
    if let Some(ty) = root.attribute("type").filter(|&t| t != "FSA") {
        return Err(ParseError::unsupported(
            file,
            line(root),
            format!("<model type=\"{ty}\">: only FSA models"),
        ));
    }
    let mut data = root.children().filter(|n| n.has_tag_name("data"));
    let data =
        data.next().ok_or_else(|| ParseError::syntax(file, line(root), "<model> has no <data> element"))?;
    if nadzoru::is_nadzoru(data) {
        return nadzoru::read_data(file, &doc, data);
    }

    let mut b = Builder::new(file, file_stem(file), Kind::Unknown);
    let mut states: HashMap<&str, StateId> = HashMap::new();
    let mut events: HashMap<&str, EventId> = HashMap::new();
    let elements: Vec<Node> = data.children().filter(Node::is_element).collect();
    for &n in &elements {
        let at = line(n);
        match n.tag_name().name() {
            "state" => {
                let id = required_id(file, &doc, n)?;
                let props = Properties::of(n);
                let s = b.state(name_of(n, id), props.has("marked"), at)?;
                if states.insert(id, s).is_some() {
                    return Err(ParseError::syntax(file, at, format!("second state with id '{id}'")));
                }
                if props.has("initial") {
                    b.initial(s, at)?;
                }
            }
            "event" => {
                let id = required_id(file, &doc, n)?;
                let e = b.event(name_of(n, id), Properties::of(n).has("controllable"), at)?;
                if events.insert(id, e).is_some() {
                    return Err(ParseError::syntax(file, at, format!("second event with id '{id}'")));
                }
            }
            "transition" => {}
            other => {
                return Err(ParseError::unsupported(file, at, format!("<{other}> inside <data>")));
            }
        }
    }
    for &n in elements.iter().filter(|n| n.has_tag_name("transition")) {
        let at = line(n);
        let id = n.attribute("id").unwrap_or("?");
        let attr = |name: &str| {
            n.attribute(name).ok_or_else(|| {
                ParseError::syntax(file, at, format!("transition {id} has no '{name}' attribute"))
            })
        };
        let state = |name: &str| -> Result<StateId, ParseError> {
            let key = attr(name)?;
            states.get(key).copied().ok_or_else(|| {
                ParseError::syntax(file, at, format!("transition {id} refers to unknown state '{key}'"))
            })
        };
        let (source, target) = (state("source")?, state("target")?);
        let key = n.attribute("event").ok_or_else(|| {
            ParseError::unsupported(file, at, format!("transition {id} has no event (epsilon transitions)"))
        })?;
        let event = events.get(key).copied().ok_or_else(|| {
            ParseError::syntax(file, at, format!("transition {id} refers to unknown event '{key}'"))
        })?;
        b.transition(source, event, target, at);
    }
    b.finish()
}

/// Writes `a` as an `.xmd` document (no layout block; IDES lays the graph out when it opens it).
pub fn write(a: &Automaton) -> String {
    let mut out = String::with_capacity(256 + 120 * (a.states.len() + a.transitions.len()));
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(out, "<model version=\"2.1\" type=\"FSA\" id=\"{}\">\n<data>", escape(&a.name));
    for (i, s) in a.states.iter().enumerate() {
        let initial = a.initial.is_some_and(|x| x.index() == i);
        let _ = writeln!(out, "\t<state id=\"{i}\">");
        flags(&mut out, &[("initial", initial), ("marked", s.marked)]);
        let _ = writeln!(out, "\t\t<name>{}</name>\n\t</state>", escape(&s.name));
    }
    for (i, e) in a.events.iter().enumerate() {
        let _ = writeln!(out, "\t<event id=\"{i}\">");
        flags(&mut out, &[("controllable", e.controllable), ("observable", true)]);
        let _ = writeln!(out, "\t\t<name>{}</name>\n\t</event>", escape(&e.name));
    }
    for (i, t) in a.transitions.iter().enumerate() {
        let _ = writeln!(
            out,
            "\t<transition id=\"{i}\" source=\"{}\" target=\"{}\" event=\"{}\"/>",
            t.source, t.target, t.event
        );
    }
    out.push_str("</data>\n</model>\n");
    out
}

fn flags(out: &mut String, flags: &[(&str, bool)]) {
    out.push_str("\t\t<properties>\n");
    for (name, _) in flags.iter().filter(|(_, on)| *on) {
        let _ = writeln!(out, "\t\t\t<{name}/>");
    }
    out.push_str("\t\t</properties>\n");
}

fn required_id<'a>(file: &Path, doc: &Document, n: Node<'a, '_>) -> Result<&'a str, ParseError> {
    n.attribute("id").ok_or_else(|| {
        ParseError::syntax(
            file,
            xml::line(doc, n),
            format!("<{}> has no 'id' attribute", n.tag_name().name()),
        )
    })
}

/// The text of the `<name>` child, or the id when there is none.
fn name_of<'a>(n: Node<'a, '_>, id: &'a str) -> &'a str {
    n.children()
        .find(|c| c.has_tag_name("name"))
        .and_then(|c| c.text())
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .unwrap_or(id)
}

/// The flags in a `<properties>` child.
struct Properties<'a, 'i>(Option<Node<'a, 'i>>);

impl<'a, 'i> Properties<'a, 'i> {
    fn of(n: Node<'a, 'i>) -> Self {
        Properties(n.children().find(|c| c.has_tag_name("properties")))
    }

    fn has(&self, flag: &str) -> bool {
        self.0.is_some_and(|p| p.children().any(|c| c.has_tag_name(flag)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<model version="2.1" type="FSA" id="x">
<data>
	<state id="1"><properties><initial/><marked/></properties><name>idle</name></state>
	<state id="2"><properties/><name>busy</name></state>
	<event id="1"><properties><controllable/></properties><name>start</name></event>
	<event id="2"><properties/><name>done</name></event>
	<transition id="4" source="1" target="2" event="1"/>
	<transition id="5" source="2" target="1" event="2"/>
</data>
<meta tag="layout"><state id="1"/></meta>
</model>"#;

    #[test]
    fn reads_flags_names_and_transitions() {
        let a = read(Path::new("dir/G.xmd"), G).unwrap();
        assert_eq!(a.name, "G");
        assert_eq!(
            a.states.iter().map(|s| (s.name.as_str(), s.marked)).collect::<Vec<_>>(),
            [("idle", true), ("busy", false)]
        );
        assert_eq!(a.initial, a.state_id("idle"));
        assert!(a.events[a.event_id("start").unwrap().index()].controllable);
        assert!(!a.events[a.event_id("done").unwrap().index()].controllable);
        assert_eq!(a.transitions.len(), 2);
    }

    #[test]
    fn write_then_read_gives_the_same_automaton() {
        let a = read(Path::new("G.xmd"), G).unwrap();
        assert_eq!(read(Path::new("G.xmd"), &write(&a)).unwrap(), a);
    }

    #[test]
    fn dangling_state_reference_names_line_and_transition() {
        let bad = G.replace(r#"id="5" source="2""#, r#"id="5" source="9""#);
        let msg = read(Path::new("G1.xmd"), &bad).unwrap_err().to_string();
        assert_eq!(msg, "G1.xmd: line 9: transition 5 refers to unknown state '9'");
    }
}
