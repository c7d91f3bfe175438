//! Reads the EFA parts of a Supremica `.wmod` module: `<VariableComponent>`s and the
//! `<GuardActionBlock>`s on edges, whose guards and actions Supremica writes as expression trees
//! (`<BinaryExpression Operator="…">`, `<UnaryExpression>`, `<SimpleIdentifier>`, `<IntConstant>`).
//! The tree fixes the precedence, so the `Text` attribute (the same expression as the user typed it) is
//! not read.

use std::collections::HashMap;
use std::path::Path;

use roxmltree::{Document, Node};

use super::expr::{Action, AssignOp, BinaryOp, Expr, UnaryOp};
use super::{Component, Edge, Efa, Variable};
use crate::formats::wmod_graph::{attr, element, graph};
use crate::formats::{xml, ParseError};
use crate::model::ModelError;

/// The most values one variable's range may hold.
pub const MAX_RANGE: i64 = 1 << 16;

/// The elements of guards, actions and variables, which a plain module has none of.
pub(crate) const ELEMENTS: [&str; 10] = [
    "VariableComponent",
    "VariableRange",
    "VariableInitial",
    "VariableMarking",
    "GuardActionBlock",
    "Guards",
    "Actions",
    "BinaryExpression",
    "UnaryExpression",
    "IntConstant",
];

/// Reads the module rooted at `root` (its events and propositions already read) as an [`Efa`].
pub(crate) fn read(
    file: &Path,
    doc: &Document,
    root: Node,
    events: &[(&str, bool)],
    propositions: &[&str],
) -> Result<Efa, ParseError> {
    let mut efa = Efa { events: events.iter().map(|&(n, c)| (n.to_owned(), c)).collect(), ..Efa::default() };
    let decls: Vec<Node> = root.descendants().filter(|n| n.has_tag_name("VariableComponent")).collect();
    let mut names: HashMap<&str, usize> = HashMap::new();
    for &d in &decls {
        let name = attr(file, doc, d, "Name")?;
        if names.insert(name, names.len()).is_some() {
            return Err(ParseError::syntax(file, xml::line(doc, d), format!("second variable '{name}'")));
        }
    }
    let r = Reader { file, doc, vars: &names };
    for &d in &decls {
        efa.variables.push(r.variable(d)?);
    }
    for c in root.descendants().filter(|n| n.has_tag_name("SimpleComponent")) {
        let g = graph(file, doc, c, events, propositions)?;
        if names.contains_key(g.name) {
            return Err(ParseError::syntax(
                file,
                xml::line(doc, c),
                format!("component '{}' has the name of a variable", g.name),
            ));
        }
        let at = xml::line(doc, c);
        let index = |name: &str| events.iter().position(|(e, _)| *e == name);
        let alphabet = g.alphabet.iter().filter_map(|(name, _, _)| index(name)).collect();
        let mut states = Vec::with_capacity(g.nodes.len());
        let mut by_name: HashMap<&str, usize> = HashMap::new();
        let mut initial = None;
        for &(name, marked, is_initial, line) in &g.nodes {
            if by_name.insert(name, states.len()).is_some() {
                return Err(ParseError::model(file, Some(line), ModelError::DuplicateState(name.into())));
            }
            if is_initial {
                if let Some(first) = initial.replace(states.len()) {
                    let first: &(String, bool) = &states[first];
                    return Err(ParseError::syntax(
                        file,
                        line,
                        format!("second initial state '{name}' (the first is '{}')", first.0),
                    ));
                }
            }
            states.push((name.to_owned(), marked));
        }
        if !states.is_empty() && initial.is_none() {
            return Err(ParseError::model(file, Some(at), ModelError::MissingInitial(g.name.into())));
        }
        let mut edges = Vec::with_capacity(g.edges.len());
        for (e, line, source, target, labels) in &g.edges {
            let state = |name: &str| {
                by_name.get(name).copied().ok_or_else(|| {
                    ParseError::model(file, Some(*line), ModelError::UnknownState(name.into()))
                })
            };
            let mut edge = Edge {
                source: state(source)?,
                target: state(target)?,
                events: labels.iter().filter_map(|(name, _)| index(name)).collect(),
                guards: vec![],
                actions: vec![],
                line: *line,
            };
            for block in e.children().filter(|n| n.has_tag_name("GuardActionBlock")) {
                for part in block.children().filter(Node::is_element) {
                    let exprs = part.children().filter(Node::is_element);
                    match part.tag_name().name() {
                        "Guards" => {
                            for g in exprs {
                                edge.guards.push(r.expr(g)?);
                            }
                        }
                        "Actions" => {
                            for a in exprs {
                                edge.actions.push(r.action(a)?);
                            }
                        }
                        _ => {}
                    }
                }
            }
            edges.push(edge);
        }
        efa.components.push(Component {
            name: g.name.to_owned(),
            kind: g.kind,
            alphabet,
            states,
            initial,
            edges,
            line: at,
        });
    }
    Ok(efa)
}

