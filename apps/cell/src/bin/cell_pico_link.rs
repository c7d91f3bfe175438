//! The Pico's link build (RP2040, rp2040-hal): the supervisors of `cell-pico` driven over UART0 by the
//! virtual plant (`codegen plant --connect serial:DEVICE`) instead of by pins — the byte protocol the
//! QEMU firmware speaks (`firmware::link`), the same runtime and event loop. UART0 receive interrupt →
//! HOLD/GO filter → input buffer; the decision loop in `idle`; commands back out on UART0; defmt over RTT.
//!
//! UART0 is GP0 (TX) and GP1 (RX), 115 200 baud 8N1: on a real Pico, through a USB-UART adapter or the
//! debug probe's UART (docs/boards.md, "The board in the loop"); on the emulated RP2040, the harness's
//! `--uart` mode. It boots on hold, as the QEMU firmware does: the host resets and releases it, so a
//! lock-step run (STEP, SYNC) repeats exactly from the seeds. Its choices draw on the manifest's seed
//! (`firmware::rng::SeedEntropy`), as under QEMU; EXIT, which a board cannot obey, leaves it idle. It
//! answers TABLES with the digest of the Cortex-M0+'s tables (`tables::m0plus::DIGEST`).
#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

/// The emitted tables.
#[allow(dead_code)]
mod tables {
    include!(env!("SCT_TABLES_FILE"));
}

mod link_app;
mod link_loop;

use firmware::event_loop::{Note, Port};
use rp2040_hal::gpio::bank0::{Gpio0, Gpio1};
use rp2040_hal::gpio::{FunctionUart, Pin, PullDown};
use rp2040_hal::pac::UART0;
use rp2040_hal::uart::Writer;

/// The link's baud rate (`codegen::link::DEFAULT_BAUD`: `serial:DEVICE` without `@BAUD`).
const BAUD: u32 = 115_200;

type UartPins = (Pin<Gpio0, FunctionUart, PullDown>, Pin<Gpio1, FunctionUart, PullDown>);

/// UART0's transmit half as the event loop's port; notes become defmt warnings.
struct UartPort(Writer<UART0, UartPins>);

impl Port for UartPort {
    fn send(&mut self, byte: u8) {
        self.0.write_full_blocking(&[byte]);
    }

    fn note(&mut self, note: Note) {
        link_loop::log_note(note);
    }
}

#[rtic::app(device = rp2040_hal::pac)]
mod app {
    use super::link_app::Rt;
    use super::link_loop::{self, halt};
    use super::{tables, UartPins, UartPort, BAUD};
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
    use firmware::link::READY;
    use rp2040_hal::clocks::Clock;
    use rp2040_hal::fugit::RateExtU32;
    use rp2040_hal::pac::UART0;
    use rp2040_hal::uart::{DataBits, Reader, StopBits, UartConfig, UartPeripheral};
    use rp2040_hal::Sio;

    #[shared]
    struct Shared {
        reader: Reader<UART0, UartPins>,
    }

    #[local]
    struct Local {
        producer: InputProducer<'static>,
        consumer: InputConsumer<'static>,
        runtime: Rt,
        port: UartPort,
    }

    #[init(local = [queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut pac = cx.device;
        let clocks = super::link_app::clocks(
            pac.XOSC,
            pac.CLOCKS,
            pac.PLL_SYS,
            pac.PLL_USB,
            &mut pac.RESETS,
            pac.WATCHDOG,
        );
        let sio = Sio::new(pac.SIO);
        let pins = rp2040_hal::gpio::Pins::new(pac.IO_BANK0, pac.PADS_BANK0, sio.gpio_bank0, &mut pac.RESETS);
        let uart_pins: UartPins = (pins.gpio0.into_function(), pins.gpio1.into_function());
        let config = UartConfig::new(BAUD.Hz(), DataBits::Eight, None, StopBits::One);
        let Ok(uart) = UartPeripheral::new(pac.UART0, uart_pins, &mut pac.RESETS)
            .enable(config, clocks.peripheral_clock.freq())
        else {
            halt("uart")
        };
        let (mut reader, writer) = uart.split();
        reader.enable_rx_interrupt();

        let (producer, consumer) = cx.local.queue.split();
        let runtime = super::link_app::runtime("UART0");
        let mut port = UartPort(writer);
        firmware::event_loop::Port::send(&mut port, READY);
        (Shared { reader }, Local { producer, consumer, runtime, port })
    }

    /// Moves received bytes into the input buffer (HOLD and GO act here). Bounded by the buffer's room:
    /// when it is full the receive interrupt is masked until the loop has drained it, so further bytes
    /// wait in the UART's FIFO (32 bytes; on a real line, past that, the UART drops them and the host's
    /// lock-step rounds, a few bytes each, never come near it).
    #[task(binds = UART0_IRQ, shared = [reader], local = [producer])]
    fn uart0(mut cx: uart0::Context) {
        let q = cx.local.producer;
        cx.shared.reader.lock(|reader| {
            // Nothing more (WouldBlock), or a framing/parity/break error on the line: the byte in error
            // is dropped (popped with its error flags); the interrupt comes again for what follows.
            let full = link_loop::receive_all(q, || {
                let mut byte = [0u8];
                matches!(reader.read_raw(&mut byte), Ok(1)).then_some(byte[0])
            });
            if full {
                reader.disable_rx_interrupt();
            }
        });
    }

    /// The decision loop; sleeps in `wfi` while there is nothing to do.
    #[idle(shared = [reader], local = [consumer, runtime, port])]
    fn idle(mut cx: idle::Context) -> ! {
        let (rx, rt, port) = (cx.local.consumer, cx.local.runtime, cx.local.port);
        link_loop::serve(rt, rx, port, tables::m0plus::DIGEST, |_| {
            cx.shared.reader.lock(|reader| reader.enable_rx_interrupt())
        })
    }
}
