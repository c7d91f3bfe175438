//! The PNML reader: place/transition nets of ISO/IEC 15909-2 as PIPE, TINA, Snoopy and WoPeD write them.
//!
//! One `<net>` per file; its places, transitions and arcs may sit directly in it (WoPeD) or in nested
//! `<page>`s (the standard), which are flattened. A label's value is the text of its `<text>` child
//! (the standard) or of a `<value>` child (PIPE, whose markings and weights read `Default,3`). An arc
//! with `<type value="inhibitor"/>` (PIPE) is an inhibitor arc. Graphics, names and `<toolspecific>`
//! sections are skipped. Other net types (symmetric, high-level), reference nodes, reset and read arcs
//! are refused naming the element: reading them as a P/T net would silently change their meaning.
//!
//! Every error names the file and the line ([`ParseError`]); no input makes the reader panic
//! ([`check_pnml`], fuzzed).

use std::collections::HashMap;
use std::path::Path;

use roxmltree::{Document, Node};

use super::model::{Net, Place, Transition};
use crate::formats::{decode, parse_xml, read_file, xml_line, ParseError};

/// The `type` attributes of `<net>` that mean a place/transition net.
const PT_TYPES: &[&str] = &[
    "http://www.pnml.org/version-2009/grammar/ptnet",
    "http://www.pnml.org/version-2009/grammar/pnmlcoremodel",
    "http://www.informatik.hu-berlin.de/top/pntd/ptNetb",
    "P/T net",
];

/// Largest marking or arc weight accepted (a bigger number is surely a mistake).
const MAX_TOKENS: u32 = 1 << 20;

/// Reads the net in the PNML file at `path`.
pub fn read_pnml(path: &Path) -> Result<Net, ParseError> {
    read_pnml_bytes(path, &read_file(path)?)
}

/// Reads the net in `bytes`, the content of a file called `path` (for errors).
pub fn read_pnml_bytes(path: &Path, bytes: &[u8]) -> Result<Net, ParseError> {
    let text = decode(path, bytes)?;
    let doc = parse_xml(path, &text)?;
    Reader { path, doc: &doc }.net()
}

/// The reader's contract as code, for the fuzz target and the random-input tests: no input panics, and
/// a net that reads is well formed — unique ids, arcs within range and of positive weight, each list of
/// a transition sorted by place without repeats.
pub fn check_pnml(path: &Path, bytes: &[u8]) {
    let Ok(net) = read_pnml_bytes(path, bytes) else { return };
    let mut ids: Vec<&str> = net
        .places
        .iter()
        .map(|p| p.id.as_str())
        .chain(net.transitions.iter().map(|t| t.id.as_str()))
        .collect();
    let count = ids.len();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), count, "node ids must be unique");
    for t in &net.transitions {
        for arcs in [&t.inputs, &t.outputs, &t.inhibitors] {
            assert!(arcs.windows(2).all(|w| w[0].0 < w[1].0), "arcs sorted by place, no repeats");
            assert!(arcs.iter().all(|&(p, w)| p < net.places.len() && w > 0), "arcs in range, weight > 0");
        }
    }
}

/// Which list of a transition an arc joins.
#[derive(Clone, Copy, PartialEq, Eq)]
enum ArcKind {
    Input,
    Output,
    Inhibitor,
}

struct Reader<'a, 'i> {
    path: &'a Path,
    doc: &'a Document<'i>,
}

