//! The verdict on an IO-reachability graph (the seed paper's Definition 2) and its diagnosis.
//!
//! A net is nonblocking under supervision when (i) every transition labels some edge and (ii) the graph,
//! read as an automaton whose only marked node is the initial one, is nonblocking: from every node the
//! initial node can be reached again. A blocking verdict carries a shortest trace to a node that cannot
//! return, the places marked there, and the actions the admissible behaviour refuses there or in the
//! nearest node after it that has any (the seed's "the supervisor blocks `al`, the action of p7").

use std::collections::VecDeque;

use serde::Serialize;

use super::interpretation::Interpretation;
use super::io_graph::{IoGraph, Label};
use crate::model::{Composition, EventTable};

/// An action of a marked place that the admissible behaviour refuses.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Refused {
    /// The marked place whose action it is.
    pub place: String,
    /// The output signal.
    pub signal: String,
    /// The value the place sets.
    pub value: bool,
    /// The event that would set it.
    pub event: String,
    /// The automata that refuse the event there (supervisors, or plants).
    pub refused_by: Vec<String>,
}

/// The verdict and what supports it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Verdict {
    /// `"nonblocking"` or `"blocking"`.
    pub verdict: &'static str,
    /// Nodes of the graph.
    pub nodes: usize,
    /// Edges of the graph.
    pub edges: usize,
    /// Transitions that label no edge (condition (i) fails when this is not empty).
    pub dead_transitions: Vec<String>,
    /// Nodes from which the initial node cannot be reached.
    pub blocking_nodes: usize,
    /// A shortest trace (events and transitions) from the initial node to one that cannot return.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trace: Option<Vec<String>>,
    /// The places marked at the trace's end.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub marking: Option<Vec<String>>,
    /// The actions refused at the trace's end (or in the nearest node after it that has any).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refused: Option<Vec<Refused>>,
}

impl Verdict {
    /// Judges `graph`, the graph of `net` under `plant`.
    pub fn judge(graph: &IoGraph, net: &Interpretation, plant: &Composition, table: &EventTable) -> Verdict {
        let n = graph.nodes.len();
        let mut seen = vec![false; net.net.transitions.len()];
        for &(_, label, _) in &graph.edges {
            if let Label::Transition(t) = label {
                seen[t] = true;
            }
        }
        let dead_transitions: Vec<String> =
            seen.iter().zip(&net.net.transitions).filter(|(s, _)| !**s).map(|(_, t)| t.id.clone()).collect();
        let returns = returning(graph);
        let blocking_nodes = returns.iter().filter(|r| !**r).count();
        let mut v = Verdict {
            verdict: if dead_transitions.is_empty() && blocking_nodes == 0 {
                "nonblocking"
            } else {
                "blocking"
            },
            nodes: n,
            edges: graph.edges.len(),
            dead_transitions,
            blocking_nodes,
            trace: None,
            marking: None,
            refused: None,
        };
        if v.verdict == "nonblocking" {
            return v;
        }
        // Node ids are breadth-first, so the lowest that cannot return is one nearest to the initial node.
        let end = returns.iter().position(|r| !*r).unwrap_or(0);
        v.trace = Some(path(graph, end).into_iter().map(|l| label_name(net, table, l)).collect());
        v.marking = Some(net.net.marked(&graph.nodes[end].marking));
        let mut forward: Vec<Vec<u32>> = vec![Vec::new(); n];
        for &(from, _, to) in &graph.edges {
            forward[from as usize].push(to);
        }
        let refused = bfs_order(&forward, end)
            .into_iter()
            .map(|node| refused_at(graph, net, plant, table, node))
            .find(|r| !r.is_empty())
            .unwrap_or_default();
        v.refused = Some(refused);
        v
    }

