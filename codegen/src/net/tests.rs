//! The IO-reachability graph and its verdict against a brute-force reference on small random nets and
//! plants: the reference follows the seed paper's definitions word by word on names and maps (every event
//! of the alphabet tried against every automaton's transition list, every valuation of the free signals
//! enumerated), sharing no code with the graph but the condition parser.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use proptest::prelude::*;

use super::condition::Expr;
use super::model::{Net, Place, Transition};
use super::{Interpretation, IoGraph, Limits, Verdict};
use crate::manifest::Manifest;
use crate::model::{Automaton, Composition, EventTable, Kind, StateId};

/// Events of the random plants: edges of the output `a` and the input `s`.
const EVENTS: [&str; 4] = ["a1", "a0", "s1", "s0"];
/// Conditions drawn from (over the carried input `s`, the free `f` and the fixed-true `x`).
const CONDITIONS: [&str; 8] =
    ["TRUE", "s", "NOT s", "f", "s AND f", "NOT f AND s", "x AND NOT s", "f AND NOT f"];

/// A reference node: marking, each automaton's state, carried signal values by name.
type State = (Vec<u32>, Vec<usize>, BTreeMap<String, bool>);

/// Labelled edges between reference nodes.
type Edges = BTreeSet<(State, String, State)>;

/// Per place, its actions: (0 for `a`, 1 for `lamp`; the value).
type Actions = Vec<Vec<(usize, u8)>>;

/// A random deterministic automaton over some of [`EVENTS`], every state marked.
fn plant(name: &'static str) -> impl Strategy<Value = Automaton> {
    (1usize..4, prop::collection::vec((0usize..4, 0usize..4, 0usize..4), 0..10)).prop_map(move |(n, rows)| {
        let mut a = Automaton::new(name, Kind::Plant);
        for s in 0..n {
            a.add_state(s.to_string(), true).unwrap();
        }
        a.initial = Some(StateId::new(0).unwrap());
        for e in EVENTS {
            a.add_event(e, e.starts_with('a')).unwrap();
        }
        let mut taken = BTreeSet::new();
        for (s, e, t) in rows {
            if taken.insert((s % n, e)) {
                a.add_transition(
                    StateId::new(s % n).unwrap(),
                    a.event_id(EVENTS[e]).unwrap(),
                    StateId::new(t % n).unwrap(),
                );
            }
        }
        a.canonicalize();
        a
    })
}

/// A random net of three places and three transitions that never gains tokens (so it is bounded), with
/// conditions, and actions over `a` and the immediate output `lamp`.
fn net() -> impl Strategy<Value = (Net, Vec<usize>, Actions)> {
    let transition = (1u8..8, 0u8..8, 0u8..8, 0usize..CONDITIONS.len());
    (
        prop::collection::vec(0u32..2, 3),
        prop::collection::vec(transition, 3),
        prop::collection::vec(prop::collection::vec((0usize..2, 0u8..2), 0..2), 3),
    )
        .prop_map(|(initial, ts, actions)| {
            let places: Vec<Place> =
                initial.iter().enumerate().map(|(i, &k)| Place { id: format!("p{i}"), initial: k }).collect();
            let set = |bits: u8| -> Vec<(usize, u32)> {
                (0..3).filter(|p| bits >> p & 1 == 1).map(|p| (p, 1)).collect()
            };
            let mut conditions = Vec::new();
            let transitions = ts
                .iter()
                .enumerate()
                .map(|(i, &(ins, outs, inhibit, c))| {
                    conditions.push(c);
                    let inputs = set(ins);
                    let mut outputs = set(outs);
                    outputs.truncate(inputs.len());
                    let inhibitors = set(inhibit & !ins).into_iter().take(1).collect();
                    Transition { id: format!("t{i}"), inputs, outputs, inhibitors }
                })
                .collect();
            (Net { name: "n".into(), places, transitions }, conditions, actions)
        })
}

