//! Each automaton drawn as SVG by a layered layout (`layout-rs`, Graphviz's dot algorithm): the whole
//! automaton when small, else the neighbourhood of its current state to a depth the page can raise. The
//! current state is filled, states where a `check` finding occurs are outlined in red, and a supervisor's
//! transitions the trace has taken are drawn green.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use layout::backends::svg::SVGWriter;
use layout::core::base::Orientation;
use layout::core::color::Color;
use layout::core::style::{LineStyleKind, StyleAttr};
use layout::std_shapes::render::get_shape_size;
use layout::std_shapes::shapes::{Arrow, Element, LineEndKind, ShapeKind};
use layout::topo::layout::VisualGraph;

use super::Sim;

/// Automata with at most this many states are drawn whole.
pub const WHOLE: usize = 40;
/// Most states a neighbourhood shows, however deep.
pub const MOST: usize = 80;

/// What [`draw`] drew.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Drawing {
    /// The SVG document.
    pub svg: String,
    /// States shown.
    pub shown: usize,
    /// Whether states beyond the drawing exist (a neighbourhood): deeper shows more.
    pub partial: bool,
}

/// A label as the SVG may hold it: characters XML gives a meaning replaced, long names cut.
pub(super) fn label(text: &str) -> String {
    let mut out: String = text
        .chars()
        .map(|c| match c {
            '<' | '>' | '&' | '"' | '\'' => '_',
            c => c,
        })
        .take(28)
        .collect();
    if text.chars().count() > 28 {
        out.push('~');
    }
    out
}

/// The states of automaton `i` to show: all of them, or those within `depth` transitions (either way)
/// of `current`, at most [`MOST`], nearest first.
pub fn neighbourhood(sim: &Sim, i: usize, current: u32, depth: usize) -> (BTreeSet<u32>, bool) {
    let a = &sim.automata[i];
    if a.states.len() <= WHOLE {
        return ((0..a.states.len() as u32).collect(), false);
    }
    let mut near: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for t in &a.transitions {
        let (s, d) = (t.source.index() as u32, t.target.index() as u32);
        near.entry(s).or_default().push(d);
        near.entry(d).or_default().push(s);
    }
    let mut seen = BTreeSet::from([current]);
    let mut queue = VecDeque::from([(current, 0)]);
    while let Some((s, d)) = queue.pop_front() {
        if d == depth {
            continue;
        }
        for &n in near.get(&s).into_iter().flatten() {
            if seen.len() >= MOST {
                return (seen, true);
            }
            if seen.insert(n) {
                queue.push_back((n, d + 1));
            }
        }
    }
    let partial = seen.len() < a.states.len();
    (seen, partial)
}

/// Draws automaton `i` of `sim` around its current state to `depth`; an error when the layout fails.
pub fn draw(sim: &Sim, i: usize, depth: usize) -> Result<Drawing, String> {
    let a = &sim.automata[i];
    let current = sim.state()[i];
    let (shown, partial) = neighbourhood(sim, i, current, depth);
    let flagged: BTreeSet<&str> = match &sim.findings {
        Ok(found) => found
            .iter()
            .flat_map(|f| f.at.iter().filter(|(who, _)| *who == a.name).map(|(_, s)| s.as_str()))
            .collect(),
        Err(_) => BTreeSet::new(),
    };
    let covered = i.checked_sub(sim.plants).and_then(|s| sim.covered.get(s));
    let table = sim.set.events();
    // Transitions between shown states, grouped by (source, target, covered) into one labelled arrow.
    let mut arrows: BTreeMap<(u32, u32, bool), Vec<String>> = BTreeMap::new();
    for t in &a.transitions {
        let (s, d) = (t.source.index() as u32, t.target.index() as u32);
        if !(shown.contains(&s) && shown.contains(&d)) {
            continue;
        }
        let name = &a.events[t.event.index()].name;
        let global = table.id(name).map(|e| e.as_u32());
        let taken = covered.is_some_and(|c| global.is_some_and(|e| c.contains(&(s, e))));
        arrows.entry((s, d, taken)).or_default().push(label(name));
    }
    let index: BTreeMap<u32, usize> = shown.iter().enumerate().map(|(k, &s)| (s, k)).collect();
    let nodes: Vec<Node> = shown
        .iter()
        .map(|&s| {
            let state = &a.states[s as usize];
            let text = label(&state.name);
            let shape =
                if state.marked { ShapeKind::new_double_circle(&text) } else { ShapeKind::new_circle(&text) };
            let fill = if s == current { "gold" } else { "white" };
            let (line, width) = if flagged.contains(state.name.as_str()) { ("red", 3) } else { ("black", 1) };
            Node { shape, line, width, fill }
        })
        .collect();
    let edges = arrows
        .into_iter()
        .filter_map(|((s, d, taken), names)| {
            Some((*index.get(&s)?, *index.get(&d)?, names.join(", "), taken))
        })
        .collect();
    let layout = render(nodes, edges);
    let svg = layout.ok_or_else(|| format!("{}: the layout failed", a.name))?;
    Ok(Drawing { svg, shown: shown.len(), partial })
}

