//! The supervisor firmware on a Raspberry Pi Pico (RP2040, rp2040-hal): input pins → input buffer by GPIO
//! edge interrupts or timer sampling (the manifest's `[board] sampling`), the decision loop in `idle`,
//! commands to output pins (set, clear, timed pulse) through `firmware::board::Outputs` (embedded-hal
//! traits), defmt over RTT. Flash and run with `cargo pico` (probe-rs); docs/firmware.md, "Flash a board".
//!
//! Tables and pin map: `SCT_TABLES_FILE` (see `build.rs`), the cell's with its manifest's `[board]` by
//! default. Randomness: the RP2040's ring-oscillator random bit, gathered while the loop is idle, mixed with
//! the microsecond timer.
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

use core::sync::atomic::{AtomicU32, Ordering};

use board_app::halt;
use firmware::board::Outputs;
use firmware::rng::Entropy;
use rp2040_hal::gpio::{new_pin, DynBankId, DynPinId, DynPullType, FunctionSioInput, FunctionSioOutput, Pin};
use rp2040_hal::pac;

/// Second-stage bootloader for the Pico's W25Q080 flash.
#[link_section = ".boot2"]
#[used]
static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

/// The Pico's crystal.
const XOSC_HZ: u32 = 12_000_000;

type InPin = Pin<DynPinId, FunctionSioInput, DynPullType>;
type OutPin = Pin<DynPinId, FunctionSioOutput, DynPullType>;
type Outs = Outputs<OutPin, { tables::OUTPUT_PINS.len() }>;

/// The runtime on the tables made for the Cortex-M0+ (`indexed` layout: no rank, aligned mask loads).
type Rt = tables::m0plus::Runtime<tables::Policy, Rosc>;

/// Entropy from the ring oscillator's random bit and the timer's low microseconds (jitter). The bits are
/// gathered one per idle turn of the loop ([`Rosc::sample`]), spaced out in time: RANDOMBIT is the
/// oscillator's level, which back-to-back reads see many times over, and a reseed then costs the decision
/// that draws it two loads instead of 32 register reads.
struct Rosc;

/// The ring-oscillator bits gathered so far, rotated in one at a time. Only thread mode (the loop, and
/// the runtime in it) touches it; an atomic because a `static` must be `Sync`.
static ROSC_BITS: AtomicU32 = AtomicU32::new(0);

impl Rosc {
    /// Rotates one more random bit into the gathered ones.
    fn sample() {
        // SAFETY: a read-only register (ROSC RANDOMBIT); reading it has no side effect.
        let rosc = unsafe { &*pac::ROSC::ptr() };
        let bit = u32::from(rosc.randombit().read().randombit().bit());
        ROSC_BITS.store(ROSC_BITS.load(Ordering::Relaxed).rotate_left(1) ^ bit, Ordering::Relaxed);
    }

    /// The source, with a word of bits gathered at once for the first seed.
    fn new() -> Self {
        for _ in 0..32 {
            Self::sample();
        }
        Rosc
    }
}

impl Entropy for Rosc {
    fn entropy(&mut self) -> u32 {
        // SAFETY: a read-only register (TIMER TIMERAWL); reading it has no side effect.
        let timer = unsafe { &*pac::TIMER::ptr() };
        timer.timerawl().read().bits() ^ ROSC_BITS.load(Ordering::Relaxed)
    }
}

/// The last GPIO of bank 0.
const LAST_GPIO: u8 = 29;

/// GPIO `num` of bank 0 with function `F`; halts past GPIO 29 (the pin map numbers up to 63).
fn pin<F: rp2040_hal::gpio::Function>(num: u8) -> Pin<DynPinId, F, DynPullType> {
    if num > LAST_GPIO {
        halt("pin past GPIO 29");
    }
    // SAFETY: `num` is a GPIO of bank 0; `codegen emit` writes each GPIO once, either in INPUT_PINS or
    // in OUTPUT_PINS, and this firmware takes no other pin, so no second instance of this pin exists.
    let p = unsafe { new_pin(DynPinId { bank: DynBankId::Bank0, num }) };
    p.into_pull_type::<DynPullType>().try_into_function::<F>().unwrap_or_else(|_| halt("pin function"))
}

#[rtic::app(device = rp2040_hal::pac)]
mod app {
    use super::board_app::{self, halt, Driver, TICK_US};
    use super::{pin, tables, InPin, Outs, Rosc, Rt, XOSC_HZ};
    use firmware::board::{Edge, Pull, Sampler, Sampling};
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
    use rp2040_hal::clocks::init_clocks_and_plls;
    use rp2040_hal::fugit::MicrosDurationU32;
    use rp2040_hal::gpio::{DynPullType, FunctionSioInput, FunctionSioOutput, Interrupt};
    use rp2040_hal::timer::{Alarm, Alarm0, Timer};
    use rp2040_hal::{Sio, Watchdog};

    #[shared]
    struct Shared {
        producer: InputProducer<'static>,
        outputs: Outs,
        inputs: [InPin; tables::INPUT_PINS.len()],
    }