/// The `[net]` section for the random net.
fn manifest(conditions: &[usize], actions: &[Vec<(usize, u8)>]) -> Manifest {
    let mut text = String::from("name = \"r\"\n[net]\npnml = \"r.pnml\"\nfree = [\"f\"]\nfixed = { x = 1 }\noutputs = [\"lamp\"]\n[net.conditions]\n");
    for (t, &c) in conditions.iter().enumerate() {
        text += &format!("t{t} = \"{}\"\n", CONDITIONS[c]);
    }
    text += "[net.actions]\n";
    for (p, acts) in actions.iter().enumerate() {
        let sets: BTreeMap<&str, u8> = acts.iter().map(|&(s, v)| (["a", "lamp"][s], v)).collect();
        let body: Vec<String> = sets.iter().map(|(s, v)| format!("{s} = {v}")).collect();
        text += &format!("p{p} = {{ {} }}\n", body.join(", "));
    }
    Manifest::parse(Path::new("r.toml"), &text).unwrap()
}

/// The value of `e` under `value`, by the book.
fn eval(e: &Expr<String>, value: &dyn Fn(&str) -> bool) -> bool {
    match e {
        Expr::Const(b) => *b,
        Expr::Var(v) => value(v),
        Expr::Not(x) => !eval(x, value),
        Expr::And(xs) => xs.iter().all(|x| eval(x, value)),
        Expr::Or(xs) => xs.iter().any(|x| eval(x, value)),
    }
}

