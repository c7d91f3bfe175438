//! A project's Petri net at the simulation's current point: the marking the trace's events lead it to,
//! which transitions its marking enables and which the last step fired, and the net drawn by the same
//! layout as the automata ([`super::draw::render`]). Two kinds of project have a net:
//!
//! - **a sequence beside the interlocks** (`[net]` over plants and specifications, docs/petri-nets.md):
//!   each event sets its signal's edge ([`Interpretation::edges`]), and then the net fires, one
//!   transition at a time in net order, every transition the RTPN firing rule enables —
//!   [`crate::net::io_graph::enabled`], `codegen verify`'s rule, which the PLC program's token passing
//!   writes: state-, input- and output-enabled — until none is; the signals no automaton carries read as
//!   the PLC program reads them when nobody sets them (a `free` input false, a `fixed` one its value).
//!   Delays are left aside (the simulation has no clock), as `verify` leaves them. The places' actions
//!   not yet holding are the sequence's requests (what the program's `req_<event>` asks the interlocks).
//! - **a hybrid controller's plant net** (`[hybrid]`, docs/hybrid.md): the net is the plant, and each
//!   event fires the transition it labels ([`Labels::firing`], the firing the reachability graph — the
//!   plant automaton — is built from), so the marking is the plant's state.

use std::collections::BTreeSet;

use layout::std_shapes::shapes::ShapeKind;

use crate::model::{EventId, EventTable};
use crate::net::condition::Value;
use crate::net::interpretation::Interpretation;
use crate::net::io_graph::{self, Node as NetNode};
use crate::net::model::Marking;
use crate::net::reachability::Labels;

use super::draw::{self, Node};
use super::Sim;

/// How the net follows the closed loop's events; see the module documentation.
#[derive(Clone, Debug)]
pub enum Follow {
    /// A sequence: events set signals, transitions fire by the firing rule.
    Sequence,
    /// A hybrid controller's plant net: each event fires the transition it labels.
    Labels(Labels),
}

/// A project's net and how it follows the events.
#[derive(Clone, Debug)]
pub struct Net {
    /// The net with its interpretation; a sequence's free inputs read false (see the module docs).
    net: Interpretation,
    follow: Follow,
}

/// Where the net is after a trace.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Point {
    /// Tokens per place.
    pub marking: Marking,
    /// The carried signals' values (a sequence's; empty for a plant net).
    pub signals: Vec<bool>,
    /// The transitions the last step fired, in order (those fired before any event when the trace is
    /// empty).
    pub fired: Vec<usize>,
    /// Whether a step's firings stopped at [`Net::most_firings`] (a cycle the firing rule never leaves).
    pub cut: bool,
}

/// One place in [`Shown`].
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct PlaceShown {
    /// Its id in the PNML file.
    pub id: String,
    /// Its tokens now.
    pub tokens: u32,
}

/// One transition in [`Shown`].
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TransitionShown {
    /// Its id in the PNML file.
    pub id: String,
    /// The event it is labelled with (a plant net's), else `null`.
    pub event: Option<String>,
    /// Whether the marking enables it (its input places hold their arcs' tokens, its inhibitor places
    /// fewer): a sequence's transition so enabled waits for its condition or its actions' feedback.
    pub enabled: bool,
    /// Whether the last step fired it.
    pub fired: bool,
}

/// The net at the current point, as the API answers it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Shown {
    /// `sequence` or `plant`.
    pub kind: &'static str,
    /// The ids of the marked places, in place order.
    pub marked: Vec<String>,
    /// Every place with its tokens.
    pub places: Vec<PlaceShown>,
    /// Every transition.
    pub transitions: Vec<TransitionShown>,
    /// A sequence's requests: the events of the marked places' actions that do not hold yet.
    pub requested: Vec<String>,
    /// Whether the last step's firings were cut at the most a step fires.
    pub cut: bool,
    /// The net drawn (SVG), or why there is no drawing.
    pub svg: Result<String, String>,
}

