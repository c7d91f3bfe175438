//! The IO-reachability graph in Graphviz: a node per (marking, state, signals), labelled with its marked
//! places; the initial node doubled, nodes that cannot return to it red; net transitions bold.

use std::fmt::Write;

use super::interpretation::Interpretation;
use super::io_graph::{IoGraph, Label};
use super::verdict::label_name;
use crate::model::EventTable;

/// `graph` (of `net`, events named by `table`) as a DOT digraph; `blocking[k]` marks node k red.
pub fn write(graph: &IoGraph, net: &Interpretation, table: &EventTable, blocking: &[bool]) -> String {
    let mut out =
        String::from("digraph io_reachability {\n  rankdir=LR;\n  node [shape=circle, fontsize=10];\n");
    for (k, node) in graph.nodes.iter().enumerate() {
        let marked = net.net.marked(&node.marking).join(",");
        let shape = if k == 0 { ", shape=doublecircle" } else { "" };
        let color = if blocking.get(k).copied().unwrap_or(false) { ", color=red" } else { "" };
        let _ = writeln!(out, "  n{k} [label=\"{k}\\n{marked}\"{shape}{color}];");
    }
    for &(from, label, to) in &graph.edges {
        let style = if matches!(label, Label::Transition(_)) { ", style=bold" } else { "" };
        let _ = writeln!(out, "  n{from} -> n{to} [label=\"{}\"{style}];", label_name(net, table, label));
    }
    out.push_str("}\n");
    out
}
