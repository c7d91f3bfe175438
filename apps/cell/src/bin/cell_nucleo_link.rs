//! The Nucleo-F401RE's link build (STM32F401RE, stm32f4xx-hal): the supervisors of `cell-nucleo` driven
//! by the virtual plant (`codegen plant --connect serial:/dev/ttyACM0`) instead of by pins — the byte
//! protocol the QEMU firmware speaks (`firmware::link`), the same runtime and event loop. USART2 receive
//! interrupt → HOLD/GO filter → input buffer; the decision loop in `idle`; commands back out on USART2;
//! defmt over RTT.
//!
//! USART2 is PA2 (TX) and PA3 (RX), 115 200 baud 8N1, wired on the board to the ST-LINK/V2-1, which the
//! host sees as a virtual COM port (`/dev/ttyACM0`): no adapter. It boots on hold: the host resets and
//! releases it, so a lock-step run (STEP, SYNC) repeats exactly from the seeds; its choices draw on the
//! manifest's seed; EXIT, which a board cannot obey, leaves it idle. It answers TABLES with the digest
//! of the tables it runs, those of `cell-nucleo` (`tables::DIGEST`). The core runs on the 16 MHz
//! internal oscillator as reset leaves it. Built, not run here: no emulator reaches this chip.
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

use stm32f4xx_hal::pac::USART2;
use stm32f4xx_hal::serial::Tx;

impl uart_link::Transmit for Tx<USART2> {
    fn transmit(&mut self, byte: u8) {
        // The only error a write reports is WouldBlock (the transmit register still full).
        while embedded_hal_nb::serial::Write::write(self, byte).is_err() {}
    }
}

#[rtic::app(device = stm32f4xx_hal::pac)]
mod app {
    use super::link_loop::{self, halt};
    use super::tables;
    use super::uart_link::{self, Rt, UartPort, BAUD};
    use firmware::event_loop::Port;
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
    use firmware::link::READY;
    use stm32f4xx_hal::pac::USART2;
    use stm32f4xx_hal::prelude::*;
    use stm32f4xx_hal::serial::{Config, Rx, RxListen, Serial, Tx};

    #[shared]
    struct Shared {
        rx: Rx<USART2>,
    }

    #[local]
    struct Local {
        producer: InputProducer<'static>,
        consumer: InputConsumer<'static>,
        runtime: Rt,
        port: UartPort<Tx<USART2>>,
    }

    #[init(local = [queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let dp = cx.device;
        let mut rcc = dp.RCC.constrain();
        let gpioa = dp.GPIOA.split(&mut rcc);
        let config = Config::default().baudrate(BAUD.bps());
        let Ok(serial) = Serial::new(dp.USART2, (gpioa.pa2, gpioa.pa3), config, &mut rcc) else {
            halt("usart2")
        };
        let (tx, mut rx) = serial.split();
        rx.listen();

        let (producer, consumer) = cx.local.queue.split();
        let runtime = uart_link::runtime("USART2");
        let mut port = UartPort(tx);
        port.send(READY);
        (Shared { rx }, Local { producer, consumer, runtime, port })
    }

    /// Moves received bytes into the input buffer (HOLD and GO act here). Bounded by the buffer's room:
    /// when it is full the receive interrupt is masked until the loop has drained it; a byte arriving
    /// meanwhile overruns USART2's one-byte data register and is lost (the host's lock-step rounds, a
    /// few bytes each, never come near the buffer's size).
    #[task(binds = USART2, shared = [rx], local = [producer])]
    fn usart2(mut cx: usart2::Context) {
        let q = cx.local.producer;
        cx.shared.rx.lock(|rx| {
            let full = link_loop::receive_all(q, || loop {
                match embedded_hal_nb::serial::Read::read(rx) {
                    Ok(byte) => return Some(byte),
                    // Nothing more.
                    Err(embedded_hal_nb::nb::Error::WouldBlock) => return None,
                    // Overrun, framing, noise or parity: the read cleared the flag; the byte in error
                    // is dropped and the host's checks see what went missing.
                    Err(embedded_hal_nb::nb::Error::Other(_)) => {}
                }
            });
            if full {
                rx.unlisten();
            }
        });
    }

    /// The decision loop; sleeps in `wfi` while there is nothing to do.
    #[idle(shared = [rx], local = [consumer, runtime, port])]
    fn idle(mut cx: idle::Context) -> ! {
        let (rx, rt, port) = (cx.local.consumer, cx.local.runtime, cx.local.port);
        link_loop::serve(rt, rx, port, tables::DIGEST, |_| cx.shared.rx.lock(|rx| rx.listen()))
    }
}