    /// The verdict in one line per fact, for the terminal.
    pub fn text(&self) -> String {
        let mut out = format!("{}: {} nodes, {} edges\n", self.verdict, self.nodes, self.edges);
        if !self.dead_transitions.is_empty() {
            out += &format!("transitions that never fire: {}\n", self.dead_transitions.join(", "));
        }
        if self.blocking_nodes > 0 {
            out += &format!("{} nodes cannot return to the initial node\n", self.blocking_nodes);
        }
        if let (Some(trace), Some(marking)) = (&self.trace, &self.marking) {
            out += &format!("trace: {}\nmarked there: {}\n", trace.join(" "), marking.join(", "));
        }
        for r in self.refused.iter().flatten() {
            out += &format!(
                "{} refuses {} ({} = {}), the action of {}\n",
                r.refused_by.join(", "),
                r.event,
                r.signal,
                u8::from(r.value),
                r.place
            );
        }
        out
    }
}

/// Which nodes of `graph` can reach the initial node again.
pub fn returning(graph: &IoGraph) -> Vec<bool> {
    let mut back: Vec<Vec<u32>> = vec![Vec::new(); graph.nodes.len()];
    for &(from, _, to) in &graph.edges {
        back[to as usize].push(from);
    }
    let mut seen = vec![false; back.len()];
    let mut stack = vec![0];
    seen[0] = true;
    while let Some(n) = stack.pop() {
        for &m in &back[n] {
            if !std::mem::replace(&mut seen[m as usize], true) {
                stack.push(m as usize);
            }
        }
    }
    seen
}

/// Nodes reachable from `start` along `forward`, nearest first.
fn bfs_order(forward: &[Vec<u32>], start: usize) -> Vec<usize> {
    let mut seen = vec![false; forward.len()];
    let mut order = vec![start];
    let mut queue = VecDeque::from([start]);
    seen[start] = true;
    while let Some(n) = queue.pop_front() {
        for &m in &forward[n] {
            if !std::mem::replace(&mut seen[m as usize], true) {
                order.push(m as usize);
                queue.push_back(m as usize);
            }
        }
    }
    order
}

/// A shortest path of labels from node 0 to `end` (breadth-first parents).
fn path(graph: &IoGraph, end: usize) -> Vec<Label> {
    let n = graph.nodes.len();
    // Edges are grouped by source in increasing order: `start[k]..start[k + 1]` are node k's.
    let mut start = vec![0usize; n + 1];
    for &(from, _, _) in &graph.edges {
        start[from as usize + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut parent: Vec<Option<(usize, Label)>> = vec![None; n];
    let mut reached = vec![false; n];
    reached[0] = true;
    let mut queue = VecDeque::from([0usize]);
    while let Some(k) = queue.pop_front() {
        for &(_, label, to) in &graph.edges[start[k]..start[k + 1]] {
            if !std::mem::replace(&mut reached[to as usize], true) {
                parent[to as usize] = Some((k, label));
                queue.push_back(to as usize);
            }
        }
    }
    let mut labels = Vec::new();
    let mut cur = end;
    while let Some((from, label)) = parent[cur] {
        labels.push(label);
        cur = from;
    }
    labels.reverse();
    labels
}

/// The name of an edge label: the event's or the transition's.
pub fn label_name(net: &Interpretation, table: &EventTable, label: Label) -> String {
    match label {
        Label::Event(e) => table.name(e).to_owned(),
        Label::Transition(t) => net.net.transitions[t].id.clone(),
    }
}

/// The actions of the places marked in `node` that are not yet done and that H_a refuses there.
fn refused_at(
    graph: &IoGraph,
    net: &Interpretation,
    plant: &Composition,
    table: &EventTable,
    node: usize,
) -> Vec<Refused> {
    let n = &graph.nodes[node];
    let mut out = Vec::new();
    for (p, &k) in n.marking.iter().enumerate() {
        if k == 0 {
            continue;
        }
        for &(s, v) in &net.actions[p] {
            let Some(e) = net.event_for(s, v) else { continue };
            if n.signals.get(s) == Some(&v) || plant.allows(&n.plant, e) {
                continue;
            }
            out.push(Refused {
                place: net.net.places[p].id.clone(),
                signal: net.signals[s].name.clone(),
                value: v,
                event: table.name(e).to_owned(),
                refused_by: plant.refusers(&n.plant, e).into_iter().map(str::to_owned).collect(),
            });
        }
    }
    out
}