impl<'i> Reader<'_, 'i> {
    fn line(&self, node: Node) -> usize {
        xml_line(self.doc, node)
    }

    fn syntax(&self, node: Node, msg: impl Into<String>) -> ParseError {
        ParseError::syntax(self.path, self.line(node), msg)
    }

    fn net(&self) -> Result<Net, ParseError> {
        let root = self.doc.root_element();
        if root.tag_name().name() != "pnml" {
            return Err(self.syntax(
                root,
                format!("expected a <pnml> root element, found <{}>", root.tag_name().name()),
            ));
        }
        let mut nets = root.children().filter(|n| n.has_tag_name_local("net"));
        let Some(net) = nets.next() else {
            return Err(self.syntax(root, "no <net> in <pnml>"));
        };
        if let Some(second) = nets.next() {
            return Err(ParseError::unsupported(
                self.path,
                self.line(second),
                format!("a second <net> (the first is on line {}); one net per file", self.line(net)),
            ));
        }
        let kind = net.attribute("type").unwrap_or("");
        if !PT_TYPES.contains(&kind) {
            return Err(ParseError::unsupported(
                self.path,
                self.line(net),
                format!("<net type=\"{kind}\"> (only place/transition nets)"),
            ));
        }
        let mut out = Net { name: net.attribute("id").unwrap_or("net").to_owned(), ..Net::default() };
        let mut arcs = Vec::new();
        // Node id → (is a place, index, line).
        let mut ids: HashMap<&str, (bool, usize, usize)> = HashMap::new();
        self.collect(net, &mut out, &mut arcs, &mut ids)?;
        for arc in arcs {
            self.arc(arc, &ids, &mut out)?;
        }
        Ok(out)
    }

    /// Places and transitions of `container` (a net or a page, pages recursively) into `out`; its arcs
    /// into `arcs`.
    fn collect<'d>(
        &self,
        container: Node<'d, 'i>,
        out: &mut Net,
        arcs: &mut Vec<Node<'d, 'i>>,
        ids: &mut HashMap<&'d str, (bool, usize, usize)>,
    ) -> Result<(), ParseError> {
        for n in container.children().filter(Node::is_element) {
            let tag = n.tag_name().name();
            match tag {
                "page" => self.collect(n, out, arcs, ids)?,
                "arc" => arcs.push(n),
                "place" | "transition" => {
                    let id = self.id(n)?;
                    let is_place = tag == "place";
                    let index = if is_place { out.places.len() } else { out.transitions.len() };
                    if let Some((_, _, first)) = ids.insert(id, (is_place, index, self.line(n))) {
                        return Err(self.syntax(n, format!("duplicate id '{id}' (first on line {first})")));
                    }
                    if is_place {
                        let initial = match self.label(n, "initialMarking")? {
                            Some((text, at)) => self.number(at, "initial marking", text, 0)?,
                            None => 0,
                        };
                        out.places.push(Place { id: id.to_owned(), initial });
                    } else {
                        out.transitions.push(Transition { id: id.to_owned(), ..Transition::default() });
                    }
                }
                "referencePlace" | "referenceTransition" => {
                    return Err(ParseError::unsupported(
                        self.path,
                        self.line(n),
                        format!("<{tag} id=\"{}\"> (reference nodes)", n.attribute("id").unwrap_or("")),
                    ));
                }
                // Names, graphics, tool-specific data and other annotations carry no semantics here.
                _ => {}
            }
        }
        Ok(())
    }

    fn id<'d>(&self, n: Node<'d, 'i>) -> Result<&'d str, ParseError> {
        match n.attribute("id") {
            Some(id) if !id.trim().is_empty() => Ok(id),
            _ => Err(self.syntax(n, format!("<{}> without an id", n.tag_name().name()))),
        }
    }

    /// The value of label `name` of `n` (its `<text>` or `<value>` child) and the node to blame.
    fn label<'d>(&self, n: Node<'d, 'i>, name: &str) -> Result<Option<(&'d str, Node<'d, 'i>)>, ParseError> {
        let Some(label) = n.children().find(|c| c.has_tag_name_local(name)) else { return Ok(None) };
        let value = label.children().find(|c| c.has_tag_name_local("text") || c.has_tag_name_local("value"));
        match value {
            Some(v) => Ok(Some((v.text().unwrap_or("").trim(), v))),
            None => Err(self.syntax(label, format!("<{name}> without <text>"))),
        }
    }

    /// `text` as a token count of at least `min`: a number, or PIPE's `Default,N`.
    fn number(&self, at: Node, what: &str, text: &str, min: u32) -> Result<u32, ParseError> {
        let digits = match text.split_once(',') {
            Some(("Default", n)) => n.trim(),
            Some(_) => {
                return Err(ParseError::unsupported(
                    self.path,
                    self.line(at),
                    format!("{what} '{text}' (token classes other than Default)"),
                ))
            }
            None => text,
        };
        match digits.parse::<u32>() {
            Ok(n) if (min..=MAX_TOKENS).contains(&n) => Ok(n),
            _ => Err(self.syntax(at, format!("{what} '{text}' is not a number from {min} to {MAX_TOKENS}"))),
        }
    }

    fn arc(
        &self,
        n: Node,
        ids: &HashMap<&str, (bool, usize, usize)>,
        out: &mut Net,
    ) -> Result<(), ParseError> {
        let end = |attr: &str| -> Result<(bool, usize), ParseError> {
            let Some(name) = n.attribute(attr) else {
                return Err(self.syntax(n, format!("<arc> without a {attr}")));
            };
            ids.get(name)
                .map(|&(place, index, _)| (place, index))
                .ok_or_else(|| self.syntax(n, format!("arc {attr} '{name}' is no place or transition")))
        };
        let (source, target) = (end("source")?, end("target")?);
        let kind =
            match n.children().find(|c| c.has_tag_name_local("type")).and_then(|t| t.attribute("value")) {
                None | Some("normal") => ArcKind::Input,
                Some("inhibitor") => ArcKind::Inhibitor,
                Some(other) => {
                    return Err(ParseError::unsupported(
                        self.path,
                        self.line(n),
                        format!("<type value=\"{other}\"> arcs"),
                    ))
                }
            };
        let weight = match self.label(n, "inscription")? {
            Some((text, at)) => self.number(at, "arc weight", text, 1)?,
            None => 1,
        };
        let (place, transition, kind) = match (source, target, kind) {
            ((true, p), (false, t), k) => (p, t, k),
            ((false, t), (true, p), ArcKind::Input) => (p, t, ArcKind::Output),
            ((false, _), (true, _), _) => {
                return Err(self.syntax(n, "an inhibitor arc goes from a place to a transition"))
            }
            _ => return Err(self.syntax(n, "an arc joins a place and a transition")),
        };
        let t = &mut out.transitions[transition];
        let list = match kind {
            ArcKind::Input => &mut t.inputs,
            ArcKind::Output => &mut t.outputs,
            ArcKind::Inhibitor => &mut t.inhibitors,
        };
        match list.binary_search_by_key(&place, |&(p, _)| p) {
            Ok(_) => {
                Err(self.syntax(n, format!("a second arc between '{}' and '{}'", out.places[place].id, t.id)))
            }
            Err(at) => {
                list.insert(at, (place, weight));
                Ok(())
            }
        }
    }
}