impl Net {
    /// A sequence beside the interlocks (`[net]`), bound to the set's events.
    pub fn sequence(mut net: Interpretation) -> Net {
        for s in &mut net.signals {
            if !s.carried && s.initial == Value::Either {
                s.initial = Value::Is(false);
            }
        }
        Net { net, follow: Follow::Sequence }
    }

    /// A hybrid controller's plant net with its transitions' events.
    pub fn plant(net: Interpretation, labels: Labels) -> Net {
        Net { net, follow: Follow::Labels(labels) }
    }

    /// The most transitions one step fires: each transition twice (beyond that the firing rule goes
    /// round a cycle no event breaks).
    pub fn most_firings(&self) -> usize {
        2 * self.net.net.transitions.len()
    }

    /// The number of carried signals (they come first in the interpretation's signals).
    fn carried(&self) -> usize {
        self.net.signals.iter().take_while(|s| s.carried).count()
    }

    /// Fires, one at a time in net order, what the firing rule enables, appending to `point.fired`.
    fn settle(&self, point: &mut Point) {
        let mut node = NetNode {
            marking: std::mem::take(&mut point.marking),
            plant: Vec::new(),
            signals: std::mem::take(&mut point.signals),
        };
        let transitions = self.net.net.transitions.len();
        'firing: for _ in 0..self.most_firings() {
            for t in 0..transitions {
                if io_graph::enabled(&self.net, t, &node) {
                    // A place that would overflow stops the firing (a net verify calls unbounded).
                    let Some(next) = self.net.net.fire(t, &node.marking) else { break 'firing };
                    node.marking = next;
                    point.fired.push(t);
                    continue 'firing;
                }
            }
            point.marking = node.marking;
            point.signals = node.signals;
            return;
        }
        point.cut = true;
        point.marking = node.marking;
        point.signals = node.signals;
    }

    /// The net after `trace` (the closed loop's events from the initial state, named by `table`).
    pub fn replay(&self, trace: impl IntoIterator<Item = EventId>, table: &EventTable) -> Point {
        let carried = self.carried();
        let mut point = Point {
            marking: self.net.net.initial_marking(),
            signals: self.net.signals[..carried].iter().map(|s| s.initial == Value::Is(true)).collect(),
            fired: Vec::new(),
            cut: false,
        };
        if let Follow::Sequence = self.follow {
            self.settle(&mut point);
        }
        for e in trace {
            point.fired.clear();
            point.cut = false;
            match &self.follow {
                Follow::Labels(labels) => {
                    if let Some(t) = labels.firing(&self.net.net, &point.marking, table.name(e)) {
                        if let Some(next) = self.net.net.fire(t, &point.marking) {
                            point.marking = next;
                            point.fired.push(t);
                        }
                    }
                }
                Follow::Sequence => {
                    if let Some(&(s, value)) = self.net.edges.get(e.index()) {
                        if let Some(level) = point.signals.get_mut(s) {
                            *level = value;
                        }
                    }
                    self.settle(&mut point);
                }
            }
        }
        point
    }

    /// The events a sequence's marked places demand and whose signal does not have the value yet.
    fn requested(&self, point: &Point, table: &EventTable) -> Vec<String> {
        if let Follow::Labels(_) = self.follow {
            return Vec::new();
        }
        let mut out = BTreeSet::new();
        for (acts, _) in self.net.actions.iter().zip(&point.marking).filter(|(_, &k)| k > 0) {
            for &(s, value) in acts {
                if point.signals.get(s).is_some_and(|&now| now != value) {
                    if let Some(e) = self.net.event_for(s, value) {
                        out.insert(e);
                    }
                }
            }
        }
        out.into_iter().map(|e| table.name(e).to_owned()).collect()
    }

