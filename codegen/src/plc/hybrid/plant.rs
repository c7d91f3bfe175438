//! The virtual plant of a hybrid controller's run (`codegen run --target plc` on a `[hybrid]`
//! manifest): the plant net's own token game with its delays, on the PLC's scan clock, whose sensors
//! the plant drives and whose actuators it reads from the program.
//!
//! The plant keeps its own marking and, per transition, the scan since which its input places have
//! been marked. It follows the program: a firing the program makes (read back from its place bits) is
//! the plant's too, once the plant has checked that it can happen physically —
//!
//! - the transition is enabled in the plant's marking and leads to the program's new marking;
//! - its condition holds on the sensors the plant presented to that scan;
//! - its input places have been marked for its delay, on the scan clock (`cycle_ms` per scan);
//!
//! and after every scan the actuators are what the marking's place actions say. A failed check is a
//! [`Finding`].
//!
//! **Sensors.** A sensor (a `free` input) is low unless a transition whose condition reads it may
//! happen physically: state-enabled in the plant's marking, with every actuator its input places
//! drive at that value in the program's outputs (a machine's "done" needs its motor on). Once such a
//! transition is there, the plant draws (seeded) after how many scans the sensor comes on: at once
//! one time in [`AT_ONCE`] (a part already waiting when the machine becomes free), else uniformly in
//! `1..=window` scans; it holds the sensor on while the transition stays possible and lets it fall
//! once it is not. The window is [`WINDOW_DELAYS`] times the net's longest delay in scans (at least
//! [`MIN_WINDOW`]), so a sensor's wait is sometimes shorter and sometimes longer than a timed
//! transition's, or than two of them, and the run meets the orders that differ.

use crate::net::condition::Value;
use crate::net::interpretation::{Direction, Interpretation};
use crate::net::model::Marking;
use crate::plant::Rng;

/// The shortest sensor window, in scans (a net without delays).
pub const MIN_WINDOW: u64 = 10;
/// The sensor window in the net's longest delays.
pub const WINDOW_DELAYS: u64 = 4;
/// One sensor in this many comes on in the first scan its transition may happen.
pub const AT_ONCE: u64 = 4;

/// Why the plant refused what the program did in one scan.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Finding(pub String);

/// One sensor as the plant drives it.
#[derive(Clone, Copy, Debug, Default)]
struct Sensor {
    /// The scan from which it is on, drawn when a transition reading it became possible.
    on_from: Option<u64>,
    level: bool,
}

/// The plant net as the physical plant of a hybrid controller's run; see the module documentation.
#[derive(Clone, Debug)]
pub struct NetPlant<'a> {
    net: &'a Interpretation,
    cycle_ms: u32,
    window: u64,
    rng: Rng,
    seed: u64,
    marking: Marking,
    /// Per transition, the scan since which its input places have all been marked.
    since: Vec<Option<u64>>,
    /// Per signal (the net's order); only inputs are driven.
    sensors: Vec<Sensor>,
    /// Per signal, the transitions whose condition reads it.
    readers: Vec<Vec<usize>>,
}

