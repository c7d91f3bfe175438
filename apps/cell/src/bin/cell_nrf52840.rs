//! The supervisor firmware on an nRF52840 DK (nRF52840, Cortex-M4F; nrf52840-hal): input pins sampled
//! every 1 ms SysTick tick (edges found by comparing levels, whatever the manifest's `[board]
//! sampling`: no GPIOTE yet), the decision loop in `idle`, commands to output pins (set, clear, timed
//! pulse) through `firmware::board::Outputs` (embedded-hal traits), defmt over RTT. Flash and run with
//! `cargo run --release` in a `codegen new --board nrf52840-dk` project (probe-rs, the on-board J-Link).
//!
//! Pins are numbered as the manifest's `[board]` numbers them, which is the chip's PSEL numbering: P0.n
//! is `n`, P1.n is `32 + n` (the DK's buttons are 11, 12, 24, 25, its LEDs 13 to 16). The core runs on
//! the 64 MHz internal oscillator as reset leaves it. Tables: `SCT_TABLES_FILE` (see `build.rs`).
//! Randomness: the manifest's seed.
#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

/// The emitted tables.
#[allow(dead_code)]
mod tables {
    include!(env!("SCT_TABLES_FILE"));
}

mod board_app;
mod systick_board;

use core::convert::Infallible;

use embedded_hal::digital::InputPin;
use firmware::board::{Outputs, Pull};
use nrf52840_hal::gpio::{Disconnected, Floating, Input, Output, Pin, PullDown, PullUp, PushPull};

/// The core clock as reset leaves it (HFINT).
const CORE_HZ: u32 = 64_000_000;

/// PSEL numbers past the last pin of P1 (P1.15).
const PINS: u8 = 48;

type Outs = Outputs<Pin<Output<PushPull>>, { tables::OUTPUT_PINS.len() }>;

/// GPIO `num` (PSEL numbering), not configured yet; `None` past P1.15.
fn pin(num: u8) -> Option<Pin<Disconnected>> {
    // SAFETY: `num` is a valid PSEL value (port bit 5, line bits 0-4, below 48); `codegen emit` writes
    // each pin once, in INPUT_PINS or in OUTPUT_PINS, and this firmware takes no other pin, so no
    // second instance of this pin exists.
    (num < PINS).then(|| unsafe { Pin::from_psel_bits(u32::from(num)) })
}

/// An input pin with the pull the manifest gives it: the HAL types the pull, the manifest chooses it
/// per pin at build time.
enum InPin {
    /// No pull resistor.
    Floating(Pin<Input<Floating>>),
    /// Pull-up.
    Up(Pin<Input<PullUp>>),
    /// Pull-down.
    Down(Pin<Input<PullDown>>),
}

impl InPin {
    /// GPIO `num` as an input with `pull`; `None` past P1.15.
    fn new(num: u8, pull: Pull) -> Option<Self> {
        let p = pin(num)?;
        Some(match pull {
            Pull::Floating => InPin::Floating(p.into_floating_input()),
            Pull::Up => InPin::Up(p.into_pullup_input()),
            Pull::Down => InPin::Down(p.into_pulldown_input()),
        })
    }
}

impl embedded_hal::digital::ErrorType for InPin {
    type Error = Infallible;
}

impl InputPin for InPin {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        match self {
            InPin::Floating(p) => p.is_high(),
            InPin::Up(p) => p.is_high(),
            InPin::Down(p) => p.is_high(),
        }
    }

    fn is_low(&mut self) -> Result<bool, Infallible> {
        self.is_high().map(|h| !h)
    }
}

#[rtic::app(device = nrf52840_hal::pac)]
mod app {
    use super::board_app::{self, halt, Driver};
    use super::systick_board::{self, Rt};
    use super::{pin, tables, InPin, Outs, CORE_HZ};
    use firmware::board::{Pull, Sampler};
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
    use nrf52840_hal::gpio::Level;

    #[shared]
    struct Shared {
        outputs: Outs,
    }

    #[local]
    struct Local {
        consumer: InputConsumer<'static>,
        producer: InputProducer<'static>,
        inputs: [InPin; tables::INPUT_PINS.len()],
        runtime: Rt,
        sampler: Sampler,
    }

    #[init(local = [queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut inputs: [InPin; tables::INPUT_PINS.len()] = core::array::from_fn(|i| {
            let pull = tables::INPUT_PULLS.get(i).copied().unwrap_or(Pull::Floating);
            InPin::new(tables::INPUT_PINS[i], pull).unwrap_or_else(|| halt("input pin past P1.15"))
        });
        let out_pins = tables::OUTPUT_PINS.map(|n| {
            let p = pin(n).unwrap_or_else(|| halt("output pin past P1.15"));
            p.into_push_pull_output(Level::Low)
        });
        let outputs = board_app::outputs(out_pins);
        systick_board::start(cx.core.SYST, CORE_HZ);
        let (producer, consumer) = cx.local.queue.split();
        let runtime = systick_board::runtime();
        let sampler = systick_board::sampler(&mut inputs);
        board_app::announce(tables::SET.automata.len());
        (Shared { outputs }, Local { consumer, producer, inputs, runtime, sampler })
    }

    /// The 1 ms tick: ends pulses; samples the inputs every period (every tick in interrupt mode).
    #[task(binds = SysTick, shared = [outputs], local = [producer, inputs, sampler])]
    fn tick(mut cx: tick::Context) {
        let l = cx.local;
        systick_board::tick(&mut cx.shared.outputs, l.sampler, l.inputs, l.producer);
    }

    /// The decision loop; sleeps in `wfi` while there is nothing to do.
    #[idle(shared = [outputs], local = [consumer, runtime])]
    fn idle(mut cx: idle::Context) -> ! {
        board_app::decide(cx.local.runtime, cx.local.consumer, &mut Driver(&mut cx.shared.outputs), || ())
    }
}
