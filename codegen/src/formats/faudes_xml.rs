//! libFAUDES's XML generator (`XWrite`, DESTool's files): the same generator as the token format
//! [`super::gen`] reads, as XML.
//!
//! ```xml
//! <?xml version="1.0" encoding="ISO-8859-1" standalone="no"?>
//! <!DOCTYPE System SYSTEM "http://www.faudes.org/dtd/1.0/system.dtd">
//! <Generator name="S" ftype="System">
//! <Alphabet><Event name="a"><Controllable/></Event><Event name="b"/></Alphabet>
//! <StateSet><State id="1" name="idle"><Initial/><Marked/></State><State id="2"/></StateSet>
//! <TransitionRelation><Transition x1="1" event="a" x2="2"/></TransitionRelation>
//! </Generator>
//! ```
//!
//! States are known by their `id` (transitions name them by it, `x1` and `x2`) and named by `name`, an
//! anonymous state by its id, as the token reader names it. Controllability follows the token format's
//! rule: a generator without `<Controllable/>` anywhere says nothing of it (libFAUDES keeps it with the
//! plant), so that the two forms of one generator read alike. Other event flags
//! (`<Observable value="false"/>`, forcible) are skipped, as `+o+` and `+F+` are in the token format.
//! The document type declaration (an external reference) is skipped; one with an internal subset is
//! refused. The automaton is named after the file stem.

use std::collections::HashMap;
use std::path::Path;

use roxmltree::Node;

use super::builder::Builder;
use super::xml;
use super::{file_stem, ParseError};
use crate::model::{Automaton, Kind, StateId};

/// Whether `text` is a generator in libFAUDES's XML form rather than its token form: an XML prolog, or
/// an element only the XML form has (the token form's markup is its section names alone).
pub(crate) fn is_xml(text: &str) -> bool {
    let head = text.trim_start_matches('\u{feff}').trim_start();
    head.starts_with("<?xml")
        || head.starts_with("<!DOCTYPE")
        || ["<StateSet", "<TransitionRelation", "<Event "].iter().any(|m| text.contains(m))
}

/// Reads the automaton of a libFAUDES XML generator.
pub(crate) fn read(file: &Path, text: &str) -> Result<Automaton, ParseError> {
    let text = without_doctype(file, text)?;
    let doc = xml::parse(file, &text)?;
    let line = |n: Node| xml::line(&doc, n);
    let root = doc.root_element();
    if !matches!(root.tag_name().name(), "Generator" | "System") {
        return Err(ParseError::syntax(
            file,
            line(root),
            format!("expected a <Generator> root element, found <{}>", root.tag_name().name()),
        ));
    }
    let mut b = Builder::new(file, file_stem(file), Kind::Unknown);
    let mut states: HashMap<&str, StateId> = HashMap::new();
    let mut seen = Vec::new();
    for section in root.children().filter(Node::is_element) {
        let name = section.tag_name().name();
        if !["Alphabet", "StateSet", "TransitionRelation"].contains(&name) {
            return Err(ParseError::unsupported(
                file,
                line(section),
                format!("section <{name}> (only <Alphabet>, <StateSet>, <TransitionRelation> are read)"),
            ));
        }
        if seen.contains(&name) {
            return Err(ParseError::syntax(file, line(section), format!("second <{name}>")));
        }
        seen.push(name);
        for n in section.children().filter(Node::is_element) {
            let at = line(n);
            let attr = |a: &str| {
                n.attribute(a).ok_or_else(|| {
                    ParseError::syntax(file, at, format!("<{}> has no '{a}' attribute", n.tag_name().name()))
                })
            };
            match (name, n.tag_name().name()) {
                ("Alphabet", "Event") => {
                    let controllable = n.children().any(|c| c.has_tag_name("Controllable"));
                    b.event(attr("name")?, controllable, at)?;
                }
                ("StateSet", "State") => {
                    let id = attr("id")?;
                    let label = n.attribute("name").filter(|s| !s.trim().is_empty()).unwrap_or(id);
                    let marked = n.children().any(|c| c.has_tag_name("Marked"));
                    let s = b.state(label, marked, at)?;
                    if states.insert(id, s).is_some() {
                        return Err(ParseError::syntax(file, at, format!("state id {id} is declared twice")));
                    }
                    if n.children().any(|c| c.has_tag_name("Initial")) {
                        b.initial(s, at)?;
                    }
                }
                ("TransitionRelation", "Transition") => {
                    let state = |a: &str| -> Result<StateId, ParseError> {
                        let id = attr(a)?;
                        states.get(id).copied().ok_or_else(|| {
                            ParseError::syntax(
                                file,
                                at,
                                format!("transition refers to unknown state id {id} ({a})"),
                            )
                        })
                    };
                    let (source, target) = (state("x1")?, state("x2")?);
                    let event = b.event_named(attr("event")?, at)?;
                    b.transition(source, event, target, at);
                }
                (_, other) => {
                    return Err(ParseError::unsupported(file, at, format!("<{other}> in <{name}>")));
                }
            }
        }
    }
    let mut a = b.finish()?;
    a.controllability_unsaid = !a.events.iter().any(|e| e.controllable);
    Ok(a)
}

