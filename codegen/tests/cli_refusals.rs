//! Refusals through the command line: a layout that cannot hold a set, or whose tables exceed what a
//! board's flash leaves them, is refused — by `emit`, `run` (QEMU and RP2040), `pack` and `new` — naming
//! the layout, the size, the limit and what would fit, before anything is built or written (exit 2).

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use codegen::config::Layout;
use codegen::synth::{families, monolithic, Config};
use common::{repo, Temp};

/// A scratch directory beside the build (`target/`), removed when dropped.
fn scratch(tag: &str) -> Temp {
    let dir = repo("target/tmp").join(format!("cli-refusals-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    Temp(dir)
}

fn codegen(dir: &Path, args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_codegen"))
        .args(args)
        .current_dir(dir)
        .env("SCT_CODEGEN_CACHE", dir.join("cache"))
        .output()
        .unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A plant whose state 0 has 256 transitions (255 uncontrollable self-loops `x0`…`x254` and `go`), more
/// than a `memory-safe` or `offset` record's count byte holds; a manifest over it with `layout`.
fn hub(dir: &Path, layout: &str) -> PathBuf {
    let xs: Vec<String> = (0..255).map(|i| format!("x{i}")).collect();
    let loops: Vec<String> = xs.iter().map(|x| format!("s0 {x} s0")).collect();
    let gen = format!(
        "<Generator>\n\"Hub\"\n<Alphabet>\n{} go +C+\n</Alphabet>\n<States>\ns0 s1\n</States>\n<TransRel>\n{}\ns0 go s1\ns1 x0 s0\n</TransRel>\n<InitStates>\ns0\n</InitStates>\n<MarkedStates>\ns0\n</MarkedStates>\n</Generator>\n",
        xs.join(" "),
        loops.join("\n")
    );
    std::fs::write(dir.join("hub.gen"), gen).unwrap();
    let manifest = dir.join("hub.toml");
    std::fs::write(
        &manifest,
        format!("name = \"hub\"\nplants = [\"hub.gen\"]\n\n[runtime]\nlayout = \"{layout}\"\n"),
    )
    .unwrap();
    manifest
}

/// What every refusal of the hub's `memory-safe` tables says: the layout, the state, the number, the
/// limit, the layouts that fit with their bytes, and the reduction.
fn assert_hub_refusal(text: &str) {
    assert!(
        text.contains("layout memory-safe: state 0 of 'hub' has 256 outgoing transitions, more than the limit of 255; --layout "),
        "{text}"
    );
    for layout in ["compact", "ranked", "indexed"] {
        assert!(text.contains(&format!("--layout {layout} ")), "{layout}: {text}");
    }
    assert!(!text.contains("--layout offset"), "offset holds no more than 255 either: {text}");
    assert!(text.contains("; or reduce the supervisors (`codegen synth --reduce`)"), "{text}");
}

#[test]
fn emit_and_run_refuse_a_layout_that_cannot_hold_the_set_and_say_what_fits() {
    let dir = scratch("hub");
    let manifest = hub(&dir.0, "memory-safe");
    let out = codegen(&dir.0, &["emit", manifest.to_str().unwrap(), "-o", "x.rs"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_hub_refusal(&stderr(&out));
    assert!(!dir.0.join("x.rs").exists());
    // `run` refuses before it builds: nothing is unpacked into the cache.
    for target in [&[][..], &["--target", "rp2040"]] {
        let mut args = vec!["run", manifest.to_str().unwrap(), "--events", "10"];
        args.extend_from_slice(target);
        let out = codegen(&dir.0, &args);
        assert_eq!(out.status.code(), Some(2), "{target:?}: {}", stderr(&out));
        assert_hub_refusal(&stderr(&out));
    }
    assert!(!dir.0.join("cache/target").exists(), "a refused run built something");
}

#[test]
fn pack_marks_only_the_layouts_that_run_and_says_why_a_core_runs_none() {
    let dir = scratch("pack");
    let manifest = hub(&dir.0, "memory-safe");
    let out = codegen(&dir.0, &["pack", manifest.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let layouts = json["layouts"].as_array().unwrap();
    assert_eq!(layouts[0]["name"], "memory-safe");
    assert_eq!(layouts[0]["bytes"], serde_json::Value::Null);
    assert!(layouts[0]["error"].as_str().unwrap().starts_with("layout memory-safe: state 0 of 'hub'"));
    assert!(layouts.iter().all(|l| l["runs_on"].as_array().unwrap().is_empty()), "{layouts:?}");
    for core in json["cores"].as_array().unwrap() {
        assert_hub_refusal(core["refused"].as_str().unwrap());
    }
    // Without the manifest's layout, the defaults run.
    let manifest = hub(&dir.0, "ranked");
    let text = String::from_utf8(codegen(&dir.0, &["pack", manifest.to_str().unwrap()]).stdout).unwrap();
    assert!(text.contains("← runs on cortex-m3 (lm3s6965 (QEMU)), cortex-m0+ (RP2040 (Pico))"), "{text}");
}

/// The monolithic supervisor of the factory with 5 machines (7 203 states, 36 407 transitions) with its
/// plants, as a manifest with `layout`: `indexed` takes about 330 KB, more than the lm3s6965's flash
/// leaves the tables.
fn factory(dir: &Path, layout: &str) -> PathBuf {
    let inst = families::generate("factory", 5).unwrap();
    let sup = monolithic(&inst.plants, &inst.specs, &Config::default()).unwrap();
    assert_eq!(sup.automaton.states.len(), 7203);
    let mut plants = Vec::new();
    for p in &inst.plants {
        let name = format!("{}.gen", p.name);
        codegen::formats::write_path(&dir.join(&name), std::slice::from_ref(p)).unwrap();
        plants.push(format!("\"{name}\""));
    }
    codegen::formats::write_path(&dir.join("S.gen"), std::slice::from_ref(&sup.automaton)).unwrap();
    let manifest = dir.join("factory.toml");
    let text = format!(
        "name = \"factory5\"\nplants = [{}]\nsupervisors = [\"S.gen\"]\n\n[runtime]\nlayout = \"{layout}\"\n",
        plants.join(", ")
    );
    std::fs::write(&manifest, text).unwrap();
    manifest
}

#[test]
fn run_refuses_tables_past_the_boards_flash_and_says_what_fits() {
    let dir = scratch("flash");
    let manifest = factory(&dir.0, "indexed");
    let out = codegen(&dir.0, &["run", manifest.to_str().unwrap(), "--events", "10"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let text = stderr(&out);
    let fits = |layout: Layout| {
        let bytes =
            codegen::pack::fit::fit(&codegen::project::Project::load(&manifest).unwrap().set, layout, None)
                .unwrap()
                .bytes;
        format!(
            "--layout {layout} {}{bytes} bytes",
            if layout == Layout::Compact { "fits in " } else { "in " }
        )
    };
    assert!(
        text.contains("layout indexed: the tables take ")
            && text.contains(" bytes, more than the 229376 bytes the lm3s6965 (QEMU)'s 262144 bytes of flash leave them (32768 kept for the application); "),
        "{text}"
    );
    // Every other layout fits, smallest first: compact, ranked, memory-safe, offset.
    for layout in [Layout::Compact, Layout::Ranked, Layout::MemorySafe, Layout::Offset] {
        assert!(text.contains(&fits(layout)), "{}: {text}", fits(layout));
    }
    assert!(!dir.0.join("cache/target").exists(), "a refused run built something");
}

#[test]
fn new_refuses_a_manifest_its_board_cannot_run_and_writes_nothing() {
    let dir = scratch("new");
    let manifest = hub(&dir.0, "memory-safe");
    let project = dir.0.join("project");
    for board in ["pico", "nucleo-f401re"] {
        let out = codegen(
            &dir.0,
            &["new", project.to_str().unwrap(), "--board", board, "--manifest", manifest.to_str().unwrap()],
        );
        assert_eq!(out.status.code(), Some(2), "{board}: {}", stderr(&out));
        assert_hub_refusal(&stderr(&out));
        assert!(!project.exists(), "{board}: the refused project was written");
    }
}
