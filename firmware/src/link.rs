//! The byte protocol between the firmware and a host (the virtual plant over QEMU's UART socket, a serial
//! port, or the RP2040 harness speaking it for the board's pins); [`crate::event_loop`] drives a
//! `Runtime` from the bytes it defines.
//!
//! One byte per event: `0x00..=0xEF` is an event id — host → firmware an uncontrollable event the plant
//! produced, firmware → host a controllable command the firmware fired. Control bytes:
//!
//! | byte | direction | meaning |
//! |---|---|---|
//! | `0xF0` RESET | host → fw | automata to initial states, counters to zero, safe state left; answered by READY |
//! | `0xF1` STATUS | both | request; answered by `0xF1` then the [`Counters`] in [`STATUS_BYTES`] bytes: six `u32` little-endian, events_in, commands_out, unexpected, overflows, guard_redecisions, unknown_bytes ([`Counters::from_status`] reads them back) |
//! | `0xF2` EXIT | host → fw | end the emulation: status 0, or 1 in the safe state |
//! | `0xF3` READY | fw → host | once at boot and after each RESET |
//! | `0xF4` SAFE | fw → host | a fault put the firmware in the safe state; it stopped deciding |
//! | `0xF5` HOLD, `0xF6` GO | host → fw | stop / resume deciding; handled in the receive interrupt ([`Hold`]) so that a burst can be queued between two decisions |
//! | `0xF7` SYNC | both | request: answer SYNC once nothing is enabled (or in the safe state) and deciding is not on hold; so a host can run the loop in lock-step, every round's decisions taken on every input it sent |
//! | `0xF8` STEP | host → fw | decide once on every input sent before it (fire at most one command), then hold again and answer SYNC; so a host can take its turn between any two decisions of a controller that never runs out of commands |
//! | `0xF9` TABLES | both | request: which tables does the firmware run? answered by `0xF9` then the [`TABLES_BYTES`] ASCII hex digits of their digest (`firmware::table::image::digest`, the `DIGEST` of the emitted tables), so that a host refuses a firmware built from another manifest; a loop given no digest ([`EventLoop::new`](crate::event_loop::EventLoop::new)) treats it as any unknown byte, as a firmware from before TABLES does |
//! | `0xFA` TIME | host → fw | then 2 bytes, little-endian: Δ ms (1..=65535): virtual time moved on by Δ. The firmware advances its timers ([`crate::timer`]) by Δ; each timeout that falls due (in the order they fall due) is taken as an uncontrollable event, as if the plant had sent it, and its event id is sent to the host as a command is. Sent while the firmware is held, before that round's plant events, so a lock-step run stays a function of its seeds. A firmware without timers takes the 2 bytes and ignores them; a Δ of 0 is a fault (`unknown_bytes`). The 2 bytes are data, whatever their value: the receive filter ([`Hold::filter`]) passes them through, not as HOLD or GO |
//!
//! A firmware a host drives (QEMU's, the host-compiled one of the tests) boots on hold ([`Hold::on_hold`]):
//! it sends READY and decides nothing until the host's first GO or STEP.
//!
//! Any other byte from `0xF0` up, an event id beyond the set, and a *controllable* event id sent by the
//! host (only the firmware generates those) count as `unknown_bytes` and are faults. Control bytes go
//! through the input buffer in order with the events (so a RESET or STATUS sees every event sent before
//! it), except HOLD and GO. STEP goes through the buffer, so its decision sees every event before it.

use crate::runtime::Counters;
use core::sync::atomic::{AtomicBool, AtomicU8, Ordering};