/// `text` with its `<!DOCTYPE …>` declaration blanked (same length, lines kept), so that the XML parser,
/// which takes no document type declarations, reads the rest; one with an internal subset (`[…]`, where
/// entities are declared) is refused.
fn without_doctype<'t>(file: &Path, text: &'t str) -> Result<std::borrow::Cow<'t, str>, ParseError> {
    let Some(start) = text.find("<!DOCTYPE") else { return Ok(text.into()) };
    let Some(len) = text[start..].find('>') else {
        return Err(ParseError::syntax(file, line_at(text, start), "unclosed <!DOCTYPE"));
    };
    let decl = &text[start..=start + len];
    if decl.contains('[') {
        return Err(ParseError::unsupported(
            file,
            line_at(text, start),
            "a document type declaration with an internal subset (entities)",
        ));
    }
    let blank: String = decl.chars().map(|c| if c == '\n' { '\n' } else { ' ' }).collect();
    Ok(format!("{}{blank}{}", &text[..start], &text[start + len + 1..]).into())
}

/// The 1-based line of byte offset `at` in `text`.
fn line_at(text: &str, at: usize) -> usize {
    text[..at].matches('\n').count() + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A system as libFAUDES's `XWrite` writes it (prolog, external document type, anonymous state).
    const SYSTEM: &str = "<?xml version=\"1.0\" encoding=\"ISO-8859-1\" standalone=\"no\"?>\n\
<!DOCTYPE System SYSTEM \"http://www.faudes.org/dtd/1.0/system.dtd\">\n\
<Generator name=\"S\" ftype=\"System\">\n\n<Alphabet>\n<Event name=\"a\">\n<Controllable/>\n</Event>\n\
<Event name=\"b\"/>\n<Event name=\"c\">\n<Observable value=\"false\"/>\n</Event>\n</Alphabet>\n\n\
<StateSet>\n<State id=\"1\" name=\"idle\">\n<Initial/>\n<Marked/>\n</State>\n<State id=\"2\" name=\"busy\"/>\n\
<State id=\"3\"/>\n</StateSet>\n\n<TransitionRelation>\n<Transition x1=\"1\" event=\"a\" x2=\"2\"/>\n\
<Transition x1=\"2\" event=\"b\" x2=\"1\"/>\n</TransitionRelation>\n\n</Generator>\n";

    fn read(text: &str) -> Result<Automaton, ParseError> {
        super::super::read_bytes(Path::new("S.gen"), text.as_bytes()).map(|mut v| v.remove(0))
    }

    #[test]
    fn reads_what_xwrite_writes() {
        let a = read(SYSTEM).unwrap();
        assert_eq!(a.name, "S");
        assert_eq!(a.states.iter().map(|s| s.name.as_str()).collect::<Vec<_>>(), ["idle", "busy", "3"]);
        assert_eq!(a.initial, a.state_id("idle"));
        assert_eq!(a.marked_count(), 1);
        assert_eq!(a.events.iter().map(|e| e.controllable).collect::<Vec<_>>(), [true, false, false]);
        assert!(!a.controllability_unsaid, "a controllable event says it");
        assert_eq!(a.transitions.len(), 2);
        let plain = SYSTEM.replace("ftype=\"System\"", "ftype=\"Generator\"").replace("<Controllable/>", "");
        assert!(read(&plain).unwrap().controllability_unsaid, "a generator without flags says nothing");
        let token = crate::formats::gen::write(&a);
        assert_eq!(read(&token).unwrap(), a, "the token form of the same generator reads alike");
    }

    #[test]
    fn errors_name_the_line() {
        let bad = SYSTEM.replace("x2=\"1\"", "x2=\"9\"");
        let e = read(&bad).unwrap_err().to_string();
        assert!(e.starts_with("S.gen: line 26: transition refers to unknown state id 9 (x2)"), "{e}");
        let typo = SYSTEM.replace("event=\"b\"", "event=\"bb\"");
        assert!(read(&typo).unwrap_err().to_string().contains("line 26"), "the event's line");
        let entities = SYSTEM.replace("system.dtd\">", "system.dtd\" [<!ENTITY x \"y\">]>");
        assert!(read(&entities).unwrap_err().to_string().contains("line 2: unsupported: a document type"));
    }
}
