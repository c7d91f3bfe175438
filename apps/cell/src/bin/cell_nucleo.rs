//! The supervisor firmware on a Nucleo-F401RE (STM32F401RE, Cortex-M4F; stm32f4xx-hal's device crate):
//! input pins sampled every 1 ms SysTick tick (edges found by comparing levels, whatever the manifest's
//! `[board] sampling`), the decision loop in `idle`, commands to output pins (set, clear, timed pulse)
//! through `firmware::board::Outputs` (embedded-hal traits), defmt over RTT. Flash and run with
//! `cargo run --release` in a `codegen new --board nucleo-f401re` project (probe-rs, the on-board ST-LINK).
//!
//! Pins are numbered as the manifest's `[board]` numbers them: pin `n` is GPIO port `n / 16` (0 = A,
//! 1 = B, … 4 = E), line `n % 16` (PA5 = 5, PC13 = 45). The core runs on the 16 MHz internal oscillator
//! as reset leaves it. Tables: `SCT_TABLES_FILE` (see `build.rs`). Randomness: the manifest's seed.
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

use firmware::board::{Outputs, Pull};
use stm32f4xx_hal::pac;

/// The core clock as reset leaves it (HSI).
const CORE_HZ: u32 = 16_000_000;

/// GPIO ports A to E.
const PORTS: u8 = 5;

type Outs = Outputs<Gpio, { tables::OUTPUT_PINS.len() }>;

/// One GPIO line by number, driven through its port's registers: the embedded-hal pin the runtime's
/// `Outputs` and the sampling take. The HAL's pins are typed by port and line at compile time; the
/// manifest numbers them at build time, so this is the by-number pin the RP2040's HAL has built in.
pub struct Gpio {
    /// The port, 0 (A) to 4 (E).
    port: u8,
    /// The line, 0 to 15.
    line: u8,
}

impl Gpio {
    /// Pin `num` as an input with `pull`, or as a push-pull output driven low; `None` past port E.
    fn new(num: u8, output: bool, pull: Pull) -> Option<Self> {
        let pin = Gpio { port: num / 16, line: num % 16 };
        if pin.port >= PORTS {
            return None;
        }
        let regs = pin.regs();
        let shift = 2 * u32::from(pin.line);
        let pupd = match pull {
            Pull::Floating => 0b00,
            Pull::Up => 0b01,
            Pull::Down => 0b10,
        };
        // SAFETY: plain register values (RM0368 §8.4): reset state low, then the line's pull and mode
        // fields; `init` does this before any interrupt is enabled, so the read-modify-writes race nothing.
        unsafe {
            if output {
                regs.bsrr().write(|w| w.bits(1 << (pin.line + 16)));
            }
            regs.pupdr().modify(|r, w| w.bits(r.bits() & !(0b11 << shift) | pupd << shift));
            regs.moder().modify(|r, w| w.bits(r.bits() & !(0b11 << shift) | u32::from(output) << shift));
        }
        Some(pin)
    }

    /// The port's registers.
    fn regs(&self) -> &'static pac::gpioa::RegisterBlock {
        let at = pac::GPIOA::ptr() as usize + 0x400 * usize::from(self.port);
        // SAFETY: GPIOA..GPIOE are register blocks of the same layout 0x400 apart (RM0368 §2.3) and
        // `port` is below PORTS; `codegen emit` writes each pin once, in INPUT_PINS or in OUTPUT_PINS,
        // so no two `Gpio` share a line, and BSRR/IDR accesses touch this line only.
        unsafe { &*(at as *const pac::gpioa::RegisterBlock) }
    }
}

impl embedded_hal::digital::ErrorType for Gpio {
    type Error = Infallible;
}

impl embedded_hal::digital::OutputPin for Gpio {
    fn set_low(&mut self) -> Result<(), Infallible> {
        // SAFETY: BSRR is write-only and atomic: it touches this line only.
        self.regs().bsrr().write(|w| unsafe { w.bits(1 << (self.line + 16)) });
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        // SAFETY: as in `set_low`.
        self.regs().bsrr().write(|w| unsafe { w.bits(1 << self.line) });
        Ok(())
    }
}

impl embedded_hal::digital::InputPin for Gpio {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.regs().idr().read().bits() & (1 << self.line) != 0)
    }

    fn is_low(&mut self) -> Result<bool, Infallible> {
        self.is_high().map(|h| !h)
    }
}

#[rtic::app(device = stm32f4xx_hal::pac)]
mod app {
    use super::board_app::{self, halt, Driver};
    use super::systick_board::{self, Rt};
    use super::{tables, Gpio, Outs, CORE_HZ};
    use firmware::board::{Pull, Sampler};
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};

    #[shared]
    struct Shared {
        outputs: Outs,
    }

    #[local]
    struct Local {
        consumer: InputConsumer<'static>,
        producer: InputProducer<'static>,
        inputs: [Gpio; tables::INPUT_PINS.len()],
        runtime: Rt,
        sampler: Sampler,
    }

    #[init(local = [queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        // GPIOA..GPIOE clocks on.
        cx.device.RCC.ahb1enr().modify(|r, w| unsafe { w.bits(r.bits() | 0b1_1111) });
        let mut inputs: [Gpio; tables::INPUT_PINS.len()] = core::array::from_fn(|i| {
            let pull = tables::INPUT_PULLS.get(i).copied().unwrap_or(Pull::Floating);
            Gpio::new(tables::INPUT_PINS[i], false, pull).unwrap_or_else(|| halt("input pin past port E"))
        });
        let out_pins = tables::OUTPUT_PINS
            .map(|n| Gpio::new(n, true, Pull::Floating).unwrap_or_else(|| halt("output pin past port E")));
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
