//! Fuzz the PNML reader: any bytes give a well-formed net or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| codegen::net::check_pnml(std::path::Path::new("fuzz.pnml"), data));
