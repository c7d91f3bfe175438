//! The event-based program run closed loop (`codegen run --target plc`): the emitted ST text under the
//! scan-cycle interpreter ([`crate::interpreter`]), wrapped so it speaks the firmware's byte protocol
//! (`firmware::link`) on an in-memory link, so the virtual plant and the monitor judge the PLC program
//! as they judge the firmware under QEMU — the same [`Session`](crate::closed_loop::Session), the same
//! [`Report`], with the scan figures added ([`ScanFigures`]). [`run`] is the entry; [`Driver`] and
//! [`spawn_plc`] are its parts, which the tests drive scan by scan.
//!
//! Event bytes from the plant become edges of the program's input variables (or `EVENTS` members), as
//! the report's I/O map says: one event per scan, in the order sent (a PLC scans much faster than its
//! plant moves, and the program takes the edges of one scan in its own order), the input first brought
//! to the level the edge starts from when it is not there. Changes of the output variables after a scan become
//! command bytes (a rising edge: the variable's `set` or `pulse` event, a falling edge: its `clear`
//! event; where a variable has several, the block's `fired` output names it); `fired` alone gives the
//! controllable events that drive no output. HOLD sets the `hold` input at once (and again in order
//! when a GO or STEP before it is still queued); GO clears it in order,
//! once the events before it have been applied, so that the events a host sends between HOLD and GO
//! are all made before the program decides on any of them — as the firmware takes a whole write before
//! it decides, though here one input changes once per scan. STEP, once the events before it have been
//! applied, clears `hold` and lets the scans run until one fires a command or has nothing to decide
//! (no edge, nothing pending), then sets `hold` again and answers SYNC once the program is at rest (a
//! command's pulse ended in the held scans); the bytes after it wait for that — so the plant takes its
//! turn between any two commands, as with a firmware in steps. RESET, STATUS and EXIT are answered in order, once the events
//! before them have been applied (no edge waiting, `pending` low): RESET by a scan with `reset` (and
//! `hold`) set, then READY; STATUS from the block's counters. SYNC, once the events before it have been applied, is answered after the first
//! scan that runs with `hold` low, makes no edge, fires no command and leaves nothing pending, no pulse
//! running: the program has decided all it can on every event before it — the lock-step rounds of a
//! session. A SYNC answer (a round's, a step's) thus finds the program at rest, where a scan with
//! nothing new changes nothing: how many scans the wrapper runs before the host's next bytes come (the
//! machine's timing) cannot change what the program does with them, nor the scan figures. (A
//! sequence net whose marking cycles with no command never leaves nothing pending: once the
//! program's whole state repeats, the cycle no longer counts, [`Driver`]'s `cycling`.) As in
//! the firmware's event loop, the bytes after it do not wait for the answer. A rise of `safe` sends
//! SAFE. The scan figures ([`ScanStats`]) count from the host's first RESET: before it the program
//! runs unheld, as a PLC from power-up, for as long as the host takes to send its first HOLD.

use std::collections::{BTreeMap, VecDeque};
use std::thread::JoinHandle;
use std::time::Duration;

use firmware::link::{EXIT, GO, HOLD, MAX_EVENT, READY, RESET, SAFE, STATUS, STEP, SYNC, TIME};

use super::report::Report as ProgramReport;
use crate::closed_loop::{attach, ClosedLoopError, Options, SessionConfig};
use crate::config::ScanPolicy;
use crate::interpreter::{Plc, Value};
use crate::link::memory::{self, MemoryLink};
use crate::link::ByteLink;
use crate::model::{Dfa, EventTable};
use crate::monitor::{ChoiceModel, Report, ScanFigures};
use crate::pack::{PackSet, Role};
use crate::plant::Rng;

use super::net_drive::NetDrive;

/// The path of the function block instance in the program.
const FB: &str = "sct";

/// Where an uncontrollable event's edge is made.
#[derive(Clone, Debug)]
struct InputLine {
    path: String,
    edge: &'static str,
}

/// The I/O map of a generated program, by event id.
#[derive(Clone, Debug, Default)]
pub struct IoMap {
    inputs: BTreeMap<u8, InputLine>,
    /// Output variable → (event id, action).
    outputs: BTreeMap<String, Vec<(u8, &'static str)>>,
    /// Per timer: its `TON`'s output (a path in the block) and its timeout's event id.
    timers: Vec<(String, u8)>,
    /// The input variables' levels at the plant's initial state ([`IoMap::with_levels_of`]); an input
    /// not here starts FALSE.
    initial: BTreeMap<String, bool>,
}

impl IoMap {
    /// The map the program's report gives, over the set's event ids; an event the set does not have, or
    /// one beyond the link's ids, is an error.
    pub fn new(report: &ProgramReport, events: &EventTable) -> Result<IoMap, String> {
        let mut map = IoMap::default();
        for io in &report.variables.io {
            let id = events
                .id(&io.event)
                .map(|e| e.as_u32())
                .ok_or(format!("event {} is not in the set", io.event))?;
            let id = u8::try_from(id)
                .ok()
                .filter(|&id| id <= MAX_EVENT)
                .ok_or(format!("event id {id} beyond the link"))?;
            if io.direction == "input" {
                map.inputs.insert(id, InputLine { path: io.variable.clone(), edge: io.kind });
            } else if io.direction == "timer" {
                map.timers.push((format!("{FB}.{}", io.variable), id));
            } else {
                map.outputs.entry(io.variable.clone()).or_default().push((id, io.kind));
            }
        }
        Ok(map)
    }

