//! Supremica / Waters `.wmod` modules (also written by UltraDES and ESCET): one automaton per
//! `<SimpleComponent>`.
//!
//! Events come from `<EventDecl>` (`Kind` CONTROLLABLE or UNCONTROLLABLE; the PROPOSITION
//! `:accepting` marks states). A component's alphabet is the events on its edges plus those in the
//! graph's own `<LabelBlock>` (declared but blocked), in declaration order; its `Kind` (PLANT, SPEC,
//! SUPERVISOR) sets [`Kind`]. Nodes list their propositions in an `<EventList>`; a component that
//! mentions `:accepting` nowhere has every state marked (Supremica's rule).
//!
//! A module with variables (`<VariableComponent>`) or guards and actions (`<GuardActionBlock>`) is an
//! extended finite automaton: [`efa`] reads it and unfolds the variables into plain automata, exactly.
//! Parameters, constants, `foreach` blocks, instances, indexed names, group nodes and other
//! propositions change the meaning of the graph; they are refused with the element and its line,
//! never flattened silently. Layout elements are skipped.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use roxmltree::Node;

use super::builder::Builder;
use super::efa;
use super::wmod_graph::{attr, element, graph, Graph, ACCEPTING};
use super::xml::{self, escape};
use super::ParseError;
use crate::model::{Automaton, EventTable, Kind};

/// Elements that only draw the graph.
const LAYOUT: [&str; 11] = [
    "PointGeometry",
    "Point",
    "LabelGeometry",
    "SplineGeometry",
    "InitialArrowGeometry",
    "StartPointGeometry",
    "EndPointGeometry",
    "ColorGeometry",
    "Color",
    "BoxGeometry",
    "Box",
];

/// Elements of a plain module, with what they hold.
const PLAIN: [&str; 13] = [
    "Module",
    "Comment",
    "EventDeclList",
    "EventDecl",
    "ComponentList",
    "SimpleComponent",
    "Graph",
    "NodeList",
    "SimpleNode",
    "EdgeList",
    "Edge",
    "LabelBlock",
    "SimpleIdentifier",
];

/// Reads every `<SimpleComponent>` of a module from the text of a `.wmod` file (a module with variables
/// unfolded into plain automata, [`efa::unfold`]).
pub fn read(file: &Path, text: &str) -> Result<Vec<Automaton>, ParseError> {
    match parse(file, text)? {
        Module::Plain(automata) => Ok(automata),
        Module::Efa(efa) => efa::unfold(file, &efa),
    }
}

/// The variables, guards and actions of a module with variables, as written (not unfolded); `None` for
/// a plain module. What the PLC program's guards over the variables are built from.
pub fn read_efa(file: &Path, text: &str) -> Result<Option<efa::Efa>, ParseError> {
    match parse(file, text)? {
        Module::Plain(_) => Ok(None),
        Module::Efa(efa) => Ok(Some(efa)),
    }
}

/// A module as read: plain automata, or an extended finite automaton before unfolding.
enum Module {
    Plain(Vec<Automaton>),
    Efa(efa::Efa),
}

fn parse(file: &Path, text: &str) -> Result<Module, ParseError> {
    let doc = xml::parse(file, text)?;
    let root = doc.root_element();
    let line = |n: Node| xml::line(&doc, n);
    if root.tag_name().name() != "Module" {
        return Err(ParseError::syntax(
            file,
            line(root),
            format!("expected a <Module> root element, found <{}>", root.tag_name().name()),
        ));
    }
    for n in root.descendants().filter(Node::is_element) {
        let name = n.tag_name().name();
        let known = PLAIN.contains(&name) || LAYOUT.contains(&name) || efa::wmod::ELEMENTS.contains(&name);
        if !known && name != "EventList" {
            return Err(ParseError::unsupported(file, line(n), format!("{} ({})", element(n), why(name))));
        }
    }
    let mut events: Vec<(&str, bool)> = Vec::new();
    let mut propositions: Vec<&str> = Vec::new();
    for d in root.descendants().filter(|n| n.has_tag_name("EventDecl")) {
        let name = attr(file, &doc, d, "Name")?;
        match attr(file, &doc, d, "Kind")? {
            "CONTROLLABLE" => events.push((name, true)),
            "UNCONTROLLABLE" => events.push((name, false)),
            "PROPOSITION" => propositions.push(name),
            kind => {
                return Err(ParseError::unsupported(
                    file,
                    line(d),
                    format!("{}: event kind {kind}", element(d)),
                ));
            }
        }
    }
    let mut automata = Vec::new();
    let efa =
        root.descendants().any(|n| n.has_tag_name("VariableComponent") || n.has_tag_name("GuardActionBlock"));
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for c in root.descendants().filter(|n| n.has_tag_name("SimpleComponent")) {
        let name = attr(file, &doc, c, "Name")?;
        if name.trim().is_empty() {
            return Err(ParseError::syntax(file, line(c), format!("{} has an empty name", element(c))));
        }
        if let Some(first) = seen.insert(name, line(c)) {
            return Err(ParseError::syntax(
                file,
                line(c),
                format!("second component '{name}' (first on line {first})"),
            ));
        }
        if !efa {
            automata.push(component(file, graph(file, &doc, c, &events, &propositions)?)?);
        }
    }
    if efa {
        return efa::wmod::read(file, &doc, root, &events, &propositions).map(Module::Efa);
    }
    Ok(Module::Plain(automata))
}