impl<'a> NetPlant<'a> {
    /// The plant of `net` on a scan clock of `cycle_ms`, its draws seeded with `seed`, in the initial
    /// marking.
    pub fn new(net: &'a Interpretation, cycle_ms: u32, seed: u64) -> NetPlant<'a> {
        let cycle = u64::from(cycle_ms.max(1));
        let longest = net.delays.iter().map(|&d| u64::from(d).div_ceil(cycle)).max().unwrap_or(0);
        let mut readers = vec![Vec::new(); net.signals.len()];
        for (t, cond) in net.conditions.iter().enumerate() {
            for &s in cond.vars() {
                if !readers[s].contains(&t) {
                    readers[s].push(t);
                }
            }
        }
        let mut plant = NetPlant {
            net,
            cycle_ms,
            window: (WINDOW_DELAYS * longest).max(MIN_WINDOW),
            rng: Rng::new(seed),
            seed,
            marking: Vec::new(),
            since: Vec::new(),
            sensors: Vec::new(),
            readers,
        };
        plant.reset();
        plant
    }

    /// Back to the initial marking, every sensor low, the draws from the seed again (the boot scan is
    /// scan 0).
    pub fn reset(&mut self) {
        self.marking = self.net.net.initial_marking();
        self.sensors = vec![Sensor::default(); self.net.signals.len()];
        self.since = vec![None; self.net.net.transitions.len()];
        self.rng = Rng::new(self.seed);
        self.mark_since(0);
    }

    /// The plant's marking.
    pub fn marking(&self) -> &[u32] {
        &self.marking
    }

    /// The longest a correct program can leave the plant without a firing, in scans: a sensor's
    /// window and the longest delay, with margin.
    pub fn patience(&self) -> u64 {
        let cycle = u64::from(self.cycle_ms.max(1));
        let longest = self.net.delays.iter().map(|&d| u64::from(d).div_ceil(cycle)).max().unwrap_or(0);
        2 * (self.window + longest) + MIN_WINDOW
    }

    /// Whether transition `t` may happen physically: state-enabled in the marking, every actuator its
    /// input places drive at that value in `outputs` (per signal; inputs ignored).
    fn possible(&self, t: usize, outputs: &[bool]) -> bool {
        let net = &self.net.net;
        net.state_enabled(t, &self.marking)
            && net.transitions[t].inputs.iter().all(|&(p, _)| {
                self.net.actions[p].iter().all(|&(s, v)| {
                    self.net.signals[s].direction != Direction::Output || outputs.get(s) == Some(&v)
                })
            })
    }

    /// The sensors for scan `scan`, given the actuators the program left after the scan before
    /// (`outputs`, per signal): per signal, its level (outputs as given).
    pub fn sense(&mut self, scan: u64, outputs: &[bool]) -> Vec<bool> {
        let mut levels = outputs.to_vec();
        for (s, level) in levels.iter_mut().enumerate() {
            if self.net.signals[s].direction != Direction::Input {
                continue;
            }
            let wanted = self.readers[s].iter().any(|&t| self.possible(t, outputs));
            let sensor = &mut self.sensors[s];
            if !wanted {
                *sensor = Sensor::default();
            } else if sensor.on_from.is_none() {
                let wait = if self.rng.below(AT_ONCE) == 0 { 0 } else { self.rng.between(1, self.window) };
                sensor.on_from = Some(scan + wait);
            }
            let sensor = &mut self.sensors[s];
            sensor.level = sensor.on_from.is_some_and(|from| scan >= from);
            *level = sensor.level;
        }
        levels
    }

    /// The program went from marking `before` to `after` in scan `scan` under the signal values
    /// `signals` (the sensors [`NetPlant::sense`] gave, the outputs before the scan): the transition it
    /// fired, now fired in the plant too, or why the plant cannot take it.
    pub fn fire(
        &mut self,
        scan: u64,
        before: &[u32],
        after: &[u32],
        signals: &[bool],
    ) -> Result<usize, Finding> {
        let net = &self.net.net;
        let names = |m: &[u32]| net.marked(m).join(".");
        if before != self.marking.as_slice() {
            return Err(Finding(format!(
                "the program's marking {} is not the plant's {}",
                names(before),
                names(&self.marking)
            )));
        }
        let fired: Vec<usize> = (0..net.transitions.len())
            .filter(|&t| net.state_enabled(t, before) && net.fire(t, before).as_deref() == Some(after))
            .collect();
        let [t] = fired[..] else {
            return Err(Finding(format!(
                "the program went from {} to {}: no firing of one transition of the net",
                names(before),
                names(after)
            )));
        };
        let id = &net.transitions[t].id;
        if !self.net.conditions[t].satisfiable(|&s| Value::Is(signals.get(s).copied().unwrap_or(false))) {
            return Err(Finding(format!("{id} fired while its condition is false")));
        }
        let delay = u64::from(self.net.delays[t]);
        let marked_ms = self.since[t].map_or(0, |from| (scan - from) * u64::from(self.cycle_ms));
        if marked_ms < delay {
            return Err(Finding(format!("{id} fired after {marked_ms} ms of its {delay} ms delay")));
        }
        self.marking = after.to_vec();
        self.mark_since(scan);
        Ok(t)
    }

    /// The actuators (per signal; inputs ignored) against the marking's place actions: an actuator is
    /// on while a place setting it is marked, off otherwise.
    pub fn check_outputs(&self, outputs: &[bool]) -> Result<(), Finding> {
        for (s, signal) in self.net.signals.iter().enumerate() {
            if signal.direction != Direction::Output {
                continue;
            }
            let on = self
                .net
                .actions
                .iter()
                .zip(&self.marking)
                .any(|(acts, &k)| k > 0 && acts.iter().any(|&(a, v)| a == s && v));
            if outputs.get(s) != Some(&on) {
                return Err(Finding(format!(
                    "actuator {} is {} with {} marked",
                    signal.name,
                    if on { "off" } else { "on" },
                    self.net.net.marked(&self.marking).join(".")
                )));
            }
        }
        Ok(())
    }

    /// Starts the delay of every transition whose input places became all marked at `scan`, and stops
    /// it where they are not.
    fn mark_since(&mut self, scan: u64) {
        for (t, tr) in self.net.net.transitions.iter().enumerate() {
            let marked = tr.inputs.iter().all(|&(p, w)| self.marking[p] >= w);
            self.since[t] = match (marked, self.since[t]) {
                (true, Some(from)) => Some(from),
                (true, None) => Some(scan),
                (false, _) => None,
            };
        }
    }
}
