//! The nRF52840 DK's link build (nRF52840, nrf52840-hal's device crate): the supervisors of
//! `cell-nrf52840` driven by the virtual plant (`codegen plant --connect serial:/dev/ttyACM0`) instead
//! of by pins — the byte protocol the QEMU firmware speaks (`firmware::link`), the same runtime and
//! event loop. UART receive interrupt → HOLD/GO filter → input buffer; the decision loop in `idle`;
//! commands back out on the UART; defmt over RTT.
//!
//! The DK wires P0.06 (TX), P0.08 (RX), P0.05 (RTS) and P0.07 (CTS) to its interface MCU (J-Link OB),
//! which the host sees as a virtual COM port (`/dev/ttyACM0`) and which handles hardware flow control
//! when the target uses it. This build uses it, 115 200 baud 8N1: when the input buffer is full the
//! receive interrupt is masked, the UART's six-byte receive FIFO fills and its RTS stops the probe —
//! nothing is lost. It drives the byte-wise UART0 instance of the serial port (the same peripheral as
//! UARTE0, without EasyDMA): one byte per interrupt, no DMA buffer to manage.
//!
//! It boots on hold: the host resets and releases it, so a lock-step run (STEP, SYNC) repeats exactly
//! from the seeds; its choices draw on the manifest's seed; EXIT, which a board cannot obey, leaves it
//! idle. It answers TABLES with the digest of the tables it runs, those of `cell-nrf52840`
//! (`tables::DIGEST`). Built, not run here: no emulator reaches this chip.
#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

/// The emitted tables.
#[allow(dead_code)]
mod tables {
    include!(env!("SCT_TABLES_FILE"));
}

mod link_loop;
mod uart_link;

use nrf52840_hal::pac::UART0;

/// The DK's virtual COM port pins (PSEL numbers, P0.n = n).
const TXD: u32 = 6;
const RXD: u32 = 8;
const RTS: u32 = 5;
const CTS: u32 = 7;

/// The BAUDRATE register's value for `uart_link::BAUD`: the rate in units of 16 MHz / 2^32, rounded to
/// the register's 20 significant bits (115 200 baud gives the data sheet's 0x01D7_E000).
const BAUDRATE: u32 = ((uart_link::BAUD as u64 * (1 << 32) / 16_000_000 + 0x800) & 0xFFFF_F000) as u32;

/// UART0, which the receive interrupt and the decision loop share: each touches its own events only.
pub struct Uart(UART0);

impl Uart {
    /// Configures and starts UART0 on the DK's virtual COM port pins: [`uart_link::BAUD`], 8N1,
    /// hardware flow control, the receive interrupt on. Its pins' directions are set by the caller (TXD
    /// and RTS outputs high, RXD and CTS inputs).
    fn start(uart: UART0) -> Self {
        // SAFETY: plain register values (nRF52840 PS, UART): PSEL numbers below 32 on port 0 with the
        // connect bit clear, the baud rate in the register's units, 1 to start a task.
        unsafe {
            uart.psel.txd.write(|w| w.bits(TXD));
            uart.psel.rxd.write(|w| w.bits(RXD));
            uart.psel.rts.write(|w| w.bits(RTS));
            uart.psel.cts.write(|w| w.bits(CTS));
            uart.baudrate.write(|w| w.bits(BAUDRATE));
            uart.config.write(|w| w.hwfc().enabled().parity().excluded());
            uart.enable.write(|w| w.enable().enabled());
            uart.events_rxdrdy.write(|w| w.bits(0));
            uart.events_txdrdy.write(|w| w.bits(0));
            uart.intenset.write(|w| w.rxdrdy().set_bit());
            uart.tasks_startrx.write(|w| w.bits(1));
            uart.tasks_starttx.write(|w| w.bits(1));
        }
        Uart(uart)
    }

    /// The next received byte, if one is waiting (RXDRDY cleared before RXD is read, as the FIFO asks).
    fn read(&mut self) -> Option<u8> {
        if self.0.events_rxdrdy.read().bits() == 0 {
            return None;
        }
        // SAFETY: clearing an event.
        self.0.events_rxdrdy.write(|w| unsafe { w.bits(0) });
        Some(self.0.rxd.read().rxd().bits())
    }

    /// Masks (`false`) or unmasks the receive interrupt.
    fn listen(&mut self, on: bool) {
        if on {
            self.0.intenset.write(|w| w.rxdrdy().set_bit());
        } else {
            self.0.intenclr.write(|w| w.rxdrdy().set_bit());
        }
    }
}

/// UART0's transmitter, borrowed from the shared [`Uart`]: it touches TXD and TXDRDY only, which the
/// receive interrupt never does.
pub struct UartTx;

impl uart_link::Transmit for UartTx {
    fn transmit(&mut self, byte: u8) {
        // SAFETY: UART0's registers; see `UartTx` for why this does not race the receive interrupt.
        let uart = unsafe { &*UART0::ptr() };
        uart.txd.write(|w| unsafe { w.txd().bits(byte) });
        while uart.events_txdrdy.read().bits() == 0 {}
        uart.events_txdrdy.write(|w| unsafe { w.bits(0) });
    }
}

#[rtic::app(device = nrf52840_hal::pac)]
mod app {
    use super::link_loop;
    use super::uart_link::{self, Rt, UartPort};
    use super::{tables, Uart, UartTx};
    use firmware::event_loop::Port;
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
    use firmware::link::READY;
    use nrf52840_hal::gpio::{p0, Level};

    #[shared]
    struct Shared {
        uart: Uart,
    }

    #[local]
    struct Local {
        producer: InputProducer<'static>,
        consumer: InputConsumer<'static>,
        runtime: Rt,
        port: UartPort<UartTx>,
    }

    #[init(local = [queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let port0 = p0::Parts::new(cx.device.P0);
        // The UART takes these pins by their PSEL numbers; the GPIO sets their directions.
        let _txd = port0.p0_06.into_push_pull_output(Level::High);
        let _rts = port0.p0_05.into_push_pull_output(Level::High);
        let _rxd = port0.p0_08.into_floating_input();
        let _cts = port0.p0_07.into_floating_input();
        let uart = Uart::start(cx.device.UART0);

        let (producer, consumer) = cx.local.queue.split();
        let runtime = uart_link::runtime("UART0");
        let mut port = UartPort(UartTx);
        port.send(READY);
        (Shared { uart }, Local { producer, consumer, runtime, port })
    }

    /// Moves received bytes into the input buffer (HOLD and GO act here). Bounded by the buffer's room:
    /// when it is full the receive interrupt is masked until the loop has drained it; the UART's FIFO
    /// then fills and its RTS holds the host back.
    #[task(binds = UARTE0_UART0, shared = [uart], local = [producer])]
    fn uart0(mut cx: uart0::Context) {
        let q = cx.local.producer;
        cx.shared.uart.lock(|uart| {
            if link_loop::receive_all(q, || uart.read()) {
                uart.listen(false);
            }
        });
    }

    /// The decision loop; sleeps in `wfi` while there is nothing to do.
    #[idle(shared = [uart], local = [consumer, runtime, port])]
    fn idle(mut cx: idle::Context) -> ! {
        let (rx, rt, port) = (cx.local.consumer, cx.local.runtime, cx.local.port);
        link_loop::serve(rt, rx, port, tables::DIGEST, |_| cx.shared.uart.lock(|uart| uart.listen(true)))
    }
}
