//! Times one synthesis in-process, for `scripts/reference/timing.py`: reads the manifest (not timed),
//! then runs monolithic synthesis (`monolithic`) or local modular synthesis with the conflict check and no
//! merge (`conflict`) three times and prints the best wall time in seconds and the total supervisor states.
//!
//! `cargo run --release --example synth_time -- MODE MANIFEST`

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use codegen::manifest::Manifest;
use codegen::synth::{self, Config};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(mode), Some(path)) = (args.first(), args.get(1)) else {
        eprintln!("usage: synth_time (monolithic | conflict) MANIFEST");
        return ExitCode::from(2);
    };
    let set = match Manifest::load(Path::new(path)).and_then(|m| m.read_automata()) {
        Ok(set) => set,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let cfg = Config { merge_conflicting: false, ..Config::default() };
    let mut best = f64::INFINITY;
    let mut states = 0;
    for _ in 0..3 {
        let start = Instant::now();
        let result = match mode.as_str() {
            "monolithic" => {
                synth::monolithic(&set.plants, &set.specs, &cfg).map(|s| s.automaton.states.len())
            }
            "conflict" => synth::local_modular(&set.plants, &set.specs, &cfg).map(|r| r.total_states()),
            _ => {
                eprintln!("unknown mode '{mode}'");
                return ExitCode::from(2);
            }
        };
        best = best.min(start.elapsed().as_secs_f64());
        match result {
            Ok(n) => states = n,
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
        }
    }
    println!("{best:.6} {states}");
    ExitCode::SUCCESS
}
