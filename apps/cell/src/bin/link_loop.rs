//! What every link build shares, whatever its board and transport (the Pico's over UART0 and USB, the
//! Nucleo-F401RE's and the nRF52840 DK's over the debug probe's virtual COM port): the HOLD/GO gate,
//! the published status, the received byte's way into the input buffer, the notes the event loop logs,
//! the decision loop and the halt on a configuration error. Each link build declares it as
//! `mod link_loop;` beside its own `mod tables` and keeps only its board's and transport's wiring
//! (`link_app.rs` the RP2040's, `uart_link.rs` the Cortex-M4 boards').

use firmware::event_loop::{EventLoop, Note, Poll, Port};
use firmware::input_queue::{InputConsumer, InputProducer};
use firmware::link::Hold;
use firmware::shell::Decide;
use firmware::status::Published;

use crate::tables;

/// The decision gate; HOLD and GO set it where the link's bytes are received. On hold from boot: the
/// host releases the firmware after its RESET (`firmware::link`).
pub static HOLD: Hold = Hold::on_hold();

/// The runtime's counters after every turn of the loop, for a debugger or the emulator harness (which
/// times the runtime's entry points by them); the host reads them over the link with STATUS.
#[no_mangle]
pub static SCT_STATUS: Published = Published::new();

/// Logs what runs over which `transport`, once at boot: the set's name, its automata, events and input
/// buffer.
pub fn announce(transport: &str, automata: usize) {
    defmt::info!(
        "{=str} over {=str}: {=usize} automata, {=usize} events, input buffer {=usize}",
        tables::NAME,
        transport,
        automata,
        tables::EVENT_NAMES.len(),
        tables::INPUT_SLOTS - 1
    );
}

/// Takes one `byte` received from the link: HOLD and GO set the gate, anything else goes into the
/// input buffer `q` (counted as an overflow when it is full: never silent).
fn receive(q: &mut InputProducer<'static>, byte: u8) {
    if let Some(byte) = HOLD.filter(byte) {
        if q.push(byte).is_err() {
            q.count_overflow();
        }
    }
}

/// Moves the bytes `read` yields (`None`: no more for now) into the input buffer `q` through
/// `receive`, as many as it has room for. True when it stopped for want of room: the caller masks its
/// receive until the loop has drained the buffer, so the rest waits in the transport.
pub fn receive_all(q: &mut InputProducer<'static>, mut read: impl FnMut() -> Option<u8>) -> bool {
    while q.has_room() {
        let Some(byte) = read() else { return false };
        receive(q, byte);
    }
    true
}

/// Logs what the event loop notes: defmt warnings, the safe state an error.
pub fn log_note(note: Note) {
    match note {
        Note::Unexpected { event, automaton } => {
            defmt::warn!("unexpected event {=u8} in automaton {=u8}", event, automaton)
        }
        Note::Unknown(byte) => defmt::warn!("unknown byte {=u8:#x}", byte),
        Note::Safe => defmt::error!("fault: safe state, deciding stopped"),
        Note::Redecided => defmt::debug!("guard: input arrived while choosing"),
    }
}

/// The decision loop of `idle`, sending over `port`: drains the
/// input buffer into the runtime, decides, sends the commands, answers TABLES with `digest` (that of
/// the tables `rt` runs on), runs the tables' timers on the host's TIME (`tables::TIMERS`: lock-step,
/// no clock of its own), publishes the counters ([`SCT_STATUS`]), calls `after_turn` with the
/// input buffer (to re-enable a receive that stopped while the buffer was full) and sleeps in `wfi` while there is
/// nothing to do. EXIT (`Poll::Exit`) ends an emulation; a board stays up for the next host: idle.
pub fn serve(
    rt: &mut impl Decide,
    rx: &mut InputConsumer<'static>,
    port: &mut impl Port,
    digest: &'static str,
    mut after_turn: impl FnMut(&InputConsumer<'static>),
) -> ! {
    let mut event_loop = EventLoop::with_tables(digest).with_timers(&tables::TIMERS);
    loop {
        let poll = event_loop.turn(rt, rx, &HOLD, port);
        SCT_STATUS.store(&rt.counters().to_array(), rt.is_safe());
        after_turn(rx);
        if poll != Poll::Busy {
            cortex_m::interrupt::free(|_| {
                if poll.may_sleep(rx, &HOLD) {
                    cortex_m::asm::wfi();
                }
            });
        }
    }
}

/// Stops for good after a configuration error (logged).
// The nRF52840 DK's link build has no configuration step that can fail.
#[cfg_attr(feature = "nrf52840", allow(dead_code))]
pub fn halt(why: &str) -> ! {
    defmt::error!("halt: {=str}", why);
    loop {
        cortex_m::asm::wfi();
    }
}
