//! Graphviz DOT output (write only), drawn the way the textbooks draw automata.
//!
//! States are circles labelled with their names, marked states double circles, and the initial state
//! has an arrow coming from nowhere. Controllable transitions are solid with a bar across the tail of
//! the arrow (the textbook "tick"); uncontrollable ones are dashed; those of an automaton whose file says
//! nothing of controllability (a libFAUDES generator without `+C+`) are dotted, the automaton's label
//! saying so. Several automata go into one graph, one box (cluster) each.

use std::fmt::Write as _;

use crate::model::Automaton;

/// One DOT graph drawing every automaton of `automata`.
pub fn write(automata: &[Automaton]) -> String {
    let mut out = String::from("digraph automata {\n\trankdir=LR;\n\tnode [shape=circle];\n");
    let clustered = automata.len() > 1;
    for (i, a) in automata.iter().enumerate() {
        let indent = if clustered { "\t\t" } else { "\t" };
        let unsaid = if a.controllability_unsaid { " (controllability unsaid)" } else { "" };
        if clustered {
            let _ = writeln!(out, "\tsubgraph cluster_{i} {{\n\t\tlabel=\"{}{unsaid}\";", quote(&a.name));
        } else {
            let _ = writeln!(out, "\tlabel=\"{}{unsaid}\";", quote(&a.name));
        }
        if let Some(init) = a.initial {
            let _ = writeln!(out, "{indent}a{i}_init [shape=point, style=invis];");
            let _ = writeln!(out, "{indent}a{i}_init -> a{i}_s{init};");
        }
        for (j, s) in a.states.iter().enumerate() {
            let shape = if s.marked { ", shape=doublecircle" } else { "" };
            let _ = writeln!(out, "{indent}a{i}_s{j} [label=\"{}\"{shape}];", quote(&s.name));
        }
        for t in &a.transitions {
            let e = &a.events[t.event.index()];
            let style = match (a.controllability_unsaid, e.controllable) {
                (true, _) => "style=dotted",
                (false, true) => "dir=both, arrowtail=tee",
                (false, false) => "style=dashed",
            };
            let _ = writeln!(
                out,
                "{indent}a{i}_s{} -> a{i}_s{} [label=\"{}\", {style}];",
                t.source,
                t.target,
                quote(&e.name)
            );
        }
        if clustered {
            out.push_str("\t}\n");
        }
    }
    out.push_str("}\n");
    out
}

/// `s` escaped for a DOT double-quoted string.
fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '"' | '\\' => {
                out.push('\\');
                out.push(c);
            }
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Kind;

    #[test]
    fn draws_initial_marked_and_controllability() {
        let mut a = Automaton::new("G\"1", Kind::Plant);
        let s0 = a.add_state("idle", true).unwrap();
        let s1 = a.add_state("busy", false).unwrap();
        let go = a.add_event("go", true).unwrap();
        let done = a.add_event("done", false).unwrap();
        a.initial = Some(s0);
        a.add_transition(s0, go, s1);
        a.add_transition(s1, done, s0);
        let dot = write(&[a]);
        assert!(dot.contains("label=\"G\\\"1\";"), "{dot}");
        assert!(dot.contains("a0_init -> a0_s0;"));
        assert!(dot.contains("a0_s0 [label=\"idle\", shape=doublecircle];"));
        assert!(dot.contains("a0_s1 [label=\"busy\"];"));
        assert!(dot.contains("a0_s0 -> a0_s1 [label=\"go\", dir=both, arrowtail=tee];"));
        assert!(dot.contains("a0_s1 -> a0_s0 [label=\"done\", style=dashed];"));
    }
}
