//! Fuzz the host's decoder of what a firmware sends: any bytes give frames, never a panic, and every byte
//! is accounted for — a command, READY or SAFE is one byte, a STATUS answer 1 + `STATUS_BYTES`, anything
//! else an unknown byte.
#![no_main]

use codegen::link::protocol::{Decoder, Frame, STATUS_BYTES};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut decoder = Decoder::default();
    let mut bytes = 0;
    for &b in data {
        match decoder.push(b) {
            Some(Frame::Status(_)) => bytes += 1 + STATUS_BYTES,
            Some(_) => bytes += 1,
            None => {}
        }
    }
    // What is left is a STATUS answer still incomplete.
    assert!(data.len() - bytes <= STATUS_BYTES);
});
