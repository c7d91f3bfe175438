//! The interface level on a real board: which input pin edge is which uncontrollable event, which
//! controllable event drives which output pin, how inputs are read (edge interrupts or timer sampling),
//! and the output layer, written against the `embedded-hal` traits so that it runs on any HAL and on the
//! host with mock pins.
//!
//! `codegen emit --board FILE` writes a [`Board`] from the manifest's `[board]` section; a board
//! application configures the pins it names and calls [`Board::edge`] (interrupt mode) or
//! [`Board::changes`] (sampling mode) to turn pin activity into events, and [`Outputs`] to run commands.
//!
//! # Examples
//!
//! ```
//! use firmware::board::{Board, Edge, Input, Pull, Sampling};
//!
//! static INPUTS: [Input; 1] = [Input { pin: 3, edge: Edge::Rising, pull: Pull::Up, event: 7 }];
//! let board = Board { name: "demo", sampling: Sampling::Interrupt, inputs: &INPUTS, outputs: &[] };
//! let mut seen = Vec::new();
//! board.changes(0b0000, 0b1000, |e| seen.push(e));
//! board.changes(0b1000, 0b0000, |e| seen.push(e));
//! assert_eq!(seen, [7]);
//! ```

use embedded_hal::digital::OutputPin;

/// Which level change of an input pin makes its event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    /// Low to high.
    Rising,
    /// High to low.
    Falling,
    /// Either.
    Both,
}

/// Input pin bias.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pull {
    /// No pull resistor.
    Floating,
    /// Pull-up.
    Up,
    /// Pull-down.
    Down,
}

/// What a controllable event does to its output pin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Drive high.
    Set,
    /// Drive low.
    Clear,
    /// Drive high for this many milliseconds, then low.
    Pulse {
        /// Pulse length in milliseconds.
        ms: u16,
    },
}

/// How inputs are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// GPIO edge interrupts: every edge is seen, bursts included.
    Interrupt,
    /// A timer interrupt samples every input pin with this period; edges shorter than it may be missed
    /// (the paper's scan-cycle reading).
    Timer {
        /// Sampling period in microseconds.
        period_us: u32,
    },
}

/// One input: an edge of `pin` is the uncontrollable event `event`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Input {
    /// GPIO number.
    pub pin: u8,
    /// Which edge counts.
    pub edge: Edge,
    /// Bias.
    pub pull: Pull,
    /// Global event id.
    pub event: u8,
}

/// One output: firing `event` applies `action` to `pin`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Output {
    /// GPIO number.
    pub pin: u8,
    /// What firing does.
    pub action: Action,
    /// Global event id (controllable).
    pub event: u8,
}

/// The pin map of one board.
#[derive(Clone, Copy, Debug)]
pub struct Board<'t> {
    /// Board name, for logs.
    pub name: &'t str,
    /// How inputs are read.
    pub sampling: Sampling,
    /// Input pins (an event may have several, a pin may make two events: one per edge).
    pub inputs: &'t [Input],
    /// Output actions (a pin may serve several events, e.g. set by one and cleared by another).
    pub outputs: &'t [Output],
}

impl Board<'_> {
    /// Sampling mode: the events of every input whose pin changed from `before` to `now` (bit `n` = level
    /// of GPIO `n`, 0 to 63: a chip with two ports of 32, the nRF52840's, numbers them all) in its edge's
    /// direction, in input order.
    pub fn changes(&self, before: u64, now: u64, mut emit: impl FnMut(u8)) {
        let (rose, fell) = (!before & now, before & !now);
        for i in self.inputs {
            let bit = 1u64.checked_shl(u32::from(i.pin)).unwrap_or(0);
            let hit = match i.edge {
                Edge::Rising => rose & bit,
                Edge::Falling => fell & bit,
                Edge::Both => (rose | fell) & bit,
            };
            if hit != 0 {
                emit(i.event);
            }
        }
    }

    /// Interrupt mode: the events of a `rising` (or falling) edge on `pin`.
    pub fn edge(&self, pin: u8, rising: bool, mut emit: impl FnMut(u8)) {
        for i in self.inputs.iter().filter(|i| i.pin == pin) {
            let hit = match i.edge {
                Edge::Rising => rising,
                Edge::Falling => !rising,
                Edge::Both => true,
            };
            if hit {
                emit(i.event);
            }
        }
    }
}