/// One node of a drawing: its shape and label, outline colour and width, and fill.
pub struct Node {
    /// The shape with its label.
    pub shape: ShapeKind,
    /// The outline's colour (a name `layout-rs` knows).
    pub line: &'static str,
    /// The outline's width.
    pub width: usize,
    /// The fill's colour.
    pub fill: &'static str,
}

/// Lays `nodes` and `edges` (from, to — indices into `nodes` — label, and whether drawn green: taken)
/// out top to bottom as SVG; `None` when the layout library fails (it panics on some inputs).
pub fn render(nodes: Vec<Node>, edges: Vec<(usize, usize, String, bool)>) -> Option<String> {
    let elements: Vec<Element> = nodes
        .into_iter()
        .map(|n| {
            let look = StyleAttr::new(Color::fast(n.line), n.width, Some(Color::fast(n.fill)), 0, 14);
            let size = get_shape_size(Orientation::TopToBottom, &n.shape, 14, true);
            Element::create(n.shape, look, Orientation::TopToBottom, size)
        })
        .collect();
    std::panic::catch_unwind(move || {
        let mut graph = VisualGraph::new(Orientation::TopToBottom);
        let handles: Vec<_> = elements.into_iter().map(|e| graph.add_node(e)).collect();
        for (from, to, text, taken) in edges {
            let (colour, width) = if taken { ("green", 3) } else { ("black", 1) };
            let look = StyleAttr::new(Color::fast(colour), width, None, 0, 12);
            let arrow = Arrow::new(
                LineEndKind::None,
                LineEndKind::Arrow,
                LineStyleKind::Normal,
                &text,
                &look,
                &None,
                &None,
            );
            if let (Some(&from), Some(&to)) = (handles.get(from), handles.get(to)) {
                graph.add_edge(arrow, from, to);
            }
        }
        let mut svg = SVGWriter::new();
        graph.do_it(false, false, false, &mut svg);
        svg.finalize()
    })
    .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_current_state_is_filled_and_taken_transitions_green() {
        let mut sim = crate::sim::tests::small();
        sim.step_named("start").unwrap();
        let s = sim.automata.iter().position(|a| a.name == "S").unwrap();
        let d = draw(&sim, s, 2).unwrap();
        assert_eq!((d.shown, d.partial), (2, false));
        assert!(d.svg.contains("<svg"), "{}", d.svg);
        assert!(d.svg.contains("used") && d.svg.contains("fresh"));
        assert!(d.svg.contains(&Color::fast("gold").to_web_color()));
        assert!(d.svg.contains(&Color::fast("green").to_web_color()));
    }

    #[test]
    fn labels_hold_no_markup() {
        assert_eq!(label("<a&b>"), "_a_b_");
        assert_eq!(label(&"x".repeat(40)).chars().count(), 29);
    }
}
