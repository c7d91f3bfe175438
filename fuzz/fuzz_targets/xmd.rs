//! Fuzz the `.xmd` reader: any bytes give automata or an error, never a panic, and what reads is
//! valid, canonical, and survives writing it back.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| codegen::formats::check_reader(std::path::Path::new("fuzz.xmd"), data));