/// The reference graph: its node set, edge set (labels by name) and the nodes that return to the initial.
fn reference(
    net: &Net,
    conditions: &[usize],
    actions: &[Vec<(usize, u8)>],
    plants: &[Automaton],
) -> (BTreeSet<State>, Edges, BTreeSet<State>) {
    // Z(p) over names; only `a` is carried (the plants' events follow the name convention).
    let z: Vec<BTreeMap<&str, bool>> =
        actions.iter().map(|acts| acts.iter().map(|&(s, v)| (["a", "lamp"][s], v == 1)).collect()).collect();
    let ctrl: BTreeSet<String> =
        z.iter().flat_map(|m| m.iter().map(|(s, v)| format!("{s}{}", u8::from(*v)))).collect();
    let alphabet: BTreeSet<&str> =
        plants.iter().flat_map(|a| a.events.iter().map(|e| e.name.as_str())).collect();
    let carried: BTreeSet<String> = alphabet.iter().map(|e| e[..e.len() - 1].to_owned()).collect();
    let exprs: Vec<Expr<String>> = conditions.iter().map(|&c| Expr::parse(CONDITIONS[c]).unwrap()).collect();
    let step = |a: &Automaton, s: usize, e: &str| -> Option<Option<usize>> {
        let Some(id) = a.event_id(e) else { return Some(None) };
        a.transitions.iter().find(|t| t.source.index() == s && t.event == id).map(|t| Some(t.target.index()))
    };
    let initial: State = (
        net.places.iter().map(|p| p.initial).collect(),
        vec![0; plants.len()],
        carried.iter().map(|s| (s.clone(), false)).collect(),
    );
    let mut nodes = BTreeSet::from([initial.clone()]);
    let mut edges = BTreeSet::new();
    let mut todo = vec![initial.clone()];
    while let Some(n) = todo.pop() {
        let (m, x, v) = &n;
        let mut next: Vec<(String, State)> = Vec::new();
        for &e in &alphabet {
            let demanded = (0..net.places.len())
                .any(|p| m[p] > 0 && z[p].get(&e[..e.len() - 1]) == Some(&e.ends_with('1')));
            if ctrl.contains(e) && !demanded {
                continue;
            }
            let moves: Option<Vec<Option<usize>>> =
                plants.iter().zip(x).map(|(a, &s)| step(a, s, e)).collect();
            let Some(moves) = moves else { continue };
            let x2 = moves.iter().zip(x).map(|(t, &s)| t.unwrap_or(s)).collect();
            let mut v2 = v.clone();
            v2.insert(e[..e.len() - 1].to_owned(), e.ends_with('1'));
            next.push((e.to_owned(), (m.clone(), x2, v2)));
        }
        for (t, tr) in net.transitions.iter().enumerate() {
            let state =
                tr.inputs.iter().all(|&(p, w)| m[p] >= w) && tr.inhibitors.iter().all(|&(p, w)| m[p] < w);
            let input = [false, true].iter().any(|&f| {
                eval(&exprs[t], &|s: &str| match s {
                    "f" => f,
                    "x" => true,
                    s => v.get(s).copied().unwrap_or(false),
                })
            });
            let output = tr
                .inputs
                .iter()
                .all(|&(p, _)| z[p].iter().all(|(s, val)| !v.contains_key(*s) || v[*s] == *val));
            if state && input && output {
                let mut m2 = m.clone();
                tr.inputs.iter().for_each(|&(p, w)| m2[p] -= w);
                tr.outputs.iter().for_each(|&(p, w)| m2[p] += w);
                next.push((tr.id.clone(), (m2, x.clone(), v.clone())));
            }
        }
        for (label, to) in next {
            edges.insert((n.clone(), label, to.clone()));
            if nodes.insert(to.clone()) {
                todo.push(to);
            }
        }
    }
    let mut returns = BTreeSet::from([initial]);
    loop {
        let more: Vec<State> = edges
            .iter()
            .filter(|(f, _, t)| returns.contains(t) && !returns.contains(f))
            .map(|(f, _, _)| f.clone())
            .collect();
        if more.is_empty() {
            break;
        }
        returns.extend(more);
    }
    (nodes, edges, returns)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn the_graph_and_verdict_match_the_brute_force_reference(
        (n, conditions, actions) in net(),
        plants in prop::collection::vec(prop_oneof![plant("G1"), plant("G2")], 1..3),
    ) {
        let mut plants = plants;
        if plants.len() == 2 {
            plants[1].name = "G2".into();
            plants[0].name = "G1".into();
        }
        let m = manifest(&conditions, &actions);
        let table = EventTable::build(&plants).unwrap();
        let refs: Vec<&Automaton> = plants.iter().collect();
        let plant = Composition::new(&refs, &table).unwrap();
        let net = Interpretation::bind(m.net.as_ref().unwrap(), &m.file, n.clone(), &table).unwrap();
        let graph = IoGraph::build(&net, &plant, Limits { state_limit: 100_000, memory_limit: None }).unwrap();
        let as_state = |k: usize| -> State {
            let node = &graph.nodes[k];
            let signals = node.signals.iter().enumerate().map(|(i, &b)| (net.signals[i].name.clone(), b)).collect();
            (node.marking.clone(), node.plant.iter().map(|&s| s as usize).collect(), signals)
        };
        let (nodes, edges, returns) = reference(&n, &conditions, &actions, &plants);
        let got: BTreeSet<State> = (0..graph.nodes.len()).map(as_state).collect();
        prop_assert_eq!(got.len(), graph.nodes.len(), "no node twice");
        prop_assert_eq!(&got, &nodes);
        let got_edges: BTreeSet<_> = graph
            .edges
            .iter()
            .map(|&(f, l, t)| (as_state(f as usize), super::verdict::label_name(&net, &table, l), as_state(t as usize)))
            .collect();
        prop_assert_eq!(got_edges.len(), graph.edges.len(), "no edge twice");
        prop_assert_eq!(&got_edges, &edges);
        let v = Verdict::judge(&graph, &net, &plant, &table);
        let fired: BTreeSet<&str> = edges.iter().map(|(_, l, _)| l.as_str()).collect();
        let all_fire = n.transitions.iter().all(|t| fired.contains(t.id.as_str()));
        let expected = if all_fire && returns.len() == nodes.len() { "nonblocking" } else { "blocking" };
        prop_assert_eq!(v.verdict, expected);
        prop_assert_eq!(v.blocking_nodes, nodes.len() - returns.len());
        if let Some(trace) = &v.trace {
            // The trace replays in the reference graph to a node that cannot return, and none is nearer.
            let mut at = nodes.iter().find(|s| *s == &as_state(0)).unwrap().clone();
            for label in trace {
                let (_, _, to) = edges.iter().find(|(f, l, _)| *f == at && l == label).unwrap();
                at = to.clone();
            }
            if v.blocking_nodes > 0 {
                prop_assert!(!returns.contains(&at));
                prop_assert_eq!(v.marking.clone().unwrap(), n.marked(&at.0));
            }
        }
    }
}
