//! The boards a project is built for ([`Board`]) and their pins: which GPIO numbers a `[board]` entry may
//! name on each, and why the others are refused — a number the chip does not have, or a pin the board
//! wires to something else (the debug probe, a crystal, the USB bridge's serial port).
//!
//! Pin numbers are as `[board]` writes them (docs/boards.md): the Pico's GPIO n is n; the Nucleo's port
//! × 16 + line (PA5 = 5, PC13 = 45); the nRF52840's P0.n is n and P1.n is 32 + n.

use clap::ValueEnum;

/// A board `codegen new` writes a project for, and whose pins a `[board]` section is checked against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, clap::ValueEnum)]
pub enum Board {
    /// Raspberry Pi Pico (RP2040, Cortex-M0+, thumbv6m-none-eabi; rp2040-hal). Runs on the RP2040
    /// emulator here (`codegen run --project DIR`).
    Pico,
    /// ST Nucleo-F401RE (STM32F401RE, Cortex-M4F, thumbv7em-none-eabihf; stm32f4xx-hal's device crate).
    /// Built, not run: no emulator for it here.
    NucleoF401re,
    /// Nordic nRF52840 DK (nRF52840, Cortex-M4F, thumbv7em-none-eabihf; nrf52840-hal). Built, not run:
    /// no emulator for it here.
    #[value(name = "nrf52840-dk")]
    Nrf52840Dk,
}

/// Whether a `[board]` entry may use a pin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Pin {
    /// The pin is there and free for the application.
    Free,
    /// The chip (in the board's package) has no such pin.
    Absent(&'static str),
    /// The board wires the pin to something else; why.
    Reserved(&'static str),
}

impl Board {
    /// The board's name on the command line and in `[board] name` (`nucleo-f401re`).
    pub fn name(self) -> String {
        self.to_possible_value().map(|v| v.get_name().to_owned()).unwrap_or_default()
    }

    /// The board `[board] name` names, if it is one of these (its command-line name, any case).
    pub fn named(name: &str) -> Option<Board> {
        Board::value_variants().iter().copied().find(|b| b.name().eq_ignore_ascii_case(name.trim()))
    }

    /// Pin `n` as the board's documentation names it (`GP2`, `PA13`, `P1.04`).
    pub fn pin_name(self, n: u8) -> String {
        match self {
            Board::Pico => format!("GP{n}"),
            Board::NucleoF401re => {
                let port = ["A", "B", "C", "D", "E"].get(usize::from(n / 16)).copied().unwrap_or("?");
                format!("P{port}{}", n % 16)
            }
            Board::Nrf52840Dk => format!("P{}.{:02}", n / 32, n % 32),
        }
    }

    /// Whether pin `n` is there and free on this board.
    pub fn pin(self, n: u8) -> Pin {
        match self {
            Board::Pico => match n {
                0..=22 | 25..=28 => Pin::Free,
                23 => Pin::Reserved("the Pico drives the power supply's power-save input with it"),
                24 => Pin::Reserved("the Pico senses VBUS on it (USB power present)"),
                29 => Pin::Reserved("the Pico measures VSYS/3 on it (ADC3)"),
                _ => Pin::Absent("the RP2040 has GPIO 0 to 29"),
            },
            Board::NucleoF401re => match n {
                2 | 3 => Pin::Reserved(
                    "USART2, wired to the ST-LINK's virtual COM port (solder bridges SB13, SB14)",
                ),
                13 | 14 => Pin::Reserved(
                    "SWD (PA13 SWDIO, PA14 SWCLK): the debug probe flashes and debugs through it",
                ),
                46 | 47 => Pin::Reserved("the 32.768 kHz crystal X2 (LSE, PC14 and PC15)"),
                27 => Pin::Absent("the STM32F401RE's 64-pin package has no PB11 (VCAP1 takes its place)"),
                0..=47 | 50 => Pin::Free,
                _ => Pin::Absent(
                    "the STM32F401RE's 64-pin package has ports A, B and C, and of port D only PD2",
                ),
            },
            Board::Nrf52840Dk => match n {
                0 | 1 => Pin::Reserved("the 32.768 kHz crystal (P0.00, P0.01)"),
                5..=8 => Pin::Reserved("the UART to the interface MCU's virtual COM port (P0.05 to P0.08)"),
                9 | 10 => {
                    Pin::Reserved("the NFC antenna (P0.09, P0.10: GPIO only once UICR NFCPINS is changed)")
                }
                17 | 19..=23 => Pin::Reserved("the QSPI flash on the DK (P0.17, P0.19 to P0.23)"),
                18 => Pin::Reserved("the reset line (P0.18, the DK's RESET button)"),
                0..=47 => Pin::Free,
                _ => Pin::Absent("the nRF52840 has P0.00 to P0.31 and P1.00 to P1.15 (numbers 0 to 47)"),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back_and_pins_are_named_as_the_boards_do() {
        for &b in Board::value_variants() {
            assert_eq!(Board::named(&b.name()), Some(b));
        }
        assert_eq!(Board::named("Pico"), Some(Board::Pico));
        assert_eq!(Board::named("rp2040"), None);
        assert_eq!(Board::NucleoF401re.pin_name(13), "PA13");
        assert_eq!(Board::NucleoF401re.pin_name(45), "PC13");
        assert_eq!(Board::Nrf52840Dk.pin_name(36), "P1.04");
        assert_eq!(Board::Pico.pin_name(25), "GP25");
    }

    #[test]
    fn the_swd_pins_absent_ports_and_board_wiring_are_refused() {
        assert!(matches!(Board::NucleoF401re.pin(13), Pin::Reserved(why) if why.contains("SWD")));
        assert!(matches!(Board::NucleoF401re.pin(14), Pin::Reserved(_)));
        assert_eq!(Board::NucleoF401re.pin(5), Pin::Free, "PA5, the LED");
        assert_eq!(Board::NucleoF401re.pin(45), Pin::Free, "PC13, the button");
        assert_eq!(Board::NucleoF401re.pin(50), Pin::Free, "PD2");
        assert!(matches!(Board::NucleoF401re.pin(49), Pin::Absent(_)));
        assert!(matches!(Board::NucleoF401re.pin(27), Pin::Absent(why) if why.contains("PB11")));
        assert!(matches!(Board::Pico.pin(30), Pin::Absent(_)));
        assert!(matches!(Board::Pico.pin(24), Pin::Reserved(_)));
        assert_eq!(Board::Pico.pin(26), Pin::Free);
        assert!(matches!(Board::Nrf52840Dk.pin(48), Pin::Absent(_)));
        assert_eq!(Board::Nrf52840Dk.pin(13), Pin::Free, "LED1");
        assert!(matches!(Board::Nrf52840Dk.pin(18), Pin::Reserved(_)));
    }
}
