//! The runtime's counters and state left in RAM, for a board without a host link.
//!
//! Under QEMU the host asks for the counters over the link (STATUS, [`crate::link`]). A board's
//! application has only pins, so it publishes the same six counters, in STATUS order, and two flags in a
//! `#[no_mangle]` static after every turn of its loop, where an emulator harness (`harness/rp2040/`,
//! which finds it by symbol) or a debugger reads them. Plain word stores: the M0+ has no atomic
//! read-modify-write, and a reader between two stores sees at worst one turn's counters mixed with the
//! next's, which only the harness reads, and only while the core sleeps.
//!
//! # Examples
//!
//! ```
//! use firmware::status::Published;
//!
//! static STATUS: Published = Published::new();
//! STATUS.store(&[3, 2, 0, 0, 1, 0], false);
//! assert_eq!(STATUS.load(), ([3, 2, 0, 0, 1, 0], Published::RUNNING));
//! ```

use core::sync::atomic::{AtomicU32, Ordering};

/// Six counter words in STATUS order (`events_in`, `commands_out`, `unexpected`, `overflows`,
/// `guard_redecisions`, `unknown_bytes`), then the flags word.
#[derive(Debug)]
#[repr(C)]
pub struct Published([AtomicU32; 7]);

impl Published {
    /// Flag: the loop has run at least one turn (the board is up).
    pub const RUNNING: u32 = 1;
    /// Flag: the runtime is in the safe state.
    pub const SAFE: u32 = 2;

    /// All zero: not running yet.
    pub const fn new() -> Self {
        Self([const { AtomicU32::new(0) }; 7])
    }

    /// Publishes `counters` and whether the runtime is in the safe state; sets [`Published::RUNNING`].
    pub fn store(&self, counters: &[u32; 6], safe: bool) {
        for (word, value) in self.0.iter().zip(counters) {
            word.store(*value, Ordering::Relaxed);
        }
        let flags = Self::RUNNING | if safe { Self::SAFE } else { 0 };
        self.0[6].store(flags, Ordering::Relaxed);
    }

    /// The counters and flags last published.
    pub fn load(&self) -> ([u32; 6], u32) {
        let mut counters = [0; 6];
        for (value, word) in counters.iter_mut().zip(&self.0) {
            *value = word.load(Ordering::Relaxed);
        }
        (counters, self.0[6].load(Ordering::Relaxed))
    }
}

impl Default for Published {
    fn default() -> Self {
        Self::new()
    }
}
