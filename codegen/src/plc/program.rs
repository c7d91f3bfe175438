//! The builder of the function block (plants, supervisors and interface in one scan) and of the
//! program that instantiates it, as ST syntax trees.
//!
//! Each scan (design notes §8), in the order of the body's sections:
//!
//! 1. `init` — on the first scan and while `reset`: initial states, inputs' previous values, counters.
//! 2. `inputs` — every input sampled once; an edge against the previous scan latches its event
//!    (`pend_*`). An edge while another event is latched or arrived in the same scan is counted in
//!    `simultaneous`; an edge of an event still latched is lost and counted in `overflows`.
//! 3. `events` — this scan's event flags cleared; the latched event of lowest id, if any, becomes this
//!    scan's uncontrollable event. So several edges in one scan are applied one per scan, in id order.
//! 4. `faults` (bits) — an automaton holding the event with no transition for it: `unexpected`.
//! 5. `aeem-set`, `transitions` — the uncontrollable event applied once to every automaton holding it.
//! 6. `enabled` — per controllable event, whether every holder allows it (a pulsed output must also be
//!    low, so every command shows as a rising edge).
//! 7. `choice` — unless `hold` or the safe state: one event by the policy; dropped (and counted in
//!    `guard_redecisions`) when the guard is on and an uncontrollable event arrived or is latched.
//! 8. `aeem-set`, `transitions` — the chosen event applied once.
//! 9. `aeem-reset` — every memory bit cleared.
//! 10. `outputs` — set, clear, pulse countdown; all off in the safe state.
//!
//! A project of Supremica modules with variables keeps each variable it can as an `INT`, updated by its
//! events' actions in a `variables` section after each `transitions` section, and a controllable
//! event's rung tests the supervisors' guard over the variables instead of their states where their
//! enablement is a function of the variables ([`super::guards`]).
//!
//! In the bits encoding the `aeem-set`, `transitions` and `aeem-reset` sections are built as Ladder
//! Diagram rungs and printed as their ST statements; with `--avalanche aeem` the program keeps those
//! rungs, after one for the initial states, as its ladder ([`Program::rungs`]), which the XML carries
//! beside the ST.

use std::ops::Not as _;

use crate::config::OnFault;
use crate::model::{EventId, StateId};
use crate::pack::{PackSet, Role};

use super::avalanche::{plan, Avalanche, Method, Plan};
use super::choice::{self, PlantChoice};
use super::guards::{self, Guards};
use super::io::{IoMap, Source};
use super::{Encoding, PlcError, PlcOptions};
use crate::config::{Action, Edge, ScanPolicy};
use crate::scan::ir::{Expr, Op, Pou, Section, Stmt, Type, Var, VarClass};
use crate::scan::ld::{Coil, CoilKind, Element, Rung};
use crate::scan::names::{sanitize, stem, Names};

/// The sections of the seed documents' structure (initialisation, AEEM set, transitions, AEEM reset),
/// which the report counts apart.
pub const SEED_STRUCTURE: [&str; 4] = [INIT, AEEM_SET, TRANSITIONS, AEEM_RESET];
const INIT: &str = "init";
const AEEM_SET: &str = "aeem-set";
const TRANSITIONS: &str = "transitions";
const AEEM_RESET: &str = "aeem-reset";

/// The counters the function block outputs, in the link's STATUS order where they have one.
pub const COUNTERS: [&str; 6] =
    ["events_in", "commands_out", "unexpected", "overflows", "guard_redecisions", "simultaneous"];

/// The POUs and what the report says about them.
#[derive(Clone, Debug)]
pub struct Program {
    /// The `EVENTS` structure type: name and members (absent when every uncontrollable event is mapped).
    pub events_type: Option<(String, Vec<Var>)>,
    /// The function block.
    pub fb: Pou,
    /// The program instantiating it.
    pub main: Pou,
    /// The I/O map.
    pub io: IoMap,
    /// Per automaton and avalanche event, how it is eliminated.
    pub avalanche: Vec<(String, EventId, Method)>,
    /// The AEEM memory bits.
    pub memory_bits: Vec<String>,
    /// The supervisors' ladder (bits with `--avalanche aeem`, the form of the seed documents): the rungs
    /// of the seed structure in the order the block runs them — the initial states (the state part of
    /// `init`), per pass a set rung per memory bit and a rung per transition, a reset rung per bit at
    /// the end — whose ST is those sections' statements. Empty for the other forms.
    pub rungs: Vec<Rung>,
    /// Choice sites with a cursor (local queue).
    pub sites: usize,
    /// Per controllable event, its request input (`req_<event>`), when the options ask for requests.
    pub requests: Vec<(EventId, String)>,
    /// Per `[[timers]]` entry: its timeout event and its `TON` instance (a local of the block), whose
    /// `Q` rises when the timeout falls due.
    pub timers: Vec<(EventId, String)>,
    /// The modules' variables kept as integers and the guards over them (empty without variables).
    pub guards: Guards,
}

/// Identifiers of one automaton.
struct Aut {
    /// `st_<A>` (int) or the `X_<A>_` prefix (bits).
    name: String,
    /// Per state, its `(global event, target)` transitions by increasing event.
    out: Vec<Vec<(EventId, StateId)>>,
    /// Its alphabet, global ids in increasing order.
    alphabet: Vec<EventId>,
    /// The statement plans of the two passes (uncontrollable, controllable).
    plans: [Plan; 2],
}