fn component(file: &Path, g: Graph) -> Result<Automaton, ParseError> {
    let mut b = Builder::new(file, g.name, g.kind);
    for &(name, controllable, at) in &g.alphabet {
        b.event(name, controllable, at)?;
    }
    for &(name, marked, initial, at) in &g.nodes {
        let s = b.state(name, marked, at)?;
        if initial {
            b.initial(s, at)?;
        }
    }
    for &(_, at, source, target, ref names) in &g.edges {
        let source = b.state_named(source, at)?;
        let target = b.state_named(target, at)?;
        for &(name, label_at) in names {
            let event = b.event_named(name, label_at)?;
            b.transition(source, event, target, label_at);
        }
    }
    b.finish()
}

/// Why an element is refused.
fn why(tag: &str) -> &'static str {
    match tag {
        "ForeachComponent" | "ForeachEvent" => "foreach blocks",
        "Instance" | "ParameterBinding" | "ParameterList" | "SimpleParameter" | "EventParameter"
        | "IntParameter" => "parameters and module instances",
        "ConstantAliasList" | "ConstantAlias" | "ConstantAliasExpression" => "constants",
        "IndexedIdentifier" | "QualifiedIdentifier" => "indexed or qualified names",
        "GroupNode" => "group nodes",
        _ => "not a plain automaton element; this reader takes flat modules only",
    }
}

/// Writes `automata` as one module called `module`: every event declared once, one component each
/// (kind unknown is written as PLANT), `:accepting` on marked nodes.
///
/// Events in an alphabet but on no edge go into the graph's own label block, and an automaton without
/// marked states lists `:accepting` there, so that reading the module back gives the same automata.
/// Fails when one event is controllable in one automaton and uncontrollable in another, or two
/// automata share a name.
pub fn write(module: &str, automata: &[Automaton]) -> Result<String, String> {
    let table = EventTable::build(automata).map_err(|e| e.to_string())?;
    let mut names = std::collections::HashSet::new();
    if let Some(a) = automata.iter().find(|a| !names.insert(a.name.as_str())) {
        return Err(format!("two automata are called '{}'", a.name));
    }
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        "<Module xmlns=\"http://waters.sourceforge.net/xsd/module\" xmlns:B=\"http://waters.sourceforge.net/xsd/base\" Name=\"{}\">",
        escape(module)
    );
    out.push_str("<EventDeclList>\n");
    let _ = writeln!(out, "<EventDecl Kind=\"PROPOSITION\" Name=\"{ACCEPTING}\"/>");
    for id in table.ids() {
        let kind = if table.is_controllable(id) { "CONTROLLABLE" } else { "UNCONTROLLABLE" };
        let _ = writeln!(out, "<EventDecl Kind=\"{kind}\" Name=\"{}\"/>", escape(table.name(id)));
    }
    out.push_str("</EventDeclList>\n<ComponentList>\n");
    for a in automata {
        component_xml(&mut out, a);
    }
    out.push_str("</ComponentList>\n</Module>\n");
    Ok(out)
}