    /// The map with its inputs' levels at the plant's initial state, as `set`'s plants give them: an
    /// input whose first edge each plant automaton over its events can take from its initial state is a
    /// falling one (and none a rising one) starts TRUE — a sensor that is on, such as an arm's end switch
    /// with the arm at that end. Derived from the plants the virtual plant runs, it holds for every
    /// program, with or without a sequence net (whose `[net] initial` states the same levels for the
    /// sensors it reads: a test checks they agree).
    pub fn with_levels_of(mut self, set: &PackSet) -> IoMap {
        let mut by_path: BTreeMap<&str, (Vec<u32>, Vec<u32>)> = BTreeMap::new();
        for (&e, line) in &self.inputs {
            let (rising, falling) = by_path.entry(line.path.as_str()).or_default();
            match line.edge {
                "rising" => rising.push(u32::from(e)),
                "falling" => falling.push(u32::from(e)),
                _ => {}
            }
        }
        for (path, (rising, falling)) in by_path {
            let firsts: Vec<(bool, bool)> = set
                .members()
                .iter()
                .filter(|m| m.role == Role::Plant)
                .map(|m| first_edges(&m.dfa, &rising, &falling))
                .filter(|&(r, f)| r || f)
                .collect();
            let on = !firsts.is_empty() && firsts.iter().all(|&(r, f)| f && !r);
            if on {
                self.initial.insert(path.to_string(), true);
            }
        }
        self
    }

    /// Whether, at the plant's initial state, the input that uncontrollable event `e` changes stands at
    /// the level `e` leads to ([`IoMap::with_levels_of`]); `None` when `e` has no input.
    pub fn initial_level(&self, e: u8) -> Option<bool> {
        let line = self.inputs.get(&e)?;
        let level = self.initial.get(&line.path).copied().unwrap_or(false);
        Some(if line.edge == "falling" { !level } else { level })
    }
}

/// Which of an input's edges (`rising`, `falling`: event ids) `dfa` can take first from its initial
/// state, over any path of its other events: (a rising one, a falling one).
fn first_edges(dfa: &Dfa, rising: &[u32], falling: &[u32]) -> (bool, bool) {
    let (mut r, mut f) = (false, false);
    let Some(start) = dfa.initial() else { return (r, f) };
    let mut seen = vec![false; dfa.state_count()];
    let mut stack = vec![start];
    seen[start as usize] = true;
    while let Some(s) = stack.pop() {
        for (e, to) in dfa.edges(s) {
            if rising.contains(&e) {
                r = true;
            } else if falling.contains(&e) {
                f = true;
            } else if !std::mem::replace(&mut seen[to as usize], true) {
                stack.push(to);
            }
        }
    }
    (r, f)
}

/// What the wrapper measured, returned when the host sends EXIT: over the scans from the host's first
/// RESET on (the session's start) that made an input's edge or fired a command. The scans a PLC repeats while it waits for its plant or the host, or works
/// off what is pending, are not counted: their number is the machine's timing, so the figures are a
/// function of what the host sent, not of how fast the interpreter ran.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanStats {
    /// Scans that did something.
    pub scans: u64,
    /// Most statements one scan executed.
    pub max_statements: u64,
}

/// The program and its input levels, as the wrapper drives them.
pub struct Driver {
    /// The interpreter.
    pub plc: Plc,
    io: IoMap,
    levels: BTreeMap<String, bool>,
    outputs: BTreeMap<String, bool>,
    /// Per timer of the map, its `TON`'s output after the last scan.
    timer_q: Vec<bool>,
    /// The task's interval: the scan clock's step while the link's TIME lets it run. A program with
    /// timers runs every other scan at 0 ms, its clock frozen, so its `TON`s count the host's virtual
    /// time alone ([`Scanner::pass_time`]).
    cycle_ms: u32,
    /// An input's edge was made (or prepared) since the last scan.
    edged: bool,
    /// A sequence net's free inputs and the seed's draws for them ([`Driver::drive_net`]).
    net: Option<(NetDrive, Rng)>,
    /// The last scan changed nothing: no edge, command, timeout nor place, nothing pending.
    settled: bool,
    /// The last scan moved the sequence net's marking: the program has not decided all it can yet (a
    /// transition that fires no command may enable one that does), so it counts as pending — unless
    /// its marking cycles (`Driver::cycling`).
    moving: bool,
    /// The program's states after the scans since the last one that did work (an edge, a command, a
    /// timeout) or left the marking where it was, or the last round or reset.
    streak: Vec<BTreeMap<String, Value>>,
    /// TIME scans every task interval, never jumping to a delay's end ([`Driver::scan_every_cycle`]).
    every_cycle: bool,
}