/// What reading an expression needs: the file and document for messages, the variables by name.
struct Reader<'r, 'i> {
    file: &'r Path,
    doc: &'r Document<'i>,
    vars: &'r HashMap<&'r str, usize>,
}

impl Reader<'_, '_> {
    fn unsupported(&self, n: Node, what: impl std::fmt::Display) -> ParseError {
        ParseError::unsupported(self.file, xml::line(self.doc, n), format!("{}: {what}", element(n)))
    }

    /// The element children of `n`, which must be `count`.
    fn operands<'a, 'i>(&self, n: Node<'a, 'i>, count: usize) -> Result<Vec<Node<'a, 'i>>, ParseError> {
        let ops: Vec<Node> = n.children().filter(Node::is_element).collect();
        if ops.len() != count {
            return Err(ParseError::syntax(
                self.file,
                xml::line(self.doc, n),
                format!("{} has {} operands, expected {count}", element(n), ops.len()),
            ));
        }
        Ok(ops)
    }

    /// An expression tree.
    fn expr(&self, n: Node) -> Result<Expr, ParseError> {
        let op = || n.attribute("Operator").unwrap_or("");
        match n.tag_name().name() {
            "IntConstant" => {
                let value = attr(self.file, self.doc, n, "Value")?;
                value.trim().parse().map(Expr::Int).map_err(|_| {
                    ParseError::syntax(
                        self.file,
                        xml::line(self.doc, n),
                        format!("<IntConstant> value '{value}' is not a 64-bit integer"),
                    )
                })
            }
            "SimpleIdentifier" => {
                let name = attr(self.file, self.doc, n, "Name")?;
                match self.vars.get(name) {
                    Some(&v) => Ok(Expr::Var(v)),
                    None => Err(self.unsupported(
                        n,
                        format!(
                            "'{name}' is not a variable of this module (constants, enumeration values \
                             and events in expressions are not supported)"
                        ),
                    )),
                }
            }
            "UnaryExpression" => {
                let unary = match op() {
                    "!" => UnaryOp::Not,
                    "-" => UnaryOp::Neg,
                    other => return Err(self.unsupported(n, format!("operator '{other}'"))),
                };
                let e = self.operands(n, 1)?[0];
                Ok(Expr::Unary(unary, Box::new(self.expr(e)?)))
            }
            "BinaryExpression" => {
                let Some(binary) = BinaryOp::from_symbol(op()) else {
                    let what = if AssignOp::from_symbol(op()).is_some() {
                        format!("assignment '{}' where a value is expected", op())
                    } else {
                        format!("operator '{}'", op())
                    };
                    return Err(self.unsupported(n, what));
                };
                let ops = self.operands(n, 2)?;
                Ok(Expr::Binary(binary, Box::new(self.expr(ops[0])?), Box::new(self.expr(ops[1])?)))
            }
            _ => Err(self.unsupported(n, "not an expression this reader supports")),
        }
    }

    /// An action `var = e`, `var += e` or `var -= e`.
    fn action(&self, n: Node) -> Result<Action, ParseError> {
        let op = n.attribute("Operator").and_then(AssignOp::from_symbol);
        let (Some(op), true) = (op, n.has_tag_name("BinaryExpression")) else {
            return Err(self.unsupported(n, "an action must be 'x = e', 'x += e' or 'x -= e'"));
        };
        let ops = self.operands(n, 2)?;
        let Expr::Var(var) = self.expr(ops[0])? else {
            return Err(self.unsupported(n, "an action assigns a variable"));
        };
        Ok(Action { var, op, value: self.expr(ops[1])? })
    }

