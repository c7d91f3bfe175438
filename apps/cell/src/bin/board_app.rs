//! What every board application shares (the Pico's, the Nucleo's, the nRF52840 DK's): the runtime's
//! published status, the outputs as the event loop's port, input sampling on a tick, the milliseconds
//! the tick counts for the tables' timers, the decision loop.
//! Each application (`cell_<board>.rs`, a `codegen new` project's `src/main.rs`) declares it as
//! `mod board_app;` beside its own `mod tables` and keeps only its board's wiring: clocks, pins, timer.
//!
//! It is a module of the application, not of the `firmware` library, because it ties the runtime to
//! what only an application has: the emitted tables (`crate::tables`), RTIC's resource locks, defmt's
//! transport and the core's `wfi`. `codegen new` writes it beside `main.rs` (`src/board_app.rs`).

use core::sync::atomic::{AtomicU32, Ordering};

use embedded_hal::digital::{InputPin, OutputPin};
use firmware::board::{Outputs, Sampler};
use firmware::event_loop::{EventLoop, Note, Poll, Port};
use firmware::input_queue::{InputConsumer, InputProducer};
use firmware::link::{Hold, SAFE};
use firmware::shell::Decide;
use firmware::status::Published;

use crate::tables;

/// Never set: a board has no host link to send HOLD.
pub static HOLD: Hold = Hold::new();

/// The runtime's counters after every turn of the loop, for an emulator harness or a debugger
/// (`firmware::status`; `harness/rp2040/` reads it by this name).
#[no_mangle]
pub static SCT_STATUS: Published = Published::new();

/// The timer tick every board application runs on: pulses are timed in it, inputs sampled in it, the
/// tables' timers advanced by it (one tick, one millisecond).
pub const TICK_US: u32 = 1_000;

/// Milliseconds the tick counted that the decision loop has not yet given the timers: a counter, not a
/// queue, so a loop that falls behind catches up in one step (bounded, no heap).
static ELAPSED_MS: AtomicU32 = AtomicU32::new(0);

/// One millisecond passed: called by the tick's interrupt, counted for the tables' timers
/// (`tables::TIMERS`), which the decision loop advances by it. Only the tick writes it outside the
/// loop's critical section, so a load and a store suffice (the Cortex-M0+ has no atomic add).
pub fn count_ms() {
    let ms = ELAPSED_MS.load(Ordering::Relaxed);
    ELAPSED_MS.store(ms.saturating_add(1), Ordering::Relaxed);
}

/// The milliseconds counted since the last call, the count back to 0 (with the tick masked meanwhile).
fn take_ms() -> u32 {
    cortex_m::interrupt::free(|_| {
        let ms = ELAPSED_MS.load(Ordering::Relaxed);
        ELAPSED_MS.store(0, Ordering::Relaxed);
        ms
    })
}

/// Stops for good after a configuration error (logged); the outputs stay as they are.
pub fn halt(why: &str) -> ! {
    defmt::error!("halt: {=str}", why);
    loop {
        cortex_m::asm::wfi();
    }
}

/// Logs what runs where, once at boot: the set's name, the board's, the number of automata and pins.
pub fn announce(automata: usize) {
    defmt::info!(
        "{=str} on {=str}: {=usize} automata, {=usize} inputs, {=usize} outputs",
        tables::NAME,
        tables::BOARD.name,
        automata,
        tables::BOARD.inputs.len(),
        tables::BOARD.outputs.len()
    );
}

/// The output pins `pins` (those of `tables::OUTPUT_PINS`, in its order) as the outputs the tables
/// drive, every one low; halts when a pin cannot be driven.
pub fn outputs<P: OutputPin>(
    pins: [P; tables::OUTPUT_PINS.len()],
) -> Outputs<P, { tables::OUTPUT_PINS.len() }> {
    let mut outputs = Outputs::new(pins, tables::OUTPUT_PINS);
    if outputs.all_off().is_err() {
        halt("output pins");
    }
    outputs
}