    /// The net at `sim`'s current point.
    pub fn shown(&self, sim: &Sim) -> Shown {
        let table = sim.set.events();
        let point = self.replay(sim.trace.iter().map(|s| s.event), table);
        let net = &self.net.net;
        let labels = match &self.follow {
            Follow::Labels(l) => Some(l),
            Follow::Sequence => None,
        };
        let transitions: Vec<TransitionShown> = net
            .transitions
            .iter()
            .enumerate()
            .map(|(t, tr)| TransitionShown {
                id: tr.id.clone(),
                event: labels.and_then(|l| l.events.get(t).cloned()),
                enabled: net.state_enabled(t, &point.marking),
                fired: point.fired.contains(&t),
            })
            .collect();
        Shown {
            kind: if labels.is_some() { "plant" } else { "sequence" },
            marked: net.marked(&point.marking),
            places: net
                .places
                .iter()
                .zip(&point.marking)
                .map(|(p, &tokens)| PlaceShown { id: p.id.clone(), tokens })
                .collect(),
            requested: self.requested(&point, table),
            cut: point.cut,
            svg: self.draw(&point, &transitions),
            transitions,
        }
    }

    /// The net drawn: places as circles (their tokens as dots, marked ones filled gold), transitions as
    /// boxes (labelled with their event, if any; those the marking enables outlined blue, those the
    /// last step fired filled green, their arcs green).
    fn draw(&self, point: &Point, transitions: &[TransitionShown]) -> Result<String, String> {
        let net = &self.net.net;
        let places = net.places.len();
        let mut nodes: Vec<Node> = net
            .places
            .iter()
            .zip(&point.marking)
            .map(|(p, &k)| {
                let tokens = match k {
                    0 => String::new(),
                    1 => " •".to_owned(),
                    k => format!(" •×{k}"),
                };
                let fill = if k > 0 { "gold" } else { "white" };
                let shape = ShapeKind::new_circle(&format!("{}{tokens}", draw::label(&p.id)));
                Node { shape, line: "black", width: 1, fill }
            })
            .collect();
        for t in transitions {
            let text = match &t.event {
                Some(e) => format!("{} {}", draw::label(&t.id), draw::label(e)),
                None => draw::label(&t.id),
            };
            let (line, width) = if t.enabled { ("blue", 3) } else { ("black", 1) };
            let fill = if t.fired { "palegreen" } else { "white" };
            nodes.push(Node { shape: ShapeKind::new_box(&text), line, width, fill });
        }
        let mut edges = Vec::new();
        for (t, tr) in net.transitions.iter().enumerate() {
            let fired = point.fired.contains(&t);
            let weight = |w: u32| if w == 1 { String::new() } else { w.to_string() };
            for &(p, w) in &tr.inputs {
                edges.push((p, places + t, weight(w), fired));
            }
            for &(p, w) in &tr.outputs {
                edges.push((places + t, p, weight(w), fired));
            }
            for &(p, w) in &tr.inhibitors {
                edges.push((p, places + t, format!("inhibits {w}"), false));
            }
        }
        draw::render(nodes, edges).ok_or_else(|| format!("the net {}: the layout failed", net.name))
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use serde_json::Value as Json;

    use super::*;
    use crate::config::NetSpec;
    use crate::manifest::Manifest;
    use crate::pack::PackSet;
    use crate::sim::api::handle;
    use crate::synth::{local_modular, Config};

    fn example(path: &str) -> Manifest {
        Manifest::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)).unwrap()
    }

    /// The station's third net (examples/station-rtpn/net3.toml) beside its local modular interlocks.
    fn station() -> Sim {
        let manifest = example("examples/station-rtpn/net3.toml");
        let models = manifest.read_automata().unwrap();
        let synthesised = local_modular(&models.plants, &models.specs, &Config::default()).unwrap();
        let supervisors = synthesised.supervisors.into_iter().map(|s| s.automaton).collect();
        let set = PackSet::new(models.plants, supervisors).unwrap();
        let spec: &NetSpec = manifest.net.as_ref().unwrap();
        let automata: Vec<_> = set.members().iter().map(|m| &m.automaton).collect();
        let net = crate::net::interpretation(spec, &manifest.file, &automata).unwrap();
        let sim = Sim::new(&manifest.name, set, manifest.runtime.clone()).unwrap();
        sim.with_net(Ok(Net::sequence(net)))
    }

    fn net_of(sim: &mut Sim) -> Json {
        let r = handle(sim, "GET", "/api/state?depth=1", "");
        assert_eq!(r.status, 200);
        let v: Json = serde_json::from_str(&r.body).unwrap();
        v["net"]["Ok"].clone()
    }

    fn strings(v: &Json) -> Vec<String> {
        v.as_array().unwrap().iter().map(|s| s.as_str().unwrap().to_owned()).collect()
    }

    /// The station's sequence follows the events a user steps: from its initial marking (p1, whose
    /// start condition holds, passes its token to p2 before any event) the requested `al1` fires t2
    /// and `al0` t5; the marking moves exactly on the steps the API says fired a transition; revert
    /// brings the marking back.
    #[test]
    fn the_station_sequence_moves_its_marking_with_the_requested_events() {
        let mut sim = station();
        let net = net_of(&mut sim);
        assert_eq!(net["kind"], "sequence");
        assert_eq!(strings(&net["marked"]), ["p2"], "{net}");
        let t1 = net["transitions"].as_array().unwrap().iter().find(|t| t["id"] == "t1").unwrap();
        assert_eq!(t1["fired"], true, "t1 fired before any event: {net}");
        assert_eq!(strings(&net["requested"]), ["al1"]);
        assert!(net["svg"]["Ok"].as_str().unwrap().contains("<svg"));
        // Follow the sequence's requests where the closed loop allows them, else let the plant move
        // (the sequence waits for a sensor): the marking moves exactly on the steps that fire.
        let mut markings = vec![strings(&net["marked"])];
        for _ in 0..12 {
            let requested = strings(&net_of(&mut sim)["requested"]);
            let events = sim.events();
            let next =
                requested.iter().find(|e| events.enabled.contains(e)).or(events.uncontrollable.first());
            let Some(event) = next.cloned() else { break };
            let r = handle(&mut sim, "POST", "/api/step", &format!(r#"{{"event": "{event}", "depth": 1}}"#));
            assert_eq!(r.status, 200, "{}", r.body);
            let net = net_of(&mut sim);
            let fired = net["transitions"].as_array().unwrap().iter().filter(|t| t["fired"] == true).count();
            let marked = strings(&net["marked"]);
            let moved = markings.last() != Some(&marked);
            assert_eq!(moved, fired > 0, "{event}: {fired} fired, marking {marked:?} after {markings:?}");
            if moved {
                markings.push(marked);
            }
        }
        assert!(markings.len() >= 3, "the sequence stopped early: {markings:?}");
        assert_eq!(
            (&markings[1], &markings[2]),
            (&vec!["p3".to_owned()], &vec!["p5".to_owned()]),
            "al1: t2, al0: t5"
        );
        handle(&mut sim, "POST", "/api/revert", r#"{"to": 0}"#);
        assert_eq!(strings(&net_of(&mut sim)["marked"]), ["p2"]);
    }

    /// A hybrid controller's plant net: the marking the events fire is the plant automaton's state
    /// (the reachability graph names its states by their marked places) at every point of a run.
    #[test]
    fn the_hybrid_plant_nets_marking_is_the_plant_state_along_a_run() {
        let manifest = example("examples/hybrid/hybrid.toml");
        let spec = manifest.net.as_ref().unwrap();
        let raw = crate::net::read_pnml(&manifest.resolve(spec.pnml.get_ref())).unwrap();
        // As the project binds a hybrid plant net: to no automaton's events (the net is the plant).
        let net = Interpretation::bind(spec, &manifest.file, raw, &EventTable::build([]).unwrap()).unwrap();
        let labels = Labels::bind(spec, manifest.hybrid.as_ref().unwrap(), &manifest.file, &net.net).unwrap();
        let graph = crate::net::reachability::reachability(&net.net, &labels, "G_line", 1000).unwrap();
        let set = PackSet::new(vec![graph], Vec::new()).unwrap();
        let mut sim =
            Sim::new("line", set, Default::default()).unwrap().with_net(Ok(Net::plant(net, labels)));
        for _ in 0..30 {
            let net = net_of(&mut sim);
            assert_eq!(net["kind"], "plant");
            assert_eq!(
                strings(&net["marked"]).join("."),
                sim.automata[0].states[sim.state()[0] as usize].name
            );
            handle(&mut sim, "POST", "/api/run", r#"{"events": 1, "depth": 1}"#);
        }
        assert_eq!(sim.trace.len(), 30);
    }
}