/// `has_tag_name` by local name only, whatever the namespace.
trait LocalName {
    fn has_tag_name_local(&self, name: &str) -> bool;
}

impl LocalName for Node<'_, '_> {
    fn has_tag_name_local(&self, name: &str) -> bool {
        self.is_element() && self.tag_name().name() == name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Net, String> {
        read_pnml_bytes(Path::new("n.pnml"), text.as_bytes()).map_err(|e| e.to_string())
    }

    const STANDARD: &str = r#"<?xml version="1.0"?>
<pnml xmlns="http://www.pnml.org/version-2009/grammar/pnml">
  <net id="n" type="http://www.pnml.org/version-2009/grammar/ptnet">
    <page id="pg">
      <place id="a"><name><text>A</text></name><initialMarking><text>2</text></initialMarking></place>
      <place id="b"/>
      <transition id="t"/>
      <arc id="1" source="a" target="t"><inscription><text>2</text></inscription></arc>
      <arc id="2" source="t" target="b"/>
    </page>
  </net>
</pnml>"#;

    #[test]
    fn a_standard_net_reads_with_weights_and_markings() {
        let n = read(STANDARD).unwrap();
        assert_eq!(n.initial_marking(), vec![2, 0]);
        assert_eq!(n.transitions[0].inputs, vec![(0, 2)]);
        assert_eq!(n.transitions[0].outputs, vec![(1, 1)]);
    }

    #[test]
    fn pipe_values_and_inhibitor_arcs_read() {
        let pipe = r#"<pnml><net id="x" type="P/T net">
<place id="P0"><initialMarking><value>Default,1</value></initialMarking></place>
<transition id="T0"/>
<arc id="P0 to T0" source="P0" target="T0"><inscription><value>Default,1</value></inscription><type value="inhibitor"/></arc>
</net></pnml>"#;
        let n = read(pipe).unwrap();
        assert_eq!(n.transitions[0].inhibitors, vec![(0, 1)]);
        assert!(n.transitions[0].inputs.is_empty());
    }

    #[test]
    fn other_net_types_are_refused_naming_the_element() {
        let sym = STANDARD.replace("ptnet", "symmetricnet");
        assert_eq!(
            read(&sym).unwrap_err(),
            "n.pnml: line 3: unsupported: <net type=\"http://www.pnml.org/version-2009/grammar/symmetricnet\"> \
             (only place/transition nets)"
        );
    }
}