/// What one scan did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Scan {
    /// The timeouts it raised (a timer's `TON` output rose), in timer order.
    pub timeouts: Vec<u8>,
    /// The commands it fired, in order.
    pub commands: Vec<u8>,
    /// The statements it executed, when it did work the figures count (read an input's change or
    /// fired a command).
    pub statements: Option<u64>,
}

/// A program as the wrapper ([`spawn_plc`]) drives it: the event-based program ([`Driver`]) or the
/// state-based one ([`super::state_based::closed_loop::StateDriver`]).
pub trait Scanner {
    /// Whether `e` is an uncontrollable event the program has an input for.
    fn has_input(&self, e: u8) -> bool;
    /// Makes the input change of uncontrollable event `e`, unless `used` says an input already
    /// changed this scan (what changed is then added to `used`).
    fn edge(&mut self, e: u8, used: &mut Vec<String>) -> Result<Edge, String>;
    /// Stops (`true`) or lets the program decide.
    fn hold(&mut self, on: bool) -> Result<(), String>;
    /// Whether the program is held.
    fn held(&self) -> Result<bool, String>;
    /// Whether the program is not at rest yet: events read still waiting to be applied, or a change it
    /// makes on its own still under way (a pulse running down, a sequence net's marking moving). The
    /// wrapper answers SYNC only at rest, so that the scans it runs while the host takes its turn — as
    /// many as the machine's timing gives — change nothing.
    fn pending(&self) -> Result<bool, String>;
    /// Whether the program is in its safe state.
    fn safe(&self) -> Result<bool, String>;
    /// Runs one scan (a program that cannot be held runs none while held).
    fn scan(&mut self) -> Result<Scan, String>;
    /// Brings the program back to its initial state, deciding nothing.
    fn reset(&mut self) -> Result<(), String>;
    /// The six STATUS counters, with the wrapper's `unknown` bytes last.
    fn status(&self, unknown: u32) -> Result<[u32; 6], String>;
    /// The task's interval when the program has timers, which the link's TIME then lets its scan clock
    /// run by (the driver's `pass_time`); `None` (the default): the program has none and TIME changes
    /// nothing.
    fn timed_cycle(&self) -> Option<u32> {
        None
    }
    /// Sets how far the scan clock moves at the next scans (a program with timers only).
    fn set_interval(&mut self, _ms: u32) {}
    /// Whether TIME runs the program released from the host's hold: a program whose only time is its
    /// own sequence's delays fires what they decide as they run out (its own moves, as a PLC makes
    /// them while its plant is still); one with `[[timers]]` stays held, so that the plant's events
    /// after a timeout reach it before it decides (the default: held).
    fn runs_free_on_time(&self) -> bool {
        false
    }
    /// A round begins (the host asked for SYNC, or STEP): inputs the wrapper draws are drawn afresh
    /// (the default: none).
    fn new_round(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// How far TIME may move the clock before the next scan without skipping a change (a program with
    /// timers only; `None`, the default: one task interval).
    fn quiet_for(&self) -> Result<Option<u32>, String> {
        Ok(None)
    }
}

/// What one attempt to make an event's edge did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    /// The edge is made this scan.
    Made,
    /// The input was brought to the edge's starting level this scan; try again next scan.
    Prepared,
    /// The input already changed this scan.
    Busy,
}

impl Driver {
    /// A driver for `text` (the `.st` file) with the map of its report, after its first scan.
    pub fn new(text: &str, io: IoMap) -> Result<Driver, String> {
        let plc = Plc::load(text)?;
        let timer_q = vec![false; io.timers.len()];
        let mut d = Driver {
            plc,
            io,
            levels: BTreeMap::new(),
            outputs: BTreeMap::new(),
            timer_q,
            cycle_ms: 10,
            edged: false,
            net: None,
            settled: false,
            moving: false,
            streak: Vec::new(),
            every_cycle: false,
        };
        // The boot scan: initial states, the inputs' first sample.
        d.reset()?;
        Ok(d)
    }

    fn snapshot(&mut self) -> Result<(), String> {
        for var in self.io.outputs.keys() {
            self.outputs.insert(var.clone(), self.plc.get_bool(var)?);
        }
        for ((q, _), was) in self.io.timers.iter().zip(&mut self.timer_q) {
            *was = self.plc.get_bool(q)?;
        }
        Ok(())
    }

    /// Sets the task's interval (`[plc] cycle_ms`): the scan clock's step; with timers, the step of the
    /// scans the link's TIME runs, every other scan then leaving the clock where it is.
    pub fn set_cycle_ms(&mut self, ms: u32) {
        self.cycle_ms = ms;
        self.plc.set_cycle_ms(if self.timed() { 0 } else { ms });
    }