/// Input sampling on an application's periodic tick: when a sample is due, and the events of the level
/// changes since the last one ([`Board::changes`]). The application reads the pins; this keeps the
/// count and the last levels, so that every board application samples the same way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    /// The levels last read (bit `n`: GPIO `n`).
    levels: u64,
    /// Ticks since the last sample.
    ticks: u32,
    /// Ticks between samples; 0: never (the application's edge interrupts make the events).
    every: u32,
}

impl Sampler {
    /// Sampling as `sampling` says on a tick of `tick_us`, from the levels `levels`: every period in
    /// timer mode (at least every tick); in interrupt mode never when the application has edge
    /// interrupts (`edge_interrupts`), else every tick. A `tick_us` of 0 is read as 1. Inline, so that
    /// an application whose sampling is a constant keeps no sampling code it never runs.
    #[inline]
    pub fn new(sampling: Sampling, tick_us: u32, levels: u64, edge_interrupts: bool) -> Self {
        let every = match sampling {
            Sampling::Timer { period_us } => (period_us / tick_us.max(1)).max(1),
            Sampling::Interrupt if edge_interrupts => 0,
            Sampling::Interrupt => 1,
        };
        Sampler { levels, ticks: 0, every }
    }

    /// One tick passed: whether a sample is due now ([`Sampler::update`] it then).
    pub fn due(&mut self) -> bool {
        if self.every == 0 {
            return false;
        }
        self.ticks += 1;
        if self.ticks < self.every {
            return false;
        }
        self.ticks = 0;
        true
    }

    /// Takes the levels `now`: the events of `board`'s inputs that changed since the last sample.
    pub fn update(&mut self, board: &Board<'_>, now: u64, emit: impl FnMut(u8)) {
        let before = core::mem::replace(&mut self.levels, now);
        board.changes(before, now, emit);
    }
}

/// The output pins of a board, `K` distinct GPIOs, with the pulses in progress.
///
/// A pulse fired again while its pin is still high would only stretch the running pulse: the plant
/// would see one rising edge for two commands. So the pin drops first and the new pulse starts after a
/// low gap of at least one full millisecond ([`Outputs::tick_ms`] comes at any time within the first;
/// the pulse starts on the second). A third firing during that gap is the same command again: it merges
/// with the pulse about to start.
pub struct Outputs<P, const K: usize> {
    pins: [P; K],
    numbers: [u8; K],
    /// Milliseconds left per pin of a running pulse (0: none).
    pulses: [u16; K],
    /// Per pin, a pulse waiting for its low gap to end: (ticks of gap left, its length in milliseconds).
    restarts: [(u8, u16); K],
}

impl<P: OutputPin, const K: usize> Outputs<P, K> {
    /// The pins, and the GPIO number of each.
    pub fn new(pins: [P; K], numbers: [u8; K]) -> Self {
        Self { pins, numbers, pulses: [0; K], restarts: [(0, 0); K] }
    }

    /// Runs every output action of `event`.
    pub fn fire(&mut self, board: &Board<'_>, event: u8) -> Result<(), P::Error> {
        for o in board.outputs.iter().filter(|o| o.event == event) {
            let Some(k) = self.numbers.iter().position(|&n| n == o.pin) else { continue };
            match o.action {
                Action::Set => self.pins[k].set_high()?,
                Action::Clear => self.pins[k].set_low()?,
                Action::Pulse { ms } => {
                    if self.restarts[k].0 > 0 {
                        // In the gap already: the pulse about to start stands for this firing too.
                    } else if self.pulses[k] > 0 {
                        self.pins[k].set_low()?;
                        self.pulses[k] = 0;
                        self.restarts[k] = (2, ms.max(1));
                    } else {
                        self.pins[k].set_high()?;
                        self.pulses[k] = ms.max(1);
                    }
                }
            }
        }
        Ok(())
    }