    #[local]
    struct Local {
        consumer: InputConsumer<'static>,
        runtime: Rt,
        alarm: Alarm0,
        sampler: Sampler,
    }

    #[init(local = [queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut pac = cx.device;
        let mut watchdog = Watchdog::new(pac.WATCHDOG);
        let Ok(clocks) = init_clocks_and_plls(
            XOSC_HZ,
            pac.XOSC,
            pac.CLOCKS,
            pac.PLL_SYS,
            pac.PLL_USB,
            &mut pac.RESETS,
            &mut watchdog,
        ) else {
            halt("clocks")
        };
        let sio = Sio::new(pac.SIO);
        // Takes IO_BANK0 and PADS_BANK0 out of reset; the pins are then taken one by one by number.
        let _bank =
            rp2040_hal::gpio::Pins::new(pac.IO_BANK0, pac.PADS_BANK0, sio.gpio_bank0, &mut pac.RESETS);
        let mut inputs = tables::INPUT_PINS.map(pin::<FunctionSioInput>);
        for (p, pull) in inputs.iter_mut().zip(tables::INPUT_PULLS) {
            p.set_pull_type(match pull {
                Pull::Floating => DynPullType::None,
                Pull::Up => DynPullType::Up,
                Pull::Down => DynPullType::Down,
            });
        }
        if tables::BOARD.sampling == Sampling::Interrupt {
            // INTR latches edges whether or not their interrupt is enabled: one latched while the pins
            // were set up (a pull moving a line nothing drives yet) would be taken as an event at once.
            // Cleared before the interrupts are enabled, as pico-sdk's `gpio_set_irq_enabled` does.
            for p in inputs.iter_mut() {
                p.clear_interrupt(Interrupt::EdgeHigh);
                p.clear_interrupt(Interrupt::EdgeLow);
            }
            for i in tables::BOARD.inputs {
                let Some(p) = inputs.iter().find(|p| p.id().num == i.pin) else { continue };
                if matches!(i.edge, Edge::Rising | Edge::Both) {
                    p.set_interrupt_enabled(Interrupt::EdgeHigh, true);
                }
                if matches!(i.edge, Edge::Falling | Edge::Both) {
                    p.set_interrupt_enabled(Interrupt::EdgeLow, true);
                }
            }
        }
        let out_pins = tables::OUTPUT_PINS.map(pin::<FunctionSioOutput>);
        let outputs = board_app::outputs(out_pins);
        let mut timer = Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);
        let Some(mut alarm) = timer.alarm_0() else { halt("alarm 0") };
        if alarm.schedule(MicrosDurationU32::micros(TICK_US)).is_err() {
            halt("alarm schedule");
        }
        alarm.enable_interrupt();

        let (producer, consumer) = cx.local.queue.split();
        // The tables were checked when they were compiled (`tables::m0plus::CHECKED`).
        let runtime =
            Rt::new(tables::m0plus::CHECKED, tables::CONFIG, tables::Policy::default(), Rosc::new());
        // Edges come by GPIO interrupt in interrupt mode: the tick samples in timer mode only.
        let sampler = board_app::sampler(board_app::levels(&mut inputs), true);
        board_app::announce(tables::m0plus::SET.automata.len());
        (Shared { producer, outputs, inputs }, Local { consumer, runtime, alarm, sampler })
    }

    /// Edge interrupts: every configured edge of every input pin becomes its event.
    #[task(binds = IO_IRQ_BANK0, shared = [producer, inputs])]
    fn edges(cx: edges::Context) {
        (cx.shared.producer, cx.shared.inputs).lock(|q, inputs| {
            for p in inputs.iter_mut() {
                for (kind, rising) in [(Interrupt::EdgeHigh, true), (Interrupt::EdgeLow, false)] {
                    if p.interrupt_status(kind) {
                        p.clear_interrupt(kind);
                        tables::BOARD.edge(p.id().num, rising, |e| board_app::push(q, e));
                    }
                }
            }
        });
    }

    /// The 1 ms tick: counts the millisecond for the timers, ends pulses; in sampling mode, samples the
    /// inputs every period.
    #[task(binds = TIMER_IRQ_0, shared = [producer, outputs, inputs], local = [alarm, sampler])]
    fn tick(mut cx: tick::Context) {
        let alarm = cx.local.alarm;
        alarm.clear_interrupt();
        if alarm.schedule(MicrosDurationU32::micros(TICK_US)).is_err() {
            defmt::error!("alarm schedule");
        }
        board_app::count_ms();
        board_app::tick_outputs(&mut cx.shared.outputs);
        let sampler = cx.local.sampler;
        if sampler.due() {
            let now = cx.shared.inputs.lock(|inputs| board_app::levels(inputs));
            cx.shared.producer.lock(|q| board_app::update(sampler, now, q));
        }
    }

    /// The decision loop; gathers one random bit whenever it is about to sleep.
    #[idle(shared = [outputs], local = [consumer, runtime])]
    fn idle(mut cx: idle::Context) -> ! {
        board_app::decide(
            cx.local.runtime,
            cx.local.consumer,
            &mut Driver(&mut cx.shared.outputs),
            Rosc::sample,
        )
    }
}