/// Host → firmware: back to the initial state.
pub const RESET: u8 = 0xF0;
/// Host → firmware: counters request; firmware → host: the answer's first byte.
pub const STATUS: u8 = 0xF1;
/// Host → firmware: end the emulation.
pub const EXIT: u8 = 0xF2;
/// Firmware → host: ready for events.
pub const READY: u8 = 0xF3;
/// Firmware → host: in the safe state.
pub const SAFE: u8 = 0xF4;
/// Host → firmware: stop deciding.
pub const HOLD: u8 = 0xF5;
/// Host → firmware: resume deciding.
pub const GO: u8 = 0xF6;
/// Host → firmware: answer SYNC once idle; firmware → host: idle (the answer).
pub const SYNC: u8 = 0xF7;
/// Host → firmware: take one decision, then hold and answer [`SYNC`].
pub const STEP: u8 = 0xF8;
/// Host → firmware: which tables do you run; firmware → host: the answer's first byte, then the
/// digest's [`TABLES_BYTES`] hex digits.
pub const TABLES: u8 = 0xF9;
/// Host → firmware: virtual time moved on; then [`TIME_BYTES`] bytes, the Δ in ms, little-endian
/// (1..=65535). The firmware's timers advance by Δ and every timeout that falls due is taken as an
/// uncontrollable event and sent back as its event id (see the module's table).
pub const TIME: u8 = 0xFA;
/// Bytes of a TIME message after its leading [`TIME`]: the Δ ms as a `u16` little-endian.
pub const TIME_BYTES: usize = 2;
/// Bytes of a TABLES answer after its leading [`TABLES`]: the 16 lowercase hex digits of the tables'
/// digest, as the emitted tables' `DIGEST` spells it.
pub const TABLES_BYTES: usize = 16;
/// Highest event id the link can carry.
pub const MAX_EVENT: u8 = 0xEF;
/// Bytes of a STATUS answer after its leading [`STATUS`]: the six counters of
/// [`Counters::to_array`], each a `u32` little-endian.
pub const STATUS_BYTES: usize = 24;

impl Counters {
    /// The counters a STATUS answer carries in its `bytes` after the leading [`STATUS`] (what
    /// [`EventLoop::turn`](crate::event_loop::EventLoop::turn) sends, read back by the host).
    pub fn from_status(bytes: &[u8; STATUS_BYTES]) -> Counters {
        let word = |i: usize| {
            u32::from_le_bytes([bytes[4 * i], bytes[4 * i + 1], bytes[4 * i + 2], bytes[4 * i + 3]])
        };
        Counters {
            events_in: word(0),
            commands_out: word(1),
            unexpected: word(2),
            overflows: word(3),
            guard_redecisions: word(4),
            unknown_bytes: word(5),
        }
    }
}

/// The decision gate that HOLD and GO set from the receive interrupt. It also counts the bytes of a
/// TIME message still to come, so that a Δ byte that happens to read as HOLD or GO goes to the loop as
/// the data it is.
#[derive(Debug, Default)]
pub struct Hold {
    held: AtomicBool,
    /// Bytes of a TIME message the receive filter still passes through as data.
    payload: AtomicU8,
}

impl Hold {
    /// Deciding allowed: a board that no host drives.
    pub const fn new() -> Self {
        Self { held: AtomicBool::new(false), payload: AtomicU8::new(0) }
    }

    /// Deciding on hold until the first GO or STEP: a firmware a host drives boots this way, so that it
    /// decides nothing (and draws nothing from its random generator) before the host has reset it and
    /// released it. A lock-step run then repeats exactly from the seeds, however long the host took to
    /// connect. A constant initialiser: no code at boot.
    pub const fn on_hold() -> Self {
        Self { held: AtomicBool::new(true), payload: AtomicU8::new(0) }
    }

    /// Called by the receive interrupt for every byte: consumes HOLD and GO, hands every other byte back
    /// for the input buffer — the [`TIME_BYTES`] after a TIME too, whatever their value. Only the
    /// receive interrupt calls it (one caller at a time), so its count needs no atomic read-modify-write
    /// (which the Cortex-M0+ lacks).
    pub fn filter(&self, byte: u8) -> Option<u8> {
        let payload = self.payload.load(Ordering::Relaxed);
        if payload > 0 {
            self.payload.store(payload - 1, Ordering::Relaxed);
            return Some(byte);
        }
        match byte {
            HOLD => self.hold(),
            GO => self.release(),
            TIME => {
                self.payload.store(TIME_BYTES as u8, Ordering::Relaxed);
                return Some(TIME);
            }
            other => return Some(other),
        }
        None
    }

    /// Puts deciding on hold, as HOLD does (the end of a STEP).
    pub fn hold(&self) {
        self.held.store(true, Ordering::Relaxed);
    }

    /// Lets deciding go on, as GO does (a STEP's start).
    pub fn release(&self) {
        self.held.store(false, Ordering::Relaxed);
    }

    /// Whether deciding is on hold.
    pub fn is_held(&self) -> bool {
        self.held.load(Ordering::Relaxed)
    }
}
