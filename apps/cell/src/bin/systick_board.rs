//! What the boards that tick on SysTick share (the Nucleo-F401RE's and the nRF52840 DK's applications,
//! not the Pico's, whose timer alarm ticks and whose ring oscillator seeds): the 1 ms SysTick at the
//! core's clock, the runtime seeded from the manifest, and the tick's work — the tables' timers' millisecond
//! counted, pulses timed, inputs sampled every tick (no edge interrupts on these boards yet). Declared as `mod systick_board;` beside
//! `mod board_app;`; `codegen new` writes it beside `main.rs` for these boards.

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use embedded_hal::digital::{InputPin, OutputPin};
use firmware::board::{Outputs, Sampler};
use firmware::input_queue::InputProducer;
use firmware::rng::SeedEntropy;

use crate::board_app::{self, TICK_US};
use crate::tables;

/// The runtime on the tables' default layout, seeded from the manifest.
pub type Rt = tables::Runtime<tables::Policy, SeedEntropy>;

/// Starts SysTick's interrupt every [`TICK_US`] on the core clock of `core_hz`.
pub fn start(mut syst: SYST, core_hz: u32) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(core_hz / 1_000_000 * TICK_US - 1);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// The runtime, seeded with the manifest's seed. The tables were checked when they were compiled
/// (`tables::CHECKED`).
pub fn runtime() -> Rt {
    Rt::new(tables::CHECKED, tables::CONFIG, tables::Policy::default(), SeedEntropy::new(tables::SEED))
}

/// The sampler of `inputs`: every tick, whatever `[board] sampling` says, when it says interrupts.
pub fn sampler<P: InputPin>(inputs: &mut [P]) -> Sampler {
    board_app::sampler(board_app::levels(inputs), false)
}

/// One SysTick: counts the millisecond for the timers, ends the pulses that are due, and samples the
/// inputs when a sample is due.
pub fn tick<P: OutputPin, I: InputPin>(
    outputs: &mut impl rtic::Mutex<T = Outputs<P, { tables::OUTPUT_PINS.len() }>>,
    sampler: &mut Sampler,
    inputs: &mut [I],
    q: &mut InputProducer<'static>,
) {
    board_app::count_ms();
    board_app::tick_outputs(outputs);
    if sampler.due() {
        board_app::update(sampler, board_app::levels(inputs), q);
    }
}