struct Builder<'a> {
    set: &'a PackSet,
    opts: &'a PlcOptions,
    io: IoMap,
    ev: Vec<String>,
    pend: Vec<String>,
    prev: Vec<String>,
    auts: Vec<Aut>,
    /// AEEM bits: (name, automaton, event).
    bits: Vec<(String, usize, EventId)>,
    /// Pulse counters per pulsed output (by output index).
    pulse: Vec<Option<String>>,
    /// Per controllable event, its request input when the options ask for requests.
    req: Vec<(EventId, String)>,
    /// The `[[timers]]` of the options whose events the set has.
    timers: Vec<Timer>,
    /// The modules' variables kept and the guards over them.
    guards: Guards,
    /// Per kept variable, its identifier.
    vars: Vec<String>,
}

/// A `[[timers]]` entry in the program: a running flag its start events set and its stop events and
/// timeout clear, a `TON` on that flag whose output's rising edge is the timeout event.
struct Timer {
    /// The running flag.
    run: String,
    /// The `TON` instance.
    ton: String,
    /// Its delay.
    ms: u32,
    /// Events that (re)start it.
    start: Vec<EventId>,
    /// Events that stop it.
    stop: Vec<EventId>,
    /// The event it raises.
    timeout: EventId,
}

impl Timer {
    /// `ton(IN := input, PT := T#<ms>ms);`
    fn call(&self, input: Expr) -> Stmt {
        Stmt::Call(self.ton.clone(), vec![("IN".into(), input), ("PT".into(), Expr::Time(self.ms))])
    }
}

/// Builds the program for `set` with `opts`.
pub fn build(set: &PackSet, opts: &PlcOptions) -> Result<Program, PlcError> {
    let events = set.events();
    let mut names = Names::default();
    for fixed in ["ready", "reset", "hold", "guard", "fired", "pending", "safe", "busy", "arrived", "EVENTS"]
        .iter()
        .chain(&COUNTERS)
        .chain(&choice::VARIABLES)
        .chain(&["sct"])
    {
        names.reserve(fixed);
    }
    let mut io = IoMap::new(&opts.spec, events, &mut names, opts.require_outputs)?;
    let mut timers = Vec::new();
    for t in &opts.timers {
        // The manifest made every one of the timer's events an event of its plant automaton.
        let ids = |names: &[String]| names.iter().filter_map(|n| events.id(n)).collect::<Vec<_>>();
        let Some(timeout) = events.id(&t.timeout_event()) else { continue };
        // The timer, not an input, is the timeout's source.
        io.sources.remove(&timeout);
        timers.push(Timer {
            run: names.fresh("run", &t.name),
            ton: names.fresh("tmr", &t.name),
            ms: t.ms,
            start: ids(&t.start),
            stop: ids(&t.stop),
            timeout,
        });
    }
    let n = events.len();
    if n == 0 {
        return Err(PlcError::Empty);
    }
    let per_event = |names: &mut Names, prefix: &str| -> Vec<String> {
        events.ids().map(|e| names.fresh(prefix, events.name(e))).collect()
    };
    let ev = per_event(&mut names, "ev");
    let pend = per_event(&mut names, "pend");
    let prev = per_event(&mut names, "prev");
    let mut auts = Vec::new();
    let mut bits = Vec::new();
    for (a, m) in set.members().iter().enumerate() {
        let name = match opts.encoding {
            Encoding::Int => names.fresh("st", m.name()),
            Encoding::Bits => {
                let base = names.fresh("X", m.name());
                for s in 0..m.state_count() {
                    if !names.reserve(&format!("{base}_{s}")) {
                        return Err(PlcError::Duplicate(format!("{base}_{s}")));
                    }
                }
                base
            }
        };
        let option = match opts.encoding {
            Encoding::Int => Avalanche::None,
            Encoding::Bits => opts.avalanche,
        };
        let out: Vec<Vec<(EventId, StateId)>> = (0..m.state_count()).map(|s| m.out(s).collect()).collect();
        let pass = |controllable: bool| {
            plan(&out, &|e: EventId| events.is_controllable(e) == controllable, option).map_err(|u| {
                PlcError::Unorderable {
                    automaton: m.name().to_owned(),
                    event: events.name(u.event).to_owned(),
                    conflict: u.conflict,
                }
            })
        };
        let plans = [pass(false)?, pass(true)?];
        for p in &plans {
            for (&e, &method) in &p.methods {
                if method == Method::Aeem {
                    bits.push((names.fresh(&format!("m_{}", sanitize(m.name())), events.name(e)), a, e));
                }
            }
        }
        auts.push(Aut { name, out, alphabet: m.alphabet(), plans });
    }
    let pulse = io.outputs.iter().map(|o| o.pulsed().then(|| names.fresh("pt", &o.variable))).collect();
    let req = if opts.requests {
        events
            .ids()
            .filter(|&e| events.is_controllable(e))
            .map(|e| (e, names.fresh("req", events.name(e))))
            .collect()
    } else {
        Vec::new()
    };
    let guards = guards::extract(set, &opts.efa);
    let vars = guards.variables.iter().map(|v| names.plain(&v.declared.name)).collect();
    let b = Builder { set, opts, io, ev, pend, prev, auts, bits, pulse, req, timers, guards, vars };
    b.check_owned()?;
    Ok(b.finish())
}

