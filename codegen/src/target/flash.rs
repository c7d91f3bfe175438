//! This module is the home of [`Flash`]: how much flash a board leaves the tables — its flash, as the
//! `memory.x` it links with says, less what the application's code takes besides them — so that a set
//! is refused before `cargo build`, naming the board and the bytes, rather than by the linker.

use super::sources;

/// Bytes the application's code and constants may take besides the tables. The cell's applications
/// take 8 KB (`cell-qemu`) to 13 KB (`cell-pico`) without their tables (docs/layouts.md); the rest is
/// room for a user's own.
pub const APPLICATION: usize = 32 * 1024;

/// A board's flash.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Flash {
    /// The board, as messages name it (`lm3s6965 (QEMU)`).
    pub board: &'static str,
    /// Bytes of flash the image may take (`memory.x`'s `FLASH` length).
    pub bytes: usize,
}

impl Flash {
    /// The flash of `board` as the `memory.x` text `memory` gives it, if it names a `FLASH` region.
    pub fn of(board: &'static str, memory: &str) -> Option<Flash> {
        Some(Flash { board, bytes: flash_length(memory)? })
    }

    /// The flash of `board` whose `memory.x` this binary carries at `rel`.
    fn carried(board: &'static str, rel: &str) -> Flash {
        let text = sources::carried(rel).map(String::from_utf8_lossy).unwrap_or_default();
        // The carried memory.x files are this checkout's (a test reads each): a board without one has
        // no room, and every set is refused by name.
        Flash::of(board, &text).unwrap_or(Flash { board, bytes: 0 })
    }

    /// QEMU's lm3s6965 (Cortex-M3), the board `codegen run` builds the `cell-qemu` image for.
    pub fn qemu() -> Flash {
        Flash::carried("lm3s6965 (QEMU)", "apps/cell/boards/lm3s6965/memory.x")
    }

    /// The Raspberry Pi Pico's RP2040 (Cortex-M0+), the board of `cell-pico` and `codegen run --target
    /// rp2040`.
    pub fn pico() -> Flash {
        Flash::carried("RP2040 (Pico)", "apps/cell/boards/pico/memory.x")
    }

    /// The flash of a board `codegen new` writes a project for, from the `memory.x` carried at `rel`.
    pub fn board(board: &'static str, rel: &str) -> Flash {
        Flash::carried(board, rel)
    }

    /// Bytes the tables may take: the flash less [`APPLICATION`].
    pub fn for_tables(&self) -> usize {
        self.bytes.saturating_sub(APPLICATION)
    }
}

/// The length of the `FLASH` region of a linker `MEMORY` block: `LENGTH = N`, `NK` or `NM` (decimal or
/// `0x` hexadecimal), less any `- M` terms (`2048K - 0x100`).
pub fn flash_length(memory: &str) -> Option<usize> {
    let line = memory.lines().find(|l| l.trim_start().starts_with("FLASH"))?;
    let (_, length) = line.split_once("LENGTH")?;
    let expr = length.trim_start().strip_prefix('=')?;
    let mut terms = expr.split('-');
    let mut bytes = number(terms.next()?)?;
    for t in terms {
        bytes = bytes.checked_sub(number(t)?)?;
    }
    Some(bytes)
}

/// A `memory.x` number: decimal or `0x` hexadecimal, with an optional `K` or `M` multiplier.
fn number(text: &str) -> Option<usize> {
    let t = text.trim().trim_end_matches(';').trim();
    let (digits, unit) = match t.strip_suffix('K') {
        Some(d) => (d, 1024),
        None => match t.strip_suffix('M') {
            Some(d) => (d, 1024 * 1024),
            None => (t, 1),
        },
    };
    let value = match digits.strip_prefix("0x") {
        Some(hex) => usize::from_str_radix(hex, 16).ok()?,
        None => digits.parse().ok()?,
    };
    value.checked_mul(unit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_read_as_the_linker_reads_them() {
        assert_eq!(flash_length("  FLASH : ORIGIN = 0x00000000, LENGTH = 256K"), Some(256 * 1024));
        assert_eq!(
            flash_length("FLASH : ORIGIN = 0x10000100, LENGTH = 2048K - 0x100"),
            Some(2048 * 1024 - 256)
        );
        assert_eq!(flash_length("FLASH : ORIGIN = 0, LENGTH = 0x8000"), Some(0x8000));
        assert_eq!(flash_length("RAM : ORIGIN = 0x20000000, LENGTH = 64K"), None);
    }

    /// Every carried board's flash reads from its memory.x, as the docs give it.
    #[test]
    fn the_carried_boards_flash() {
        assert_eq!(Flash::qemu().bytes, 256 * 1024);
        assert_eq!(Flash::pico().bytes, 2048 * 1024 - 256);
        assert_eq!(
            Flash::board("Nucleo-F401RE", "apps/cell/boards/nucleo-f401re/memory.x").bytes,
            512 * 1024
        );
        assert_eq!(Flash::board("nRF52840 DK", "apps/cell/boards/nrf52840-dk/memory.x").bytes, 1024 * 1024);
        assert_eq!(Flash::qemu().for_tables(), 224 * 1024);
    }
}