    /// Whether the scan clock moves on the link's TIME alone: the program has `[[timers]]`, or delays of
    /// its own (a sequence net's, [`Driver::drive_net`]).
    fn timed(&self) -> bool {
        !self.io.timers.is_empty() || self.net.as_ref().is_some_and(|(d, _)| d.delays.is_some())
    }

    /// Drives the free inputs of the sequence net beside the interlocks as `drive` says, drawing from
    /// `seed` ([`NetDrive`]): from the next reset on, and at every round. With delays, the scan clock
    /// then moves on TIME alone, so the net's `TON`s count the session's time, not the machine's.
    pub fn drive_net(&mut self, drive: NetDrive, seed: u64) -> Result<(), String> {
        self.net = Some((drive, Rng::new(seed)));
        self.set_cycle_ms(self.cycle_ms);
        self.reset()
    }

    /// With `on`, TIME scans every task interval, as a PLC does, instead of jumping the clock over
    /// settled scans to the next delay's end ([`Driver::quiet_for`]); the two give the same run (a test
    /// compares them), the jump in a fraction of the scans.
    pub fn scan_every_cycle(&mut self, on: bool) {
        self.every_cycle = on;
    }

    /// How far the clock may move before the next scan without skipping a change: after a settled scan
    /// (nothing changed, nothing pending; the inputs only change between TIME's scans), the scans before
    /// the next end of a running delay of the sequence net would repeat it, so the clock may jump to
    /// that end (`u32::MAX`: none running). `None`: scan every task interval.
    pub fn quiet_for(&self) -> Result<Option<u32>, String> {
        let Some((drive, _)) = &self.net else { return Ok(None) };
        if self.every_cycle || !self.settled {
            return Ok(None);
        }
        let mut next = u32::MAX;
        for t in &drive.timers {
            if self.plc.get_bool(&format!("{t}.RUNNING"))? && !self.plc.get_bool(&format!("{t}.Q"))? {
                let left = self.plc.get_int(&format!("{t}.PT"))? - self.plc.get_int(&format!("{t}.ET"))?;
                next = next.min(u32::try_from(left.max(1)).unwrap_or(u32::MAX));
            }
        }
        Ok(Some(next))
    }

    /// Whether a pulsed output is still high: its pulse runs down over the next scans, so the program
    /// is not at rest — a scan with nothing new would still change it, and a command on that output is
    /// disabled until it ends.
    fn pulsing(&self) -> bool {
        self.io.outputs.iter().any(|(var, actions)| {
            actions.iter().any(|&(_, k)| k == "pulse") && self.outputs.get(var).copied().unwrap_or(false)
        })
    }

    /// The sequence net's marking (empty without one).
    fn marking(&self) -> Result<Vec<bool>, String> {
        let Some((drive, _)) = &self.net else { return Ok(Vec::new()) };
        drive.places.iter().map(|p| self.plc.get_bool(p)).collect()
    }

    /// Whether the sequence net's marking cycles: the program's whole state after the last scan is one
    /// a scan of this streak left already — its inputs unchanged since (an edge or a timeout is work,
    /// which `ended` says ends the streak, as does a scan that left the marking where it was), so every
    /// scan from here repeats the cycle, and nothing comes of it until something outside changes (an
    /// event, a round's draw, a delay running out on TIME). The program is deterministic and its
    /// states finite, so a cycle shows within as many scans as it passes through states, and the
    /// session then judges the round instead of waiting for the program to settle.
    fn cycling(&mut self, ended: bool) -> bool {
        if ended {
            self.streak.clear();
            return false;
        }
        let now = self.plc.variables();
        if self.streak.iter().any(|s| s == now) {
            return true;
        }
        self.streak.push(now.clone());
        false
    }

    /// A new round: the free inputs that are drawn are drawn afresh.
    pub fn new_round(&mut self) -> Result<(), String> {
        self.streak.clear();
        let Some((drive, rng)) = &mut self.net else { return Ok(()) };
        for var in &drive.drawn {
            self.plc.set_bool(var, rng.chance(500))?;
        }
        Ok(())
    }

    /// Makes the edge of uncontrollable event `e` on its input, unless `used` says the input already
    /// changed this scan (the input is then added to `used`).
    pub fn edge(&mut self, e: u8, used: &mut Vec<String>) -> Result<Edge, String> {
        let line = self.io.inputs.get(&e).ok_or(format!("event {e} has no input"))?.clone();
        if used.contains(&line.path) {
            return Ok(Edge::Busy);
        }
        used.push(line.path.clone());
        let level = *self.levels.get(&line.path).unwrap_or(&false);
        let (next, made) = match line.edge {
            "rising" if level => (false, Edge::Prepared),
            "falling" if !level => (true, Edge::Prepared),
            _ => (!level, Edge::Made),
        };
        self.levels.insert(line.path.clone(), next);
        self.plc.set_bool(&line.path, next)?;
        self.edged = true;
        Ok(made)
    }