impl Builder<'_> {
    fn events(&self) -> &crate::model::EventTable {
        self.set.events()
    }

    fn uncontrollable(&self) -> Vec<EventId> {
        self.events().ids().filter(|&e| !self.events().is_controllable(e)).collect()
    }

    fn controllable(&self) -> Vec<EventId> {
        self.events().ids().filter(|&e| self.events().is_controllable(e)).collect()
    }

    fn holders(&self, e: EventId) -> impl Iterator<Item = usize> + '_ {
        self.auts
            .iter()
            .enumerate()
            .filter(move |(_, x)| x.alphabet.binary_search(&e).is_ok())
            .map(|(a, _)| a)
    }

    /// Every controllable event must be generated by a plant (as the firmware requires).
    fn check_owned(&self) -> Result<(), PlcError> {
        for c in self.controllable() {
            let plants = self.set.members().iter().zip(&self.auts).filter(|(m, _)| m.role == Role::Plant);
            if !plants.into_iter().any(|(_, x)| x.alphabet.binary_search(&c).is_ok()) {
                return Err(PlcError::Unowned(self.events().name(c).to_owned()));
            }
        }
        Ok(())
    }

    fn state_var(&self, a: usize, s: usize) -> String {
        format!("{}_{s}", self.auts[a].name)
    }

    /// Automaton `a` is in state `s`.
    fn at(&self, a: usize, s: usize) -> Expr {
        match self.opts.encoding {
            Encoding::Int => Expr::var(&self.auts[a].name).op(Op::Eq, Expr::Int(s as i64)),
            Encoding::Bits => Expr::var(self.state_var(a, s)),
        }
    }

    /// Automaton `a` is in one of the states that have a transition on `e`.
    fn allows(&self, a: usize, e: EventId) -> Expr {
        let out = &self.auts[a].out;
        let states = (0..out.len()).filter(|&s| out[s].iter().any(|&(x, _)| x == e));
        Expr::fold(states.map(|s| self.at(a, s)), Op::Or, Expr::Bool(false))
    }

    /// A fault: the counter incremented, and the safe state entered under `on_fault = safe-state`.
    fn fault(&self, counter: &str) -> Vec<Stmt> {
        let mut out = vec![Stmt::incr(counter)];
        if self.opts.on_fault == OnFault::SafeState {
            out.push(Stmt::set("safe", Expr::Bool(true)));
        }
        out
    }

    fn source(&self, e: EventId) -> (Expr, Edge) {
        if let Some(t) = self.timers.iter().find(|t| t.timeout == e) {
            return (Expr::var(format!("{}.Q", t.ton)), Edge::Rising);
        }
        match &self.io.sources[&e] {
            Source::Input { variable, edge, .. } => (Expr::var(variable), *edge),
            Source::Member(m) => (Expr::var(format!("EVENTS.{m}")), Edge::Rising),
        }
    }

    fn init(&self) -> Vec<Stmt> {
        let mut body = Vec::new();
        for (a, m) in self.set.members().iter().enumerate() {
            let initial = m.initial().index();
            match self.opts.encoding {
                Encoding::Int => body.push(Stmt::set(&self.auts[a].name, Expr::Int(initial as i64))),
                Encoding::Bits => {
                    for s in 0..m.state_count() {
                        body.push(Stmt::set(self.state_var(a, s), Expr::Bool(s == initial)));
                    }
                }
            }
        }
        for (v, name) in self.guards.variables.iter().zip(&self.vars) {
            body.push(Stmt::set(name, Expr::Int(v.declared.initial)));
        }
        for u in self.uncontrollable() {
            body.push(Stmt::set(&self.pend[u.index()], Expr::Bool(false)));
            body.push(Stmt::set(&self.prev[u.index()], self.source(u).0));
        }
        for (bit, ..) in &self.bits {
            body.push(Stmt::set(bit, Expr::Bool(false)));
        }
        for (o, pt) in self.io.outputs.iter().zip(&self.pulse) {
            body.push(Stmt::set(&o.variable, Expr::Bool(false)));
            if let Some(pt) = pt {
                body.push(Stmt::set(pt, Expr::Int(0)));
            }
        }
        for t in &self.timers {
            body.push(Stmt::set(&t.run, Expr::Bool(false)));
            body.push(t.call(Expr::Bool(false)));
        }
        for c in COUNTERS {
            body.push(Stmt::set(c, Expr::Int(0)));
        }
        body.push(Stmt::set("safe", Expr::Bool(false)));
        body.push(Stmt::set("pending", Expr::Bool(false)));
        match self.opts.policy {
            _ if self.controllable().is_empty() => {}
            ScanPolicy::First => {}
            ScanPolicy::GlobalQueue => body.push(Stmt::set("gq", Expr::Int(0))),
            ScanPolicy::LocalQueue => {
                body.push(Stmt::set("pc", Expr::Int(0)));
                if self.sites().iter().any(|p| !p.sites.is_empty()) {
                    body.push(Stmt::For(
                        "i".into(),
                        0,
                        self.site_count() - 1,
                        vec![Stmt::Assign(Expr::at("sc", Expr::var("i")), Expr::Int(0))],
                    ));
                }
            }
            ScanPolicy::Random => body.push(Stmt::set("rng", Expr::Int(choice::minstd_seed(self.opts.seed)))),
        }
        body.push(Stmt::set("ready", Expr::Bool(true)));
        vec![Stmt::when(Expr::var("ready").not().op(Op::Or, Expr::var("reset")), body)]
    }

    fn inputs(&self) -> Vec<Stmt> {
        let us = self.uncontrollable();
        if us.is_empty() {
            return Vec::new();
        }
        let mut out = vec![Stmt::set(
            "busy",
            Expr::fold(us.iter().map(|u| Expr::var(&self.pend[u.index()])), Op::Or, Expr::Bool(false)),
        )];
        for u in us {
            let (x, edge) = self.source(u);
            let prev = Expr::var(&self.prev[u.index()]);
            let cond = match edge {
                Edge::Rising => x.clone().op(Op::And, prev.not()),
                Edge::Falling => x.clone().not().op(Op::And, prev),
                Edge::Both => x.clone().op(Op::Xor, prev),
            };
            let pend = &self.pend[u.index()];
            out.push(Stmt::when(
                cond,
                vec![
                    Stmt::when(Expr::var("busy"), vec![Stmt::incr("simultaneous")]),
                    Stmt::when(Expr::var(pend), self.fault("overflows")),
                    Stmt::set(pend, Expr::Bool(true)),
                    Stmt::set("busy", Expr::Bool(true)),
                ],
            ));
            out.push(Stmt::set(&self.prev[u.index()], x));
        }
        out
    }

    /// Each timer's `TON` called on its running flag, before the inputs are sampled: its output's edge
    /// is an input like the sensors'.
    fn timer_calls(&self) -> Vec<Stmt> {
        self.timers.iter().map(|t| t.call(Expr::var(&t.run))).collect()
    }

    /// After this scan's events: a stop or the timeout clears a timer's flag; a start resets its `TON`
    /// and sets the flag, so it counts its full delay from the next scan (a start while it runs
    /// restarts it).
    fn timer_updates(&self) -> Vec<Stmt> {
        let any = |events: &[EventId]| {
            Expr::fold(events.iter().map(|e| Expr::var(&self.ev[e.index()])), Op::Or, Expr::Bool(false))
        };
        let mut out = Vec::new();
        for t in &self.timers {
            let stops: Vec<EventId> = t.stop.iter().copied().chain([t.timeout]).collect();
            out.push(Stmt::when(any(&stops), vec![Stmt::set(&t.run, Expr::Bool(false))]));
            out.push(Stmt::when(
                any(&t.start),
                vec![t.call(Expr::Bool(false)), Stmt::set(&t.run, Expr::Bool(true))],
            ));
        }
        out
    }

    fn events_section(&self) -> Vec<Stmt> {
        let mut out: Vec<Stmt> = self.ev.iter().map(|v| Stmt::set(v, Expr::Bool(false))).collect();
        let us = self.uncontrollable();
        if us.is_empty() {
            return out;
        }
        out.push(Stmt::set("arrived", Expr::var("busy")));
        let arms = us
            .iter()
            .map(|u| {
                let (ev, pend) = (&self.ev[u.index()], &self.pend[u.index()]);
                (
                    Expr::var(pend),
                    vec![
                        Stmt::set(ev, Expr::Bool(true)),
                        Stmt::set(pend, Expr::Bool(false)),
                        Stmt::incr("events_in"),
                    ],
                )
            })
            .collect();
        out.push(Stmt::If(arms, Vec::new()));
        out.push(Stmt::set(
            "pending",
            Expr::fold(us.iter().map(|u| Expr::var(&self.pend[u.index()])), Op::Or, Expr::Bool(false)),
        ));
        out
    }

    /// Bits: an uncontrollable event some holder cannot take in its state.
    fn faults(&self) -> Vec<Stmt> {
        if self.opts.encoding != Encoding::Bits {
            return Vec::new();
        }
        let mut out = Vec::new();
        for u in self.uncontrollable() {
            for a in self.holders(u) {
                let cond = Expr::var(&self.ev[u.index()]).op(Op::And, self.allows(a, u).not());
                out.push(Stmt::when(cond, self.fault("unexpected")));
            }
        }
        out
    }

    /// The transition trigger of event `e` in automaton `a`: its AEEM bit (`true`: the transition
    /// resets it), or the event flag.
    fn trigger(&self, a: usize, e: EventId) -> (&str, bool) {
        match self.bits.iter().find(|(_, x, y)| *x == a && *y == e) {
            Some((bit, ..)) => (bit, true),
            None => (&self.ev[e.index()], false),
        }
    }

    /// The AEEM set rungs of a pass: an event's flag sets its memory bit (AEEM's first step).
    fn aeem_set(&self, controllable: bool) -> Vec<Rung> {
        self.bits
            .iter()
            .filter(|(_, _, e)| self.events().is_controllable(*e) == controllable)
            .map(|(bit, a, e)| Rung {
                comment: format!(
                    "event '{}' of {}: set its memory bit",
                    self.events().name(*e),
                    self.set.members()[*a].name()
                ),
                condition: Element::contact(self.ev[e.index()].clone(), false),
                coils: vec![coil(bit, CoilKind::Set)],
            })
            .collect()
    }

    /// The bits encoding's transition rungs of a pass, grouped by source state in the plan's order: the
    /// source state and the trigger in series; the source reset (unless a self-loop), the target set,
    /// and the trigger's memory bit reset where it has one (AEEM's second step).
    fn transition_rungs(&self, controllable: bool) -> Vec<Rung> {
        let pass = usize::from(controllable);
        let in_pass = |e: EventId| self.events().is_controllable(e) == controllable;
        let mut out = Vec::new();
        for (a, aut) in self.auts.iter().enumerate() {
            let m = &self.set.members()[a];
            for &s in &aut.plans[pass].order {
                for &(e, t) in aut.out[s].iter().filter(|(e, _)| in_pass(*e)) {
                    let (trig, is_bit) = self.trigger(a, e);
                    let mut coils = Vec::new();
                    if t.index() != s {
                        coils.push(coil(&self.state_var(a, s), CoilKind::Reset));
                    }
                    coils.push(coil(&self.state_var(a, t.index()), CoilKind::Set));
                    if is_bit {
                        coils.push(coil(trig, CoilKind::Reset));
                    }
                    let states = &m.automaton.states;
                    out.push(Rung {
                        comment: format!(
                            "{}: {} -{}-> {}",
                            m.name(),
                            states[s].name,
                            self.events().name(e),
                            states[t.index()].name
                        ),
                        condition: Element::Series(vec![
                            Element::contact(self.state_var(a, s), false),
                            Element::contact(trig, false),
                        ]),
                        coils,
                    });
                }
            }
        }
        out
    }

    /// The transition statements of a pass: the bits encoding's rungs, or (int) a `CASE` per event and
    /// holder.
    fn transitions(&self, controllable: bool) -> Vec<Stmt> {
        if self.opts.encoding == Encoding::Bits {
            return statements(&self.transition_rungs(controllable));
        }
        let in_pass = |e: EventId| self.events().is_controllable(e) == controllable;
        let mut out = Vec::new();
        for e in self.events().ids().filter(|&e| in_pass(e)) {
            let mut body = Vec::new();
            for a in self.holders(e) {
                let var = &self.auts[a].name;
                let mut arms: Vec<(Vec<i64>, Vec<Stmt>)> = Vec::new();
                for (s, edges) in self.auts[a].out.iter().enumerate() {
                    for &(_, t) in edges.iter().filter(|(x, _)| *x == e) {
                        let set = Stmt::set(var, Expr::Int(t.index() as i64));
                        match arms.iter_mut().find(|(_, b)| b[0] == set) {
                            Some((labels, _)) => labels.push(s as i64),
                            None => arms.push((vec![s as i64], vec![set])),
                        }
                    }
                }
                let els = if controllable { Vec::new() } else { self.fault("unexpected") };
                if arms.is_empty() {
                    body.extend(els);
                } else {
                    body.push(Stmt::Case(Expr::var(var), arms, els));
                }
            }
            if !body.is_empty() {
                out.push(Stmt::when(Expr::var(&self.ev[e.index()]), body));
            }
        }
        out
    }

    fn enabled(&self) -> Vec<Stmt> {
        self.controllable()
            .into_iter()
            .map(|c| {
                let mut terms: Vec<Expr> = match self.guards.of(c) {
                    // The supervisors' enablement as their guard; the plants' states still tested.
                    Some(g) => self
                        .holders(c)
                        .filter(|&a| self.set.members()[a].role == Role::Plant)
                        .map(|a| self.allows(a, c))
                        .chain([g.condition(&self.vars)])
                        .collect(),
                    None => self.holders(c).map(|a| self.allows(a, c)).collect(),
                };
                for (o, pt) in self.io.outputs.iter().zip(&self.pulse) {
                    if pt.is_some() && o.actions.iter().any(|&(e, ..)| e == c) {
                        terms.push(Expr::var(&o.variable).not());
                    }
                }
                if let Some((_, req)) = self.req.iter().find(|(e, _)| *e == c) {
                    terms.push(Expr::var(req));
                }
                let value = Expr::fold(terms, Op::And, Expr::Bool(true));
                Stmt::Assign(Expr::at(choice::ENABLED, Expr::Int(c.index() as i64)), value)
            })
            .collect()
    }

    /// The plants' generated events and choice sites, in plant order (as `firmware::table`'s side tables:
    /// an event is generated by the first plant holding it; a site is a plant state with two or more
    /// generated controllable out-events).
    fn sites(&self) -> Vec<PlantChoice> {
        let mut next = 0;
        let mut taken: Vec<EventId> = Vec::new();
        let mut out = Vec::new();
        for (a, m) in self.set.members().iter().enumerate().filter(|(_, m)| m.role == Role::Plant) {
            let events: Vec<EventId> = m
                .alphabet()
                .into_iter()
                .filter(|&e| self.events().is_controllable(e) && !taken.contains(&e))
                .collect();
            taken.extend(&events);
            let mut sites = Vec::new();
            for (s, edges) in self.auts[a].out.iter().enumerate() {
                let mut own: Vec<EventId> =
                    edges.iter().map(|&(e, _)| e).filter(|e| events.contains(e)).collect();
                own.dedup();
                if own.len() >= 2 {
                    sites.push((self.at(a, s), next));
                    next += 1;
                }
            }
            out.push(PlantChoice { events: events.iter().map(|e| e.index() as i64).collect(), sites });
        }
        out
    }

    fn site_count(&self) -> i64 {
        self.sites().iter().map(|p| p.sites.len() as i64).sum()
    }

    fn choice(&self) -> Vec<Stmt> {
        let cs = self.controllable();
        if cs.is_empty() {
            return Vec::new();
        }
        let mut decide = choice::statements(self.opts.policy, self.events().len() as i64, &self.sites());
        if !self.uncontrollable().is_empty() {
            decide.push(Stmt::when(
                Expr::var("c")
                    .op(Op::Ge, Expr::Int(0))
                    .op(Op::And, Expr::var("guard"))
                    .op(Op::And, Expr::var("arrived")),
                vec![Stmt::incr("guard_redecisions"), Stmt::set("c", Expr::Int(-1))],
            ));
        }
        let fire = cs
            .iter()
            .map(|c| (vec![c.index() as i64], vec![Stmt::set(&self.ev[c.index()], Expr::Bool(true))]))
            .collect();
        vec![
            Stmt::set("c", Expr::Int(-1)),
            Stmt::when(Expr::var("hold").not().op(Op::And, Expr::var("safe").not()), decide),
            Stmt::Case(Expr::var("c"), fire, Vec::new()),
            Stmt::when(Expr::var("c").op(Op::Ge, Expr::Int(0)), vec![Stmt::incr("commands_out")]),
            Stmt::set("fired", Expr::var("c")),
        ]
    }

    /// The variables' updates of a pass: per event, `IF ev THEN` its assignments ([`Guards::assignments`]).
    fn variable_updates(&self, controllable: bool) -> Vec<Stmt> {
        self.events()
            .ids()
            .filter(|&e| self.events().is_controllable(e) == controllable)
            .filter_map(|e| {
                let body = self.guards.assignments(e, &self.vars);
                (!body.is_empty()).then(|| Stmt::when(Expr::var(&self.ev[e.index()]), body))
            })
            .collect()
    }

    /// AEEM's last step: a rung per memory bit resetting it, whatever used it.
    fn aeem_reset(&self) -> Vec<Rung> {
        self.bits
            .iter()
            .map(|(bit, ..)| Rung {
                comment: format!("end of scan: {bit} clear"),
                condition: Element::Series(Vec::new()),
                coils: vec![coil(bit, CoilKind::Reset)],
            })
            .collect()
    }

    /// The ladder's first rung: on the first scan and while `reset`, every automaton in its initial state
    /// and every memory bit clear — what the `init` section does to them.
    fn init_rung(&self) -> Rung {
        let mut coils = Vec::new();
        for (a, m) in self.set.members().iter().enumerate() {
            let initial = m.initial().index();
            for s in 0..m.state_count() {
                let kind = if s == initial { CoilKind::Set } else { CoilKind::Reset };
                coils.push(coil(&self.state_var(a, s), kind));
            }
        }
        coils.extend(self.bits.iter().map(|(bit, ..)| coil(bit, CoilKind::Reset)));
        Rung {
            comment: "first scan and reset: initial states, memory bits clear".into(),
            condition: Element::Parallel(vec![
                Element::contact("ready", true),
                Element::contact("reset", false),
            ]),
            coils,
        }
    }

    /// The supervisors' ladder ([`Program::rungs`]): bits with AEEM only, else empty.
    fn ladder(&self) -> Vec<Rung> {
        if self.opts.encoding != Encoding::Bits || self.opts.avalanche != Avalanche::Aeem {
            return Vec::new();
        }
        let mut out = vec![self.init_rung()];
        for controllable in [false, true] {
            out.extend(self.aeem_set(controllable));
            out.extend(self.transition_rungs(controllable));
        }
        out.extend(self.aeem_reset());
        out
    }

    fn outputs(&self) -> Vec<Stmt> {
        let mut out = Vec::new();
        for (o, pt) in self.io.outputs.iter().zip(&self.pulse) {
            for &(e, action, scans) in &o.actions {
                let ev = Expr::var(&self.ev[e.index()]);
                let act = match (action, pt) {
                    (Action::Set, _) => Stmt::set(&o.variable, Expr::Bool(true)),
                    (Action::Clear, _) => Stmt::set(&o.variable, Expr::Bool(false)),
                    (Action::Pulse, Some(pt)) => Stmt::set(pt, Expr::Int(i64::from(scans))),
                    (Action::Pulse, None) => continue,
                };
                out.push(Stmt::when(ev, vec![act]));
            }
            if let Some(pt) = pt {
                let running = Expr::var(pt).op(Op::Gt, Expr::Int(0));
                out.push(Stmt::set(&o.variable, running.clone()));
                out.push(Stmt::when(running, vec![Stmt::set(pt, Expr::var(pt).op(Op::Sub, Expr::Int(1)))]));
            }
            if self.opts.on_fault == OnFault::SafeState {
                out.push(Stmt::when(Expr::var("safe"), vec![Stmt::set(&o.variable, Expr::Bool(false))]));
            }
        }
        out
    }

    fn finish(mut self) -> Program {
        let events = self.set.events().clone();
        let mut sections = vec![
            Section::new(INIT, "first scan and reset", self.init()),
            Section::new("inputs", "sampled once, edges against the previous scan", self.inputs()),
            Section::new("events", "one latched input per scan, in event order", self.events_section()),
            Section::new("faults", "", self.faults()),
            Section::new(AEEM_SET, "uncontrollable", statements(&self.aeem_set(false))),
            Section::new(TRANSITIONS, "uncontrollable", self.transitions(false)),
            Section::new("enabled", "", self.enabled()),
            Section::new("choice", self.opts.policy.name(), self.choice()),
            Section::new(AEEM_SET, "controllable", statements(&self.aeem_set(true))),
            Section::new(TRANSITIONS, "controllable", self.transitions(true)),
            Section::new(AEEM_RESET, "", statements(&self.aeem_reset())),
            Section::new("outputs", "", self.outputs()),
        ];
        // Only a set with variables has their sections: every other program stays as it was.
        if !self.vars.is_empty() {
            let after = |sections: &[Section], n: usize| {
                sections
                    .iter()
                    .enumerate()
                    .filter(|(_, x)| x.label == TRANSITIONS)
                    .nth(n)
                    .map_or(0, |(i, _)| i + 1)
            };
            let at = after(&sections, 0);
            sections.insert(at, Section::new("variables", "uncontrollable", self.variable_updates(false)));
            let at = after(&sections, 1);
            sections.insert(at, Section::new("variables", "controllable", self.variable_updates(true)));
        }
        // Only a set with timers has their sections: every other program stays as it was.
        if !self.timers.is_empty() {
            sections.insert(1, Section::new("timers", "a TON per [[timers]] entry", self.timer_calls()));
            let at = sections.len() - 1;
            sections
                .insert(at, Section::new("timer starts", "after this scan's events", self.timer_updates()));
        }
        let rungs = self.ladder();
        let sites = self.site_count().max(0) as usize;
        let base = stem(&self.opts.name);
        let fb_name = format!("{base}_sct");
        let type_name = format!("{base}_events");
        let members: Vec<Var> = self
            .io
            .members()
            .map(|(e, m)| Var::new(m, Type::Bool, format!("'{}': its rising edge", events.name(e))))
            .collect();
        let events_type = (!members.is_empty()).then(|| (type_name.clone(), members));

        // The I/O variables, located as the manifest says: declared so in the PROGRAM only, which binds
        // each address once and passes the values to the block, whose interface is never located
        // (IEC 61131-3 Ed. 3 6.5.5). An input carrying several events (both edges) is declared once.
        let mut io_inputs: Vec<Var> = Vec::new();
        for (&e, s) in &self.io.sources {
            if let Source::Input { variable, edge, address } = s {
                let what = format!("'{}': {} edge", events.name(e), edge.name());
                match io_inputs.iter_mut().find(|v| &v.name == variable) {
                    Some(v) => v.comment = format!("{}, {what}", v.comment),
                    None => {
                        let mut v = Var::new(variable, Type::Bool, what);
                        v.address.clone_from(address);
                        io_inputs.push(v);
                    }
                }
            }
        }
        let unlocated =
            |vars: &[Var]| -> Vec<Var> { vars.iter().map(|v| Var { address: None, ..v.clone() }).collect() };
        let mut inputs = unlocated(&io_inputs);
        if events_type.is_some() {
            inputs.push(Var::new(
                "EVENTS",
                Type::Named(type_name.clone()),
                "internal uncontrollable events (tests)",
            ));
        }
        for (e, req) in &self.req {
            let what = format!("'{}' requested (the sequence asks, the supervisors allow)", events.name(*e));
            inputs.push(Var::new(req, Type::Bool, what).init(Expr::Bool(false)));
        }
        inputs.push(Var::new("hold", Type::Bool, "no command while TRUE").init(Expr::Bool(false)));
        inputs.push(
            Var::new("guard", Type::Bool, "inexact-synchronisation guard").init(Expr::Bool(self.opts.guard)),
        );
        inputs.push(Var::new("reset", Type::Bool, "initial states while TRUE").init(Expr::Bool(false)));

        let outputs: Vec<Var> = self
            .io
            .outputs
            .iter()
            .map(|o| {
                let what: Vec<String> = o
                    .actions
                    .iter()
                    .map(|&(e, a, n)| match a {
                        Action::Pulse => format!("'{}' pulse {n}", events.name(e)),
                        _ => format!("'{}' {}", events.name(e), a.name()),
                    })
                    .collect();
                let mut v = Var::new(&o.variable, Type::Bool, what.join(", "));
                v.address.clone_from(&o.address);
                v
            })
            .collect();
        let io_outputs = outputs;
        let mut outputs = unlocated(&io_outputs);
        outputs.push(
            Var::new("fired", Type::Int, "controllable event id fired this scan, -1 none")
                .init(Expr::Int(-1)),
        );
        outputs.push(Var::new("pending", Type::Bool, "uncontrollable events latched, not yet applied"));
        outputs.push(Var::new("safe", Type::Bool, "a fault stopped the controller"));
        for c in COUNTERS {
            outputs.push(Var::new(c, Type::Udint, ""));
        }

        let mut locals = vec![Var::new("ready", Type::Bool, "initialised")];
        for (a, m) in self.set.members().iter().enumerate() {
            let role = m.role.as_str();
            match self.opts.encoding {
                Encoding::Int => locals.push(Var::new(
                    &self.auts[a].name,
                    Type::Int,
                    format!("{role} {}: state index, initial {}", m.name(), m.initial().index()),
                )),
                Encoding::Bits => {
                    for s in 0..m.state_count() {
                        let state = &m.automaton.states[s].name;
                        locals.push(Var::new(
                            self.state_var(a, s),
                            Type::Bool,
                            format!("{role} {} in state '{state}'", m.name()),
                        ));
                    }
                }
            }
        }
        for e in events.ids() {
            let kind = if events.is_controllable(e) { "controllable" } else { "uncontrollable" };
            locals.push(Var::new(
                &self.ev[e.index()],
                Type::Bool,
                format!("event {} '{}' ({kind}) this scan", e.index(), events.name(e)),
            ));
        }
        for u in self.uncontrollable() {
            locals.push(Var::new(&self.pend[u.index()], Type::Bool, "latched"));
            locals.push(Var::new(&self.prev[u.index()], Type::Bool, "input at the previous scan"));
        }
        for (bit, a, e) in &self.bits {
            let m = &self.set.members()[*a];
            locals.push(Var::new(
                bit,
                Type::Bool,
                format!("AEEM bit of '{}' in {}", events.name(*e), m.name()),
            ));
        }
        for pt in self.pulse.iter().flatten() {
            locals.push(Var::new(pt, Type::Int, "pulse scans left"));
        }
        locals.extend(self.guards.variables.iter().zip(&self.vars).map(|(v, name)| v.local(name)));
        for t in &self.timers {
            let timeout = events.name(t.timeout);
            locals.push(Var::new(&t.run, Type::Bool, format!("timer of '{timeout}' running")));
            locals.push(Var::new(
                &t.ton,
                Type::Named("TON".into()),
                format!("raises '{timeout}' after {} ms", t.ms),
            ));
        }
        let has_u = !self.uncontrollable().is_empty();
        let has_c = !self.controllable().is_empty();
        if has_u {
            locals.push(Var::new("busy", Type::Bool, "an event latched or arrived this scan"));
            locals.push(Var::new(
                "arrived",
                Type::Bool,
                "an uncontrollable event arrived: the guard holds commands",
            ));
        }
        if has_c {
            locals.extend(choice::locals(self.opts.policy, events.len(), sites, self.opts.seed, "event id"));
        }
        let fb = Pou {
            program: false,
            name: fb_name.clone(),
            vars: vec![(VarClass::Input, inputs), (VarClass::Output, outputs), (VarClass::Local, locals)],
            sections,
        };

        let mut main_vars: Vec<Var> = io_inputs.iter().chain(&io_outputs).cloned().collect();
        let mut args: Vec<(String, Expr)> =
            io_inputs.iter().map(|v| (v.name.clone(), Expr::var(&v.name))).collect();
        if let Some((ty, _)) = &events_type {
            main_vars.push(Var::new(
                "EVENTS",
                Type::Named(ty.clone()),
                "internal uncontrollable events (tests)",
            ));
            args.push(("EVENTS".into(), Expr::var("EVENTS")));
        }
        let passed = self.req.iter().map(|(_, r)| r.as_str()).chain(["hold", "guard", "reset"]);
        for v in passed {
            let input = fb.vars[0].1.iter().find(|x| x.name == v).cloned();
            if let Some(x) = input {
                main_vars.push(x);
            }
            args.push((v.into(), Expr::var(v)));
        }
        main_vars.push(Var::new("sct", Type::Named(fb_name.clone()), "plants, supervisors and interface"));
        let mut run = vec![Stmt::Call("sct".into(), args)];
        run.extend(io_outputs.iter().map(|v| Stmt::set(&v.name, Expr::var(format!("sct.{}", v.name)))));
        let main = Pou {
            program: true,
            name: format!("{base}_main"),
            vars: vec![(VarClass::Local, main_vars)],
            sections: vec![Section::new("run", "the function block, then its outputs", run)],
        };
        let mut avalanche: Vec<(String, EventId, Method)> = self
            .auts
            .iter()
            .zip(self.set.members())
            .flat_map(|(aut, m)| {
                let case = self.opts.encoding == Encoding::Int;
                aut.plans.iter().flat_map(|p| p.methods.iter()).map(move |(&e, &method)| {
                    (m.name().to_owned(), e, if case { Method::Case } else { method })
                })
            })
            .collect();
        // Automata in set order, events by id within each (the two passes merged).
        let rank = |name: &str| self.set.members().iter().position(|m| m.name() == name);
        avalanche.sort_by_key(|(a, e, _)| (rank(a), *e));
        let memory_bits = std::mem::take(&mut self.bits).into_iter().map(|(b, ..)| b).collect();
        let requests = std::mem::take(&mut self.req);
        let timers = self.timers.iter().map(|t| (t.timeout, t.ton.clone())).collect();
        let guards = std::mem::take(&mut self.guards);
        Program {
            events_type,
            fb,
            main,
            io: self.io,
            avalanche,
            memory_bits,
            rungs,
            sites,
            requests,
            timers,
            guards,
        }
    }
}

/// A coil of `kind` on `variable`.
fn coil(variable: &str, kind: CoilKind) -> Coil {
    Coil { variable: variable.to_owned(), kind }
}

/// The rungs as the ST statements that run them, top to bottom.
fn statements(rungs: &[Rung]) -> Vec<Stmt> {
    rungs.iter().flat_map(Rung::statements).collect()
}