    /// A predicate that may read variable `var` only.
    fn predicate_of(&self, n: Node, var: usize, name: &str) -> Result<Expr, ParseError> {
        let e = self.expr(n)?;
        let mut other = None;
        e.visit_vars(&mut |v| {
            if v != var {
                other = Some(v);
            }
        });
        match other {
            None => Ok(e),
            Some(_) => Err(self.unsupported(n, format!("a predicate of '{name}' may read '{name}' only"))),
        }
    }

    /// A `<VariableComponent>`.
    fn variable(&self, d: Node) -> Result<Variable, ParseError> {
        let name = attr(self.file, self.doc, d, "Name")?;
        let var = self.vars[name];
        let line = xml::line(self.doc, d);
        let part = |tag: &str| d.children().find(|n| n.has_tag_name(tag));
        let missing =
            |tag: &str| ParseError::syntax(self.file, line, format!("variable '{name}' has no <{tag}>"));
        let range = part("VariableRange").ok_or_else(|| missing("VariableRange"))?;
        let range = range.children().find(Node::is_element).ok_or_else(|| missing("VariableRange"))?;
        if !(range.has_tag_name("BinaryExpression") && range.attribute("Operator") == Some("..")) {
            return Err(self.unsupported(
                range,
                format!(
                    "the range of '{name}' is not an integer range a..b (enumerations are not supported)"
                ),
            ));
        }
        let bounds = self.operands(range, 2)?;
        let bound = |n: Node| {
            self.expr(n).ok().and_then(|e| e.eval(&[]).filter(|_| !reads_any(&e))).ok_or_else(|| {
                self.unsupported(n, format!("the range of '{name}' is unbounded or not constant"))
            })
        };
        let (min, max) = (bound(bounds[0])?, bound(bounds[1])?);
        if min > max {
            return Err(self.unsupported(range, format!("the range {min}..{max} of '{name}' is empty")));
        }
        if max.checked_sub(min).is_none_or(|span| span >= MAX_RANGE) {
            return Err(self.unsupported(
                range,
                format!("the range {min}..{max} of '{name}' holds more than {MAX_RANGE} values"),
            ));
        }
        let init = part("VariableInitial").ok_or_else(|| missing("VariableInitial"))?;
        let init_expr = init.children().find(Node::is_element).ok_or_else(|| missing("VariableInitial"))?;
        let predicate = self.predicate_of(init_expr, var, name)?;
        let mut env = vec![0; self.vars.len()];
        let initial: Vec<i64> = (min..=max)
            .filter(|&x| {
                env[var] = x;
                predicate.holds(&env)
            })
            .take(2)
            .collect();
        let [initial] = initial[..] else {
            let what = if initial.is_empty() { "no value" } else { "several values" };
            return Err(self.unsupported(
                init,
                format!("the initial predicate of '{name}' holds for {what}; exactly one is supported"),
            ));
        };
        let mut marked: Option<Expr> = None;
        for m in d.children().filter(|n| n.has_tag_name("VariableMarking")) {
            let parts: Vec<Node> = m.children().filter(Node::is_element).collect();
            let [prop, pred] = parts[..] else {
                return Err(ParseError::syntax(
                    self.file,
                    xml::line(self.doc, m),
                    "<VariableMarking> holds a proposition and a predicate",
                ));
            };
            let prop_name = attr(self.file, self.doc, prop, "Name")?;
            if prop_name != ":accepting" {
                return Err(self.unsupported(
                    prop,
                    format!("marking proposition '{prop_name}' (only :accepting is supported)"),
                ));
            }
            let p = self.predicate_of(pred, var, name)?;
            marked = Some(match marked {
                None => p,
                Some(q) => Expr::Binary(BinaryOp::And, Box::new(q), Box::new(p)),
            });
        }
        Ok(Variable { name: name.to_owned(), min, max, initial, marked, line })
    }
}

fn reads_any(e: &Expr) -> bool {
    let mut any = false;
    e.visit_vars(&mut |_| any = true);
    any
}