    /// Whether `e` is an uncontrollable event the program has an input for.
    pub fn has_input(&self, e: u8) -> bool {
        self.io.inputs.contains_key(&e)
    }

    /// Runs one scan; returns the commands it fired, as output changes and `fired` show them.
    pub fn scan(&mut self) -> Result<Vec<u8>, String> {
        Ok(self.scan_counted()?.commands)
    }

    fn scan_counted(&mut self) -> Result<Scan, String> {
        let marking = self.marking()?;
        let statements = self.plc.scan()?;
        let edged = std::mem::take(&mut self.edged);
        let mut timeouts = Vec::new();
        for ((q, id), was) in self.io.timers.iter().zip(&mut self.timer_q) {
            let now = self.plc.get_bool(q)?;
            if now && !*was {
                timeouts.push(*id);
            }
            *was = now;
        }
        let fired = self.plc.get_int(&format!("{FB}.fired"))?;
        let mut commands = Vec::new();
        let mut seen_fired = false;
        for (var, actions) in &self.io.outputs {
            let now = self.plc.get_bool(var)?;
            let before = self.outputs.insert(var.clone(), now).unwrap_or(false);
            if now == before {
                continue;
            }
            let kinds: &[&str] = if now { &["set", "pulse"] } else { &["clear"] };
            let candidates: Vec<u8> =
                actions.iter().filter(|(_, k)| kinds.contains(k)).map(|&(e, _)| e).collect();
            let event = match candidates.as_slice() {
                [] if !now => continue, // a pulse ending
                [one] => *one,
                many if many.iter().any(|&e| i64::from(e) == fired) => u8::try_from(fired).unwrap_or(0),
                _ => return Err(format!("{var} changed to {now}, but no event of it fired ({fired})")),
            };
            seen_fired |= i64::from(event) == fired;
            commands.push(event);
        }
        let mapped = self.io.outputs.values().flatten().any(|&(e, _)| i64::from(e) == fired);
        // A `set` of an output already set (or a `clear` of one already clear) fires its event with no
        // change to see: an alarm lamp that stays lit through a second fault.
        let mut unchanged = false;
        for (var, actions) in &self.io.outputs {
            let level = self.outputs.get(var).copied().unwrap_or(false);
            unchanged |= actions
                .iter()
                .any(|&(e, k)| i64::from(e) == fired && ((k == "set" && level) || (k == "clear" && !level)));
        }
        match (fired >= 0, mapped, seen_fired) {
            (true, false, _) => commands.push(u8::try_from(fired).map_err(|_| format!("fired {fired}"))?),
            (true, true, false) if unchanged => {
                commands.push(u8::try_from(fired).map_err(|_| format!("fired {fired}"))?)
            }
            (true, true, false) => return Err(format!("event {fired} fired but its output did not change")),
            _ => {}
        }
        if commands.len() > 1 {
            return Err(format!("more than one command in a scan: {commands:?}"));
        }
        let worked = edged || !commands.is_empty() || !timeouts.is_empty();
        let moved = self.marking()? != marking;
        let cycling = self.cycling(worked || !moved);
        self.moving = moved && !cycling;
        self.settled =
            !worked && !moved && !self.pulsing() && !self.plc.get_bool(&format!("{FB}.pending"))?;
        Ok(Scan { timeouts, commands, statements: worked.then_some(statements) })
    }

    /// A scan with `reset` and `hold` set: the program back to its initial states, no command.
    /// The inputs are first brought to their levels at the plant's initial state, and a sequence net's
    /// free inputs to theirs (held, or drawn), so the reset scan samples them without an edge; the
    /// program's `reset` brings a sequence net back to its initial marking in the same scan.
    pub fn reset(&mut self) -> Result<(), String> {
        let paths: Vec<String> = self.io.inputs.values().map(|l| l.path.clone()).collect();
        for path in paths {
            let level = self.io.initial.get(&path).copied().unwrap_or(false);
            self.plc.set_bool(&path, level)?;
            self.levels.insert(path, level);
        }
        if let Some((drive, _)) = &self.net {
            for var in &drive.held {
                self.plc.set_bool(var, true)?;
            }
        }
        self.new_round()?;
        let hold = self.plc.get_bool("hold")?;
        self.plc.set_bool("reset", true)?;
        self.plc.set_bool("hold", true)?;
        self.plc.scan()?;
        self.plc.set_bool("reset", false)?;
        self.plc.set_bool("hold", hold)?;
        self.edged = false;
        (self.moving, self.settled) = (false, false);
        self.streak.clear();
        self.snapshot()
    }
}

impl Scanner for Driver {
    fn has_input(&self, e: u8) -> bool {
        Driver::has_input(self, e)
    }

    fn edge(&mut self, e: u8, used: &mut Vec<String>) -> Result<Edge, String> {
        Driver::edge(self, e, used)
    }

    fn hold(&mut self, on: bool) -> Result<(), String> {
        self.plc.set_bool("hold", on)
    }

    fn held(&self) -> Result<bool, String> {
        self.plc.get_bool("hold")
    }

