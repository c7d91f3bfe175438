//! The supervisor firmware on QEMU's lm3s6965evb: UART0 receive interrupt → input buffer, the decision
//! loop in `idle`, commands back out on UART0 (protocol: `firmware::link`), defmt logs over semihosting.
//!
//! Tables: `SCT_TABLES_FILE` (see `build.rs`), the cell's by default: supervisor tables
//! (`[runtime] mode = "event"`) or the state feedback's (`mode = "state"`, `firmware::state`), which
//! define the same names (`Runtime`, `CHECKED`, `DIGEST`, `CONFIG`, `Policy`, `TIMERS`, …), so one application runs
//! both; the loop answers the link's TABLES with the tables' `DIGEST`, so a host refuses other tables,
//! and runs the tables' timers on the link's TIME alone (lock-step: a run is a function of its seeds). Run with `cargo qemu` from the
//! repository root, or start QEMU on a socket for the virtual plant (docs/firmware.md, "Run the cell under QEMU").
#![no_std]
#![no_main]

mod stack;
mod uart;

use defmt_semihosting as _;
use panic_semihosting as _;

/// The emitted tables.
#[allow(dead_code)]
mod tables {
    include!(env!("SCT_TABLES_FILE"));
}

use firmware::event_loop::{Note, Port};
use firmware::link::Hold;

/// The decision gate; HOLD and GO set it from the receive interrupt. On hold from boot: the host
/// releases the firmware after its RESET, so a seeded run repeats exactly (`firmware::link`).
static HOLD: Hold = Hold::on_hold();

/// The runtime over the emitted tables.
type Rt = tables::Runtime<tables::Policy, firmware::rng::SeedEntropy>;

/// UART0 as the event loop's port; notes become defmt warnings.
struct UartPort;

impl Port for UartPort {
    fn send(&mut self, byte: u8) {
        uart::send(byte);
    }

    fn note(&mut self, note: Note) {
        let name = |e: u8| tables::EVENT_NAMES.get(usize::from(e)).copied().unwrap_or("?");
        match note {
            Note::Unexpected { event, automaton } => {
                let a = tables::AUTOMATON_NAMES.get(usize::from(automaton)).copied().unwrap_or("?");
                defmt::warn!("unexpected event {=str} in {=str}", name(event), a);
            }
            Note::Unknown(byte) => defmt::warn!("unknown byte {=u8:#x}", byte),
            Note::Safe => defmt::error!("fault: safe state, deciding stopped"),
            Note::Redecided => defmt::debug!("guard: input arrived while choosing, decide again"),
        }
    }
}

/// Ends the emulation with `status` after logging the counters and the stack high-water mark.
fn exit(status: u8) -> ! {
    defmt::info!("exit {=u8}: stack high-water {=usize} bytes", status, stack::high_water());
    let code = if status == 0 {
        cortex_m_semihosting::debug::EXIT_SUCCESS
    } else {
        cortex_m_semihosting::debug::EXIT_FAILURE
    };
    cortex_m_semihosting::debug::exit(code);
    loop {
        cortex_m::asm::wfi();
    }
}

#[rtic::app(device = lm3s6965)]
mod app {
    use super::{exit, stack, tables, uart, Rt, UartPort, HOLD};
    use firmware::event_loop::{EventLoop, Poll};
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
    use firmware::link::READY;
    use firmware::rng::SeedEntropy;

    #[shared]
    struct Shared {}

    #[local]
    struct Local {
        producer: InputProducer<'static>,
        consumer: InputConsumer<'static>,
        runtime: Rt,
        event_loop: EventLoop<{ tables::TIMERS.len() }>,
    }

    #[init(local = [queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        stack::paint();
        let (producer, consumer) = cx.local.queue.split();
        let policy = tables::Policy::default();
        // The tables were checked when they were compiled (`tables::CHECKED`).
        let runtime = Rt::new(tables::CHECKED, tables::CONFIG, policy, SeedEntropy::new(tables::SEED));
        defmt::info!(
            "{=str}: {=usize} automata, {=usize} events, input buffer {=usize}",
            tables::NAME,
            tables::AUTOMATON_NAMES.len(),
            tables::EVENT_NAMES.len(),
            tables::INPUT_SLOTS - 1
        );
        let event_loop = EventLoop::with_tables(tables::DIGEST).with_timers(&tables::TIMERS);
        uart::init();
        uart::send(READY);
        (Shared {}, Local { producer, consumer, runtime, event_loop })
    }

    /// Moves received bytes into the input buffer (HOLD and GO act here). Bounded by the buffer's room:
    /// when it is full the receive interrupt is masked and QEMU holds further bytes back, so a burst is
    /// delayed, never lost; on a real line the overflow would be counted.
    #[task(binds = UART0, local = [producer])]
    fn uart0(cx: uart0::Context) {
        let q = cx.local.producer;
        loop {
            if !q.has_room() {
                uart::mask_rx();
                return;
            }
            let Some(byte) = uart::try_read() else { return };
            if let Some(byte) = HOLD.filter(byte) {
                if q.push(byte).is_err() {
                    q.count_overflow();
                }
            }
        }
    }

    /// The decision loop; sleeps in `wfi` while there is nothing to do.
    #[idle(local = [consumer, runtime, event_loop])]
    fn idle(cx: idle::Context) -> ! {
        let (rx, rt, event_loop) = (cx.local.consumer, cx.local.runtime, cx.local.event_loop);
        let mut port = UartPort;
        loop {
            let poll = event_loop.turn(rt, rx, &HOLD, &mut port);
            uart::unmask_rx();
            match poll {
                Poll::Busy => {}
                Poll::Idle | Poll::Held => cortex_m::interrupt::free(|_| {
                    if poll.may_sleep(rx, &HOLD) {
                        cortex_m::asm::wfi();
                    }
                }),
                Poll::Exit(status) => {
                    let c = rt.counters();
                    defmt::info!(
                        "events in {=u32}, commands out {=u32}, unexpected {=u32}, overflows {=u32}, redecisions {=u32}, unknown {=u32}",
                        c.events_in, c.commands_out, c.unexpected, c.overflows, c.guard_redecisions, c.unknown_bytes
                    );
                    exit(status)
                }
            }
        }
    }
}
