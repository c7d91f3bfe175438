//! What the Pico's link builds share (`cell_pico_link.rs` over UART0, `cell_pico_usb.rs` over USB): the
//! second-stage bootloader, the clocks, the HOLD/GO gate, the published status, the runtime's type,
//! the notes the event loop logs and the halt on a configuration error. Each declares it as
//! `mod link_app;` beside its own `mod tables` and keeps only its transport's wiring.

use firmware::event_loop::Note;
use firmware::link::Hold;
use firmware::status::Published;
use rp2040_hal::clocks::{init_clocks_and_plls, ClocksManager};
use rp2040_hal::pac;
use rp2040_hal::Watchdog;

use crate::tables;

/// Second-stage bootloader for the Pico's W25Q080 flash.
#[link_section = ".boot2"]
#[used]
pub static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

/// The Pico's crystal.
const XOSC_HZ: u32 = 12_000_000;

/// The decision gate; HOLD and GO set it where the link's bytes are received. On hold from boot: the
/// host releases the firmware after its RESET (`firmware::link`).
pub static HOLD: Hold = Hold::on_hold();

/// The runtime's counters after every turn of the loop, for a debugger or the emulator harness (which
/// times the runtime's entry points by them); the host reads them over the link with STATUS.
#[no_mangle]
pub static SCT_STATUS: Published = Published::new();

/// The runtime on the tables made for the Cortex-M0+, its choices seeded from the manifest.
pub type Rt = tables::m0plus::Runtime<tables::Policy, firmware::rng::SeedEntropy>;

/// The runtime on the emitted tables, seeded from the manifest; logs what runs over which `transport`.
pub fn runtime(transport: &str) -> Rt {
    defmt::info!(
        "{=str} over {=str}: {=usize} automata, {=usize} events, input buffer {=usize}",
        tables::NAME,
        transport,
        tables::m0plus::SET.automata.len(),
        tables::EVENT_NAMES.len(),
        tables::INPUT_SLOTS - 1
    );
    // The tables were checked when they were compiled (`tables::m0plus::CHECKED`).
    Rt::new(
        tables::m0plus::CHECKED,
        tables::CONFIG,
        tables::Policy::default(),
        firmware::rng::SeedEntropy::new(tables::SEED),
    )
}

/// The Pico's clocks from its crystal (the system's PLL at 125 MHz, USB's at 48 MHz); halts when a
/// PLL does not lock.
pub fn clocks(
    xosc: pac::XOSC,
    clocks: pac::CLOCKS,
    pll_sys: pac::PLL_SYS,
    pll_usb: pac::PLL_USB,
    resets: &mut pac::RESETS,
    watchdog: pac::WATCHDOG,
) -> ClocksManager {
    let mut watchdog = Watchdog::new(watchdog);
    let Ok(clocks) = init_clocks_and_plls(XOSC_HZ, xosc, clocks, pll_sys, pll_usb, resets, &mut watchdog)
    else {
        halt("clocks")
    };
    clocks
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

/// Stops for good after a configuration error (logged).
pub fn halt(why: &str) -> ! {
    defmt::error!("halt: {=str}", why);
    loop {
        cortex_m::asm::wfi();
    }
}