    fn pending(&self) -> Result<bool, String> {
        Ok(self.moving || self.pulsing() || self.plc.get_bool(&format!("{FB}.pending"))?)
    }

    fn safe(&self) -> Result<bool, String> {
        self.plc.get_bool(&format!("{FB}.safe"))
    }

    fn scan(&mut self) -> Result<Scan, String> {
        self.scan_counted()
    }

    fn reset(&mut self) -> Result<(), String> {
        Driver::reset(self)
    }

    fn timed_cycle(&self) -> Option<u32> {
        self.timed().then_some(self.cycle_ms)
    }

    fn runs_free_on_time(&self) -> bool {
        self.io.timers.is_empty()
    }

    fn new_round(&mut self) -> Result<(), String> {
        Driver::new_round(self)
    }

    fn quiet_for(&self) -> Result<Option<u32>, String> {
        Driver::quiet_for(self)
    }

    fn set_interval(&mut self, ms: u32) {
        self.plc.set_cycle_ms(ms);
    }

    fn status(&self, unknown: u32) -> Result<[u32; 6], String> {
        let mut out = [0; 6];
        for (slot, name) in
            out.iter_mut().zip(["events_in", "commands_out", "unexpected", "overflows", "guard_redecisions"])
        {
            *slot = u32::try_from(self.plc.get_int(&format!("{FB}.{name}"))?).map_err(|e| e.to_string())?;
        }
        out[5] = unknown;
        Ok(out)
    }
}

/// Runs `driver` behind `link` in a thread, as the firmware would run; see the module documentation.
/// The thread returns the scan statistics on EXIT, or the first error of the program or the link.
pub fn spawn_plc<D: Scanner + Send + 'static>(
    mut driver: D,
    mut link: MemoryLink,
) -> JoinHandle<Result<ScanStats, String>> {
    std::thread::spawn(move || {
        let io = |e: std::io::Error| e.to_string();
        link.send(&[READY]).map_err(io)?;
        let mut fifo: VecDeque<u8> = VecDeque::new();
        let mut unknown = 0u32;
        let mut was_safe = false;
        let mut buf = [0u8; 512];
        let mut idle = false;
        // A SYNC came in, in order, and waits for a scan that decides nothing.
        let mut sync_asked = false;
        // A STEP was taken: the scans decide until one fires a command or has nothing to decide.
        let mut stepping = false;
        // The STEP's decision is taken, the program held again: SYNC is answered once it is at rest.
        let mut stepped = false;
        // The figures count from the host's first RESET: before it the program runs on its own, as a
        // PLC does from power-up, for as long as the host takes to send its first HOLD — a matter of
        // the machine's timing, and unmonitored (the session starts with HOLD, STATUS, RESET).
        let mut stats: Option<ScanStats> = None;
        loop {
            let wait = if idle { Duration::from_millis(2) } else { Duration::ZERO };
            let n = link.recv(&mut buf, wait).map_err(io)?;
            for &b in &buf[..n] {
                if b == HOLD {
                    driver.hold(true)?;
                    // A GO or STEP still queued came before this HOLD: taken in order it would clear
                    // it, and the program would decide, or not, as the bytes happened to arrive. The
                    // HOLD is taken again after it.
                    if !fifo.iter().any(|&q| q == GO || q == STEP) {
                        continue;
                    }
                }
                fifo.push_back(b);
            }
            let mut used = Vec::new();
            let mut out = Vec::new();
            let mut answered = false;
            while let Some(&b) = fifo.front() {
                if stepping || stepped {
                    // The bytes after a STEP wait for its answer.
                    break;
                }
                match b {
                    0..=MAX_EVENT if driver.has_input(b) => {
                        if !used.is_empty() {
                            break;
                        }
                        if driver.edge(b, &mut used)? == Edge::Made {
                            fifo.pop_front();
                        }
                    }
                    SYNC => {
                        fifo.pop_front();
                        sync_asked = true;
                        driver.new_round()?;
                    }
                    STEP => {
                        // Its one decision sees every event before it, and none after it.
                        if !used.is_empty() || driver.pending()? {
                            break;
                        }
                        fifo.pop_front();
                        driver.new_round()?;
                        driver.hold(false)?;
                        stepping = true;
                        break;
                    }
                    GO | HOLD => {
                        fifo.pop_front();
                        driver.hold(b == HOLD)?;
                    }
                    TIME => {
                        // Its Δ in full, and every event before it applied.
                        if fifo.len() < 3 || !used.is_empty() || driver.pending()? {
                            break;
                        }
                        let ms = u16::from_le_bytes([fifo[1], fifo[2]]);
                        fifo.drain(..3);
                        pass_time(&mut driver, u32::from(ms), &mut out, &mut stats)?;
                    }
                    RESET | STATUS | EXIT => {
                        if !used.is_empty() || driver.pending()? {
                            break;
                        }
                        fifo.pop_front();
                        answered = true;
                        match b {
                            RESET => {
                                stats.get_or_insert_with(ScanStats::default);
                                driver.reset()?;
                                unknown = 0;
                                was_safe = false;
                                out.push(READY);
                            }
                            STATUS => {
                                out.push(STATUS);
                                for word in driver.status(unknown)? {
                                    out.extend(word.to_le_bytes());
                                }
                            }
                            _ => {
                                link.send(&out).map_err(io)?;
                                return Ok(stats.unwrap_or_default());
                            }
                        }
                    }
                    _ => {
                        fifo.pop_front();
                        unknown += 1;
                    }
                }
            }
            let held = driver.held()?;
            let Scan { timeouts, commands, statements } = driver.scan()?;
            out.extend(&timeouts);
            out.extend(&commands);
            let pending = driver.pending()?;
            let quiet = timeouts.is_empty() && commands.is_empty() && used.is_empty() && !pending;
            // Only a scan that made an edge or fired a command is counted: how many scans a program
            // waits or works off what is pending before the host's next byte arrives is the machine's
            // timing, not the program's work.
            if let (Some(stats), Some(statements)) = (stats.as_mut(), statements) {
                stats.scans += 1;
                stats.max_statements = stats.max_statements.max(statements);
            }
            if stepping && !held && (!commands.is_empty() || quiet) {
                // The step's decision is taken (a command, or none to take): hold again.
                stepping = false;
                stepped = true;
                driver.hold(true)?;
            }
            if stepped && !pending {
                // At rest (a command's pulse ended in the held scans since): the same program state
                // however soon the host's next bytes come.
                stepped = false;
                answered = true;
                out.push(SYNC);
            } else if sync_asked && quiet && !held && !stepping && !stepped {
                sync_asked = false;
                answered = true;
                out.push(SYNC);
            }
            let safe = driver.safe()?;
            if safe && !was_safe {
                out.push(SAFE);
            }
            was_safe = safe;
            if !out.is_empty() {
                link.send(&out).map_err(io)?;
            }
            idle = n == 0 && fifo.is_empty() && quiet && !answered;
        }
    })
}