fn component_xml(out: &mut String, a: &Automaton) {
    let kind = match a.kind {
        Kind::Spec => "SPEC",
        Kind::Supervisor => "SUPERVISOR",
        Kind::Plant | Kind::Unknown => "PLANT",
    };
    let _ = writeln!(out, "<SimpleComponent Kind=\"{kind}\" Name=\"{}\">\n<Graph>", escape(&a.name));
    let mut on_edge = vec![false; a.events.len()];
    a.transitions.iter().for_each(|t| on_edge[t.event.index()] = true);
    let mut blocked: Vec<&str> =
        a.events.iter().zip(&on_edge).filter(|(_, &u)| !u).map(|(e, _)| e.name.as_str()).collect();
    if !a.states.is_empty() && a.marked_count() == 0 {
        blocked.push(ACCEPTING);
    }
    if !blocked.is_empty() {
        out.push_str("<LabelBlock>\n");
        for name in blocked {
            let _ = writeln!(out, "<SimpleIdentifier Name=\"{}\"/>", escape(name));
        }
        out.push_str("</LabelBlock>\n");
    }
    out.push_str("<NodeList>\n");
    for (i, s) in a.states.iter().enumerate() {
        let initial = if a.initial.is_some_and(|x| x.index() == i) { " Initial=\"true\"" } else { "" };
        let _ = write!(out, "<SimpleNode{initial} Name=\"{}\"", escape(&s.name));
        if s.marked {
            let _ = writeln!(
                out,
                ">\n<EventList>\n<SimpleIdentifier Name=\"{ACCEPTING}\"/>\n</EventList>\n</SimpleNode>"
            );
        } else {
            out.push_str("/>\n");
        }
    }
    out.push_str("</NodeList>\n<EdgeList>\n");
    for t in &a.transitions {
        let _ = writeln!(
            out,
            "<Edge Source=\"{}\" Target=\"{}\">\n<LabelBlock>\n<SimpleIdentifier Name=\"{}\"/>\n</LabelBlock>\n</Edge>",
            escape(&a.states[t.source.index()].name),
            escape(&a.states[t.target.index()].name),
            escape(&a.events[t.event.index()].name)
        );
    }
    out.push_str("</EdgeList>\n</Graph>\n</SimpleComponent>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    fn module(components: &str) -> String {
        format!(
            r#"<?xml version="1.0" encoding="UTF-8"?>
<Module xmlns="http://waters.sourceforge.net/xsd/module" Name="m">
<EventDeclList>
<EventDecl Kind="PROPOSITION" Name=":accepting"/>
<EventDecl Kind="CONTROLLABLE" Name="go"/>
<EventDecl Kind="UNCONTROLLABLE" Name="done"/>
</EventDeclList>
<ComponentList>{components}</ComponentList>
</Module>"#
        )
    }

    const MACHINE: &str = r#"
<SimpleComponent Kind="SPEC" Name="M"><Graph><NodeList>
<SimpleNode Initial="true" Name="idle"/><SimpleNode Name="busy"/>
</NodeList><EdgeList>
<Edge Source="idle" Target="busy"><LabelBlock><SimpleIdentifier Name="go"/></LabelBlock></Edge>
<Edge Source="busy" Target="idle"><LabelBlock><SimpleIdentifier Name="done"/></LabelBlock></Edge>
</EdgeList></Graph></SimpleComponent>"#;

    #[test]
    fn component_without_accepting_has_every_state_marked() {
        let a = read(Path::new("m.wmod"), &module(MACHINE)).unwrap();
        assert_eq!(a.len(), 1);
        assert_eq!((a[0].name.as_str(), a[0].kind, a[0].marked_count()), ("M", Kind::Spec, 2));
        assert!(a[0].events[a[0].event_id("go").unwrap().index()].controllable);
    }

    #[test]
    fn accepting_on_one_node_marks_only_that_node() {
        let text = module(&MACHINE.replace(
            r#"<SimpleNode Name="busy"/>"#,
            r#"<SimpleNode Name="busy"><EventList><SimpleIdentifier Name=":accepting"/></EventList></SimpleNode>"#,
        ));
        let a = read(Path::new("m.wmod"), &text).unwrap().remove(0);
        assert_eq!(a.states.iter().map(|s| s.marked).collect::<Vec<_>>(), [false, true]);
    }

    #[test]
    fn unsupported_guard_operators_are_refused_by_element_and_line() {
        let text = module(&MACHINE.replace(
            "<LabelBlock><SimpleIdentifier Name=\"go\"/></LabelBlock>",
            "<LabelBlock><SimpleIdentifier Name=\"go\"/></LabelBlock>\n<GuardActionBlock><Guards>\
             <BinaryExpression Operator=\"^\"><IntConstant Value=\"1\"/><IntConstant Value=\"1\"/>\
             </BinaryExpression></Guards></GuardActionBlock>",
        ));
        let msg = read(Path::new("m.wmod"), &text).unwrap_err().to_string();
        assert_eq!(msg, "m.wmod: line 13: unsupported: <BinaryExpression>: operator '^'");
    }

    #[test]
    fn write_then_read_keeps_unmarked_automata_and_unused_events() {
        let mut a = read(Path::new("m.wmod"), &module(MACHINE)).unwrap().remove(0);
        a.states.iter_mut().for_each(|s| s.marked = false);
        a.add_event("spare", true).unwrap();
        let back = read(Path::new("m.wmod"), &write("m", std::slice::from_ref(&a)).unwrap()).unwrap();
        assert_eq!(back, [a]);
    }
}
