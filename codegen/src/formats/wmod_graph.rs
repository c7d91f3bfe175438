//! A `.wmod` component's graph as written — role, alphabet, nodes and edges, checked against the module's
//! declarations — and the element helpers its readers share: the plain reader ([`super::wmod`]) builds an
//! automaton from it, the EFA reader ([`super::efa`]) unfolds it with the module's variables.

use std::collections::HashMap;
use std::path::Path;

use roxmltree::{Document, Node};

use super::xml;
use super::ParseError;
use crate::model::Kind;

/// The marking proposition.
pub(super) const ACCEPTING: &str = ":accepting";

/// A component's graph as written: role, alphabet, nodes and edges, checked against the module's
/// declarations but not yet built (plain and EFA components share it).
pub(super) struct Graph<'a, 'i> {
    /// The component's name.
    pub name: &'a str,
    /// Its role.
    pub kind: Kind,
    /// Its alphabet in declaration order: name, controllable, line first used.
    pub alphabet: Vec<(&'a str, bool, usize)>,
    /// Its nodes: name, marked, initial, line.
    pub nodes: Vec<(&'a str, bool, bool, usize)>,
    /// Its edges: the element, its line, source and target names, and the events labelling it with
    /// their lines.
    pub edges: Vec<GraphEdge<'a, 'i>>,
}

/// An edge as written: the element, its line, source and target names, and its events with their lines.
pub(super) type GraphEdge<'a, 'i> = (Node<'a, 'i>, usize, &'a str, &'a str, Vec<(&'a str, usize)>);

/// Reads the graph of `<SimpleComponent>` `c`.
pub(super) fn graph<'a, 'i>(
    file: &Path,
    doc: &'a Document<'i>,
    c: Node<'a, 'i>,
    events: &[(&'a str, bool)],
    propositions: &[&str],
) -> Result<Graph<'a, 'i>, ParseError> {
    let line = |n: Node| xml::line(doc, n);
    let kind = match attr(file, doc, c, "Kind")? {
        "PLANT" => Kind::Plant,
        "SPEC" => Kind::Spec,
        "SUPERVISOR" => Kind::Supervisor,
        other => {
            return Err(ParseError::unsupported(
                file,
                line(c),
                format!("{}: component kind {other}", element(c)),
            ))
        }
    };
    let mut g =
        Graph { name: attr(file, doc, c, "Name")?, kind, alphabet: vec![], nodes: vec![], edges: vec![] };
    let Some(graph) = c.children().find(|n| n.has_tag_name("Graph")) else { return Ok(g) };
    let labels = |parent| labels(file, doc, parent);
    let nodes = children(graph, "NodeList", "SimpleNode");
    let edges = children(graph, "EdgeList", "Edge");

    // The alphabet: events on edges and blocked events, in declaration order.
    let mut used: HashMap<&str, usize> = HashMap::new();
    let mut accepting_in_alphabet = false;
    for (name, at) in edges
        .iter()
        .map(|&e| labels(e))
        .chain([labels(graph)])
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .flatten()
    {
        if name == ACCEPTING {
            accepting_in_alphabet = true;
        } else if !events.iter().any(|(e, _)| *e == name) {
            return Err(ParseError::syntax(
                file,
                at,
                format!("event '{name}' is not declared in <EventDeclList>"),
            ));
        } else {
            used.entry(name).or_insert(at);
        }
    }
    for &(name, controllable) in events {
        if let Some(&at) = used.get(name) {
            g.alphabet.push((name, controllable, at));
        }
    }

    let mut any_accepting = accepting_in_alphabet;
    for &n in &nodes {
        let mut marked = false;
        for p in n
            .children()
            .filter(|e| e.has_tag_name("EventList"))
            .flat_map(|l| l.children())
            .filter(Node::is_element)
        {
            let name = attr(file, doc, p, "Name")?;
            if name != ACCEPTING {
                let what =
                    if propositions.contains(&name) { "proposition" } else { "undeclared proposition" };
                return Err(ParseError::unsupported(
                    file,
                    line(p),
                    format!("{what} '{name}' on node (only {ACCEPTING} is supported)"),
                ));
            }
            marked = true;
        }
        any_accepting |= marked;
        let initial = n.attribute("Initial") == Some("true");
        g.nodes.push((attr(file, doc, n, "Name")?, marked, initial, line(n)));
    }
    if !any_accepting {
        g.nodes.iter_mut().for_each(|n| n.1 = true);
    }
    for &e in &edges {
        let names = labels(e)?;
        if let Some((_, at)) = names.iter().find(|(name, _)| *name == ACCEPTING) {
            return Err(ParseError::syntax(file, *at, format!("proposition {ACCEPTING} labels an edge")));
        }
        g.edges.push((e, line(e), attr(file, doc, e, "Source")?, attr(file, doc, e, "Target")?, names));
    }
    Ok(g)
}

/// The `item` children of `parent`'s `list` children (`<NodeList><SimpleNode/>…`).
fn children<'a, 'i>(parent: Node<'a, 'i>, list: &str, item: &str) -> Vec<Node<'a, 'i>> {
    let items = parent.children().filter(|n| n.has_tag_name(list)).flat_map(|l| l.children());
    items.filter(|n| n.has_tag_name(item)).collect()
}

/// The names (and lines) in `parent`'s `<LabelBlock>`.
fn labels<'a>(
    file: &Path,
    doc: &Document,
    parent: Node<'a, '_>,
) -> Result<Vec<(&'a str, usize)>, ParseError> {
    children(parent, "LabelBlock", "SimpleIdentifier")
        .into_iter()
        .map(|s| Ok((attr(file, doc, s, "Name")?, xml::line(doc, s))))
        .collect()
}

/// `<Tag Name="...">` for messages.
pub(super) fn element(n: Node) -> String {
    match n.attribute("Name") {
        Some(name) => format!("<{} Name=\"{name}\">", n.tag_name().name()),
        None => format!("<{}>", n.tag_name().name()),
    }
}

/// The attribute `name` of `n`, or an error naming the element and its line.
pub(super) fn attr<'a>(
    file: &Path,
    doc: &Document,
    n: Node<'a, '_>,
    name: &str,
) -> Result<&'a str, ParseError> {
    n.attribute(name).ok_or_else(|| {
        ParseError::syntax(
            file,
            xml::line(doc, n),
            format!("<{}> has no '{name}' attribute", n.tag_name().name()),
        )
    })
}