/// The link's TIME: lets the scan clock of a timed program run `ms` milliseconds, and appends what
/// the scans raised and fired to `out` — each scan's timeouts before its commands. A program with
/// `[[timers]]` stays held if the host holds it: its `TON`s run and its timeouts are taken while its
/// commands wait for GO, so that an event the plant sends after a timeout, in the same round, reaches
/// the program before it decides (a late end switch after the timeout), as on the firmware. A program
/// timed only by its sequence's delays runs released during TIME ([`Scanner::runs_free_on_time`]) and
/// held again after it. First a scan at 0 ms, so that a timer started by the last command counts from
/// the time it was started at, then scans a task interval apart (the last one shorter when `ms` is not
/// a multiple of it, or a jump over settled scans, [`Scanner::quiet_for`]), so the clock ends exactly
/// `ms` later. A `TON` is only evaluated at scans: its timeout is raised at the first scan at or after
/// its deadline, up to one task interval late — the slack the host gives a PLC
/// ([`crate::closed_loop::Options::timer_slack_ms`]). A program without timers ignores TIME.
fn pass_time<D: Scanner>(
    driver: &mut D,
    ms: u32,
    out: &mut Vec<u8>,
    stats: &mut Option<ScanStats>,
) -> Result<(), String> {
    let Some(cycle) = driver.timed_cycle() else { return Ok(()) };
    let held = driver.held()?;
    if driver.runs_free_on_time() {
        driver.hold(false)?;
    }
    let mut left = ms;
    let mut first = true;
    while first || left > 0 {
        let cycle = cycle.max(1);
        let step = match driver.quiet_for()? {
            _ if first => 0,
            // Whole task intervals, as the scans it stands for would have moved the clock.
            Some(quiet) => left.min(quiet.div_ceil(cycle).max(1).saturating_mul(cycle)),
            None => left.min(cycle),
        };
        first = false;
        left -= step;
        driver.set_interval(step);
        let Scan { timeouts, commands, statements } = driver.scan()?;
        out.extend(timeouts);
        out.extend(commands);
        if let (Some(stats), Some(statements)) = (stats.as_mut(), statements) {
            stats.scans += 1;
            stats.max_statements = stats.max_statements.max(statements);
        }
    }
    driver.set_interval(0);
    driver.hold(held)
}

/// Why a program's closed-loop run failed (as opposed to finding violations, which are in its report).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The interpreter refused the program (a strict compiler's refusal, [`crate::interpreter::check`]),
    /// or the program failed while running (an integer out of its type's range, an index out of its
    /// array, more than one command in a scan, an output changed with no event of it fired).
    #[error("the PLC program: {0}")]
    Program(String),
    /// The closed loop around it failed.
    #[error(transparent)]
    ClosedLoop(#[from] ClosedLoopError),
}