    /// One millisecond passed: ends the pulses that are due, starts those whose gap is over.
    pub fn tick_ms(&mut self) -> Result<(), P::Error> {
        for ((pin, left), restart) in
            self.pins.iter_mut().zip(self.pulses.iter_mut()).zip(self.restarts.iter_mut())
        {
            if restart.0 > 0 {
                restart.0 -= 1;
                if restart.0 == 0 {
                    pin.set_high()?;
                    *left = restart.1;
                }
            } else if *left > 0 {
                *left -= 1;
                if *left == 0 {
                    pin.set_low()?;
                }
            }
        }
        Ok(())
    }

    /// Every output low, pulses cancelled (the safe state).
    pub fn all_off(&mut self) -> Result<(), P::Error> {
        self.pulses = [0; K];
        self.restarts = [(0, 0); K];
        for pin in &mut self.pins {
            pin.set_low()?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::convert::Infallible;
    use std::cell::RefCell;
    use std::rc::Rc;

    /// A pin that records its level changes in a shared log, as (gpio, level).
    struct Mock(u8, Rc<RefCell<Vec<(u8, bool)>>>);

    impl embedded_hal::digital::ErrorType for Mock {
        type Error = Infallible;
    }

    impl OutputPin for Mock {
        fn set_low(&mut self) -> Result<(), Infallible> {
            self.1.borrow_mut().push((self.0, false));
            Ok(())
        }
        fn set_high(&mut self) -> Result<(), Infallible> {
            self.1.borrow_mut().push((self.0, true));
            Ok(())
        }
    }

    static INPUTS: [Input; 3] = [
        Input { pin: 1, edge: Edge::Rising, pull: Pull::Up, event: 10 },
        Input { pin: 1, edge: Edge::Falling, pull: Pull::Up, event: 11 },
        Input { pin: 4, edge: Edge::Both, pull: Pull::Floating, event: 12 },
    ];
    static OUTPUTS: [Output; 3] = [
        Output { pin: 7, action: Action::Set, event: 0 },
        Output { pin: 7, action: Action::Clear, event: 1 },
        Output { pin: 9, action: Action::Pulse { ms: 2 }, event: 2 },
    ];
    static BOARD: Board<'static> = Board {
        name: "t",
        sampling: Sampling::Timer { period_us: 1000 },
        inputs: &INPUTS,
        outputs: &OUTPUTS,
    };

    fn events(f: impl FnOnce(&mut dyn FnMut(u8))) -> Vec<u8> {
        let mut v = Vec::new();
        f(&mut |e| v.push(e));
        v
    }

    #[test]
    fn sampled_changes_and_interrupt_edges_give_the_same_events() {
        assert_eq!(events(|e| BOARD.changes(0, 0b10010, e)), [10, 12]);
        assert_eq!(events(|e| BOARD.changes(0b10010, 0, e)), [11, 12]);
        assert_eq!(events(|e| BOARD.changes(0b10010, 0b10010, e)), []);
        static HIGH: [Input; 1] = [Input { pin: 45, edge: Edge::Rising, pull: Pull::Up, event: 13 }];
        let high = Board { inputs: &HIGH, ..BOARD };
        assert_eq!(events(|e| high.changes(0, 1 << 45, e)), [13], "a pin past 31 (P1.13 on an nRF52840)");
        assert_eq!(events(|e| high.changes(0, 1 << 13, e)), []);
        assert_eq!(events(|e| BOARD.edge(1, true, e)), [10]);
        assert_eq!(events(|e| BOARD.edge(1, false, e)), [11]);
        assert_eq!(events(|e| BOARD.edge(4, false, e)), [12]);
        assert_eq!(events(|e| BOARD.edge(31, true, e)), []);
    }

    /// The ticks of the first `n` on which a sample is due.
    fn due_ticks(mut sampler: Sampler, n: u32) -> Vec<u32> {
        (1..=n).filter(|_| sampler.due()).collect()
    }

    #[test]
    fn a_sample_is_due_every_period_or_every_tick_or_never() {
        let timer = |us| Sampling::Timer { period_us: us };
        assert_eq!(due_ticks(Sampler::new(timer(3000), 1000, 0, true), 9), [3, 6, 9]);
        assert_eq!(due_ticks(Sampler::new(timer(3500), 1000, 0, false), 8), [3, 6], "whole ticks");
        assert_eq!(due_ticks(Sampler::new(timer(200), 1000, 0, true), 3), [1, 2, 3], "at least a tick");
        assert_eq!(due_ticks(Sampler::new(Sampling::Interrupt, 1000, 0, false), 3), [1, 2, 3]);
        assert_eq!(due_ticks(Sampler::new(Sampling::Interrupt, 1000, 0, true), 5), []);
        assert_eq!(due_ticks(Sampler::new(timer(3), 0, 0, true), 6), [3, 6], "a 0 µs tick read as 1 µs");
    }

    #[test]
    fn each_sample_gives_the_changes_since_the_one_before() {
        let mut sampler = Sampler::new(BOARD.sampling, 1000, 0b10, false);
        let mut update = |now| events(|e| sampler.update(&BOARD, now, e));
        assert_eq!(update(0b10), [], "pin 1 was high from the start");
        assert_eq!(update(0b10000), [11, 12]);
        assert_eq!(update(0b10010), [10]);
        assert_eq!(update(0b10010), []);
    }

    #[test]
    fn set_clear_pulse_and_safe_state() {
        let log = Rc::new(RefCell::new(Vec::new()));
        let mut out = Outputs::new([Mock(7, log.clone()), Mock(9, log.clone())], [7, 9]);
        out.fire(&BOARD, 0).unwrap();
        out.fire(&BOARD, 2).unwrap();
        out.tick_ms().unwrap();
        assert_eq!(*log.borrow(), [(7, true), (9, true)]);
        out.tick_ms().unwrap();
        assert_eq!(log.borrow().last(), Some(&(9, false)), "pulse of 2 ms ends");
        out.fire(&BOARD, 1).unwrap();
        assert_eq!(log.borrow().last(), Some(&(7, false)));
        out.fire(&BOARD, 2).unwrap();
        log.borrow_mut().clear();
        out.all_off().unwrap();
        out.tick_ms().unwrap();
        out.tick_ms().unwrap();
        assert_eq!(*log.borrow(), [(7, false), (9, false)], "pulse cancelled");
    }

    #[test]
    fn a_pulse_fired_again_restarts_after_a_full_millisecond_low() {
        let log = Rc::new(RefCell::new(Vec::new()));
        let mut out = Outputs::new([Mock(9, log.clone())], [9]);
        out.fire(&BOARD, 2).unwrap();
        out.tick_ms().unwrap();
        out.fire(&BOARD, 2).unwrap();
        assert_eq!(*log.borrow(), [(9, true), (9, false)], "dropped at once: the plant sees a new edge");
        out.tick_ms().unwrap();
        out.fire(&BOARD, 2).unwrap();
        assert_eq!(log.borrow().len(), 2, "still low through the first tick; a third firing merges");
        out.tick_ms().unwrap();
        assert_eq!(log.borrow().last(), Some(&(9, true)), "high again on the second tick");
        out.tick_ms().unwrap();
        out.tick_ms().unwrap();
        assert_eq!(log.borrow().last(), Some(&(9, false)), "a full 2 ms pulse");
        assert_eq!(log.borrow().len(), 4);
    }
}
