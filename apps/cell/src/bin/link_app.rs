//! What the Pico's link builds share (`cell_pico_link.rs` over UART0, `cell_pico_usb.rs` over USB) that
//! is the RP2040's: the second-stage bootloader, the clocks, the runtime on the Cortex-M0+'s tables.
//! Each declares it as `mod link_app;` beside `mod link_loop;` (what every board's link build shares)
//! and its own `mod tables`, and keeps only its transport's wiring.

use rp2040_hal::clocks::{init_clocks_and_plls, ClocksManager};
use rp2040_hal::pac;
use rp2040_hal::Watchdog;

use crate::link_loop::{announce, halt};
use crate::tables;

/// Second-stage bootloader for the Pico's W25Q080 flash.
#[link_section = ".boot2"]
#[used]
pub static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

/// The Pico's crystal.
const XOSC_HZ: u32 = 12_000_000;

/// The runtime on the tables made for the Cortex-M0+, its choices seeded from the manifest.
pub type Rt = tables::m0plus::Runtime<tables::Policy, firmware::rng::SeedEntropy>;

/// The runtime on the emitted tables, seeded from the manifest; logs what runs over which `transport`.
pub fn runtime(transport: &str) -> Rt {
    announce(transport, tables::m0plus::SET.automata.len());
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