/// Runs the event-based program `text` (its `.st` file) with its report `program` closed loop against
/// `set`'s plants, judged by plants ‖ supervisors, for `options.events` events; returns the report,
/// with the scan figures and the duration on the PLC's own clock (scans × `program.cycle_ms`). The
/// session runs in lock-step rounds, in steps as a firmware's (`options.session.step`): the plant's
/// events of a round, then the program scans until it has decided all it can on them, so the run is a
/// function of the plant's seed, however fast the interpreter runs. The monitor models the program's
/// choice policy (`options.choices` is not read).
pub fn run(
    text: &str,
    program: &ProgramReport,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, RunError> {
    run_net(text, program, set, name, None, options, progress)
}

/// [`run`] for a program with a sequence net beside the interlocks (`[net]`): its free inputs driven
/// and its delays waited for as `net` says ([`NetDrive`]), from the plant's seed.
pub fn run_net(
    text: &str,
    program: &ProgramReport,
    set: &PackSet,
    name: &str,
    net: Option<&NetDrive>,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, RunError> {
    let driver = net_driver(text, program, set, net, options.plant.seed).map_err(RunError::Program)?;
    let mut options = options.clone();
    options.session.own_delays = net.and_then(|net| net.own_delays(program.cycle_ms));
    let (host, target) = memory::pair();
    let plc = spawn_plc(driver, target);
    run_spawned(host, plc, &program.into(), set, name, &options, progress)
}

/// The driver [`run_net`] runs: the program `text` with its report's map, its inputs at the plant's
/// initial levels ([`IoMap::with_levels_of`]), the net's free inputs driven from `seed`.
pub fn net_driver(
    text: &str,
    program: &ProgramReport,
    set: &PackSet,
    net: Option<&NetDrive>,
    seed: u64,
) -> Result<Driver, String> {
    let mut driver = Driver::new(text, IoMap::new(program, set.events())?.with_levels_of(set))?;
    driver.set_cycle_ms(program.cycle_ms);
    if let Some(net) = net {
        driver.drive_net(net.clone(), seed)?;
    }
    Ok(driver)
}

/// What the host's side of a run needs to know of the program it runs.
#[derive(Clone, Copy, Debug)]
pub struct Facts {
    /// The static bound on statements per scan, from the program's report.
    pub bound_per_scan: u64,
    /// The task's interval, in milliseconds.
    pub cycle_ms: u32,
    /// How the monitor models the program's choice among the commands it may fire.
    pub choices: ChoiceModel,
}

impl From<&ProgramReport> for Facts {
    /// The event-based program's: the monitor models `first` and `local-queue` as the firmware's (the
    /// program's choice section follows the same rules over the same event ids), the global queue and the
    /// program's generator as a uniform choice.
    fn from(program: &ProgramReport) -> Facts {
        let choices = match program.policy {
            p if p == ScanPolicy::First.name() => ChoiceModel::First,
            p if p == ScanPolicy::LocalQueue.name() => ChoiceModel::LocalQueue,
            _ => ChoiceModel::Uniform,
        };
        Facts { bound_per_scan: program.bound_per_scan, cycle_ms: program.cycle_ms, choices }
    }
}

/// The host's side of [`run`], for a program already running behind `host` ([`spawn_plc`]): the
/// session, EXIT, and the report with the scan figures. A test uses it to choose what the program does
/// before the session starts.
pub fn run_spawned(
    mut host: MemoryLink,
    plc: JoinHandle<Result<ScanStats, String>>,
    program: &Facts,
    set: &PackSet,
    name: &str,
    options: &Options,
    progress: &mut dyn FnMut(&Report),
) -> Result<Report, RunError> {
    let options = Options {
        session: SessionConfig { lockstep: true, ..options.session.clone() },
        choices: program.choices,
        // The program has no tables' digest to report.
        tables: Vec::new(),
        // Its `TON`s are evaluated at scans: a timeout comes up to one task interval after its deadline.
        timer_slack_ms: u64::from(program.cycle_ms),
        ..options.clone()
    };
    let report = attach(&mut host, set, name, &options, progress);
    // EXIT ends the program's thread (the link stays open for its last answer); were the link down, the
    // thread has ended already.
    let _ = host.send(&[EXIT]);
    let stats = plc.join().map_err(|_| RunError::Program("the interpreter's thread panicked".into()))?;
    drop(host);
    // The program's own failure first: it is why the session failed, when it did.
    let (stats, mut report) = match (stats, report) {
        (Ok(stats), Ok(report)) => (stats, report),
        (Err(program), Err(session)) => {
            return Err(RunError::Program(format!("{program} (the session: {session})")))
        }
        (Err(program), Ok(_)) => return Err(RunError::Program(program)),
        (Ok(_), Err(session)) => return Err(session.into()),
    };
    report.target = "plc".into();
    report.scan = Some(ScanFigures {
        scans: stats.scans,
        max_statements: stats.max_statements,
        bound_per_scan: program.bound_per_scan,
        cycle_ms: program.cycle_ms,
    });
    report.finish(stats.scans as f64 * f64::from(program.cycle_ms) / 1000.0);
    Ok(report)
}
