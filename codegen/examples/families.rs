//! Writes a generated instance (see `codegen::synth::families`) as IDES3 files with a manifest:
//! `cargo run --example families -- FAMILY N DIR [SEED]` gives `DIR/FAMILY-N.toml` (`random-N-sSEED.toml`
//! with a seed, `random` only), `DIR/plants/*.xmd` and `DIR/specs/*.xmd`, ready for `codegen synth` and
//! for the reference-tool scripts.

use std::path::Path;
use std::process::ExitCode;

use codegen::formats::write_path;
use codegen::synth::families::{generate, random_seeded, state_section, FAMILIES};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(family), Some(Ok(n)), Some(dir)) =
        (args.first(), args.get(1).map(|n| n.parse::<usize>()), args.get(2))
    else {
        eprintln!(
            "usage: families FAMILY N DIR [SEED]   (FAMILY: {}; SEED: random only)",
            FAMILIES.join(", ")
        );
        return ExitCode::from(2);
    };
    let inst = match (family.as_str(), args.get(3).map(|s| s.parse::<u64>())) {
        (_, None) => generate(family, n),
        ("random", Some(Ok(seed))) => Some(random_seeded(n, seed)),
        (_, Some(_)) => {
            eprintln!("a SEED is a number, and only the random family takes one");
            return ExitCode::from(2);
        }
    };
    let Some(inst) = inst else {
        eprintln!("unknown family '{family}' (known: {})", FAMILIES.join(", "));
        return ExitCode::from(2);
    };
    let dir = Path::new(dir);
    let mut manifest = format!("name = \"{}\"\n", inst.name);
    for (key, automata) in [("plants", &inst.plants), ("specs", &inst.specs)] {
        let sub = dir.join(key);
        if let Err(e) = std::fs::create_dir_all(&sub) {
            eprintln!("{}: {e}", sub.display());
            return ExitCode::from(2);
        }
        let files: Vec<String> = automata.iter().map(|a| format!("\"{key}/{}.xmd\"", a.name)).collect();
        manifest.push_str(&format!("{key} = [{}]\n", files.join(", ")));
        for a in automata {
            if let Err(e) = write_path(&sub.join(format!("{}.xmd", a.name)), std::slice::from_ref(a)) {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
        }
    }
    if let Some(state) = state_section(family, n) {
        manifest.push_str(&state);
    }
    let path = dir.join(format!("{}.toml", inst.name));
    if let Err(e) = std::fs::write(&path, manifest) {
        eprintln!("{}: {e}", path.display());
        return ExitCode::from(2);
    }
    println!("{}", path.display());
    ExitCode::SUCCESS
}