/// The outputs, behind the RTIC lock `L`, as the event loop's port: a fired event runs its actions;
/// SAFE turns everything off.
pub struct Driver<'a, L>(pub &'a mut L);

impl<P: OutputPin, const K: usize, L: rtic::Mutex<T = Outputs<P, K>>> Port for Driver<'_, L> {
    fn send(&mut self, byte: u8) {
        let ok = self.0.lock(|o| if byte == SAFE { o.all_off() } else { o.fire(&tables::BOARD, byte) });
        if ok.is_err() {
            defmt::error!("output pin error");
        }
    }

    fn note(&mut self, note: Note) {
        match note {
            Note::Unexpected { event, automaton } => {
                defmt::warn!("unexpected event {=u8} in automaton {=u8}", event, automaton)
            }
            Note::Unknown(byte) => defmt::warn!("unknown event {=u8}", byte),
            Note::Safe => defmt::error!("fault: safe state, outputs off, deciding stopped"),
            Note::Redecided => defmt::debug!("guard: input arrived while choosing"),
        }
    }
}

/// The input pins' levels: bit `n` set when GPIO `n` (the manifest's number) reads high. `inputs` are
/// the pins of `tables::INPUT_PINS`, in its order.
pub fn levels<P: InputPin>(inputs: &mut [P]) -> u64 {
    let mut levels = 0;
    for (p, num) in inputs.iter_mut().zip(tables::INPUT_PINS) {
        if p.is_high().unwrap_or(false) {
            levels |= 1u64.checked_shl(u32::from(num)).unwrap_or(0);
        }
    }
    levels
}

/// Queues `event`; counts it as an overflow when the buffer is full (never silent).
pub fn push(q: &mut InputProducer<'static>, event: u8) {
    if q.push(event).is_err() {
        q.count_overflow();
    }
}

/// The sampler of the inputs whose levels are `levels` now, on the [`TICK_US`] tick: every `[board]
/// sampling` period; in interrupt mode never on a board with `edge_interrupts`, else every tick.
pub fn sampler(levels: u64, edge_interrupts: bool) -> Sampler {
    Sampler::new(tables::BOARD.sampling, TICK_US, levels, edge_interrupts)
}

/// Takes the levels `now` into `sampler`, queueing the events of the changes since its last sample.
pub fn update(sampler: &mut Sampler, now: u64, q: &mut InputProducer<'static>) {
    sampler.update(&tables::BOARD, now, |e| push(q, e));
}

/// One millisecond passed for the outputs behind `outputs`: ends the pulses that are due.
pub fn tick_outputs<P: OutputPin, const K: usize>(outputs: &mut impl rtic::Mutex<T = Outputs<P, K>>) {
    if outputs.lock(|o| o.tick_ms()).is_err() {
        defmt::error!("output pin error");
    }
}

/// The decision loop of `idle`: advances the tables' timers by the milliseconds the tick counted
/// ([`count_ms`]; a timeout that falls due is taken as an input), drains the inputs into the runtime,
/// decides, drives the outputs behind `outputs`, publishes the counters ([`SCT_STATUS`]); when there
/// is nothing to do, calls `on_idle` and sleeps in `wfi` unless an input came in meanwhile (the tick
/// wakes it every millisecond).
pub fn decide(
    rt: &mut impl Decide,
    rx: &mut InputConsumer<'static>,
    outputs: &mut impl Port,
    mut on_idle: impl FnMut(),
) -> ! {
    let mut event_loop = EventLoop::new().with_timers(&tables::TIMERS);
    loop {
        event_loop.elapse(take_ms(), rt, outputs);
        let poll = event_loop.turn(rt, rx, &HOLD, outputs);
        SCT_STATUS.store(&rt.counters().to_array(), rt.is_safe());
        if poll != Poll::Busy {
            on_idle();
            cortex_m::interrupt::free(|_| {
                if poll.may_sleep(rx, &HOLD) {
                    cortex_m::asm::wfi();
                }
            });
        }
    }
}
