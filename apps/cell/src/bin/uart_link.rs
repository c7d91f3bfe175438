//! What the Cortex-M4 boards' link builds share (`cell_nucleo_link.rs`, `cell_nrf52840_link.rs`, both
//! over the UART that the on-board debug probe exposes as a virtual COM port): the runtime on the
//! tables' default layout — the Cortex-M3/M4 tables `cell-nucleo` and `cell-nrf52840` run —, seeded
//! from the manifest, and the UART's sending half as the event loop's port. Declared as
//! `mod uart_link;` beside `mod link_loop;`.

use firmware::event_loop::{Note, Port};
use firmware::rng::SeedEntropy;

use crate::link_loop::{announce, log_note};
use crate::tables;

/// The link's baud rate (`codegen::link::DEFAULT_BAUD`: `serial:DEVICE` without `@BAUD`), 8N1.
pub const BAUD: u32 = 115_200;

/// The runtime on the tables' default layout, its choices seeded from the manifest.
pub type Rt = tables::Runtime<tables::Policy, SeedEntropy>;

/// The runtime on the emitted tables, seeded from the manifest; logs what runs over which `transport`.
/// The link answers TABLES with these tables' digest, `tables::DIGEST`.
pub fn runtime(transport: &str) -> Rt {
    announce(transport, tables::SET.automata.len());
    // The tables were checked when they were compiled (`tables::CHECKED`).
    Rt::new(tables::CHECKED, tables::CONFIG, tables::Policy::default(), SeedEntropy::new(tables::SEED))
}

/// A UART's sending half: one byte out, waiting while its transmitter is busy.
pub trait Transmit {
    /// Sends `byte`, returning once the UART has taken it.
    fn transmit(&mut self, byte: u8);
}

/// The UART's sending half as the event loop's port; notes become defmt warnings.
pub struct UartPort<T>(pub T);

impl<T: Transmit> Port for UartPort<T> {
    fn send(&mut self, byte: u8) {
        self.0.transmit(byte);
    }

    fn note(&mut self, note: Note) {
        log_note(note);
    }
}
