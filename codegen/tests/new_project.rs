//! A firmware project of the user's own: `codegen new DIR --board pico` with DIR outside the checkout,
//! built and run closed loop on the emulated RP2040 by `codegen run --project DIR` (`cargo build
//! --release` inside it: the tables emitted by its build script, codegen a build-dependency); then the
//! manifest edited (a specification dropped) and the project built again with no other step changes
//! its tables and its image; and a broken model fails the build with the file named.
//!
//! The projects build into one target directory under the checkout's (`target/new-project`), with the
//! carried sources unpacked beside it, so the dependencies compile once across runs.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{repo, Temp};

/// The shared target directory and cache of the generated projects.
fn shared() -> (PathBuf, PathBuf) {
    let dir = repo("target/new-project");
    (dir.join("target"), dir.join("cache"))
}

/// `program ARGS` in `dir` as a user runs it in a shell (the cargo on `PATH`, none of the test's cargo
/// settings), with the shared cache and target directory.
fn user(program: &str, dir: &Path, args: &[&str]) -> Output {
    Command::new(program)
        .args(args)
        .current_dir(dir)
        .env_remove("CARGO")
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        .env("SCT_CODEGEN_CACHE", shared().1)
        .env("CARGO_TARGET_DIR", shared().0)
        .output()
        .unwrap()
}

/// `codegen ARGS` in `dir`.
fn codegen(dir: &Path, args: &[&str]) -> Output {
    user(env!("CARGO_BIN_EXE_codegen"), dir, args)
}

/// `cargo build --release` in the project `dir`.
fn cargo_build(dir: &Path) -> Output {
    user("cargo", dir, &["build", "--release"])
}

/// The emitted tables of the newest build of package `name` (its build script's `OUT_DIR`).
fn tables(target: &Path, name: &str) -> String {
    let build = target.join("thumbv6m-none-eabi/release/build");
    let newest = std::fs::read_dir(&build)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with(&format!("{name}-"))))
        .map(|p| p.join("out/tables.rs"))
        .filter(|p| p.is_file())
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).unwrap())
        .expect("the build script wrote its tables");
    std::fs::read_to_string(newest).unwrap()
}

fn text(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

#[test]
fn a_new_pico_project_builds_outside_the_checkout_runs_closed_loop_and_follows_its_manifest() {
    let temp = Temp(std::env::temp_dir().join(format!("codegen-new-project-{}", std::process::id())));
    std::fs::create_dir_all(&temp.0).unwrap();
    let dir = temp.0.join("cell-pico");
    let out = codegen(&temp.0, &["new", "cell-pico", "--board", "pico"]);
    assert!(out.status.success(), "{}", text(&out));
    for file in [
        "Cargo.toml",
        "Cargo.lock",
        "memory.x",
        ".cargo/config.toml",
        "build.rs",
        "src/main.rs",
        "src/board_app.rs",
        "README.md",
    ] {
        assert!(dir.join(file).is_file(), "{file} missing");
    }
    let config = std::fs::read_to_string(dir.join(".cargo/config.toml")).unwrap();
    assert!(
        config.contains("probe-rs run --chip RP2040") && config.contains("thumbv6m-none-eabi"),
        "{config}"
    );
    assert!(
        !codegen(&temp.0, &["new", "cell-pico", "--board", "pico"]).status.success(),
        "a second new over it"
    );

    // Built by `codegen run --project` (cargo build --release in it), run on the emulated RP2040
    // against the project's own manifest.
    let ran = codegen(&temp.0, &["run", "--project", "cell-pico", "--events", "5000", "--json"]);
    assert_eq!(ran.status.code(), Some(0), "{}", text(&ran));
    let json: serde_json::Value = serde_json::from_slice(&ran.stdout).unwrap();
    assert_eq!((json["target"].as_str(), json["name"].as_str()), (Some("rp2040"), Some("cell")), "{json}");
    assert_eq!(json["violations"].as_u64(), Some(0), "{json}");
    assert!(json["full_coverage_at"].is_u64(), "coverage not complete: {}", json["coverage"]);
    let target = shared().0;
    let elf = target.join("thumbv6m-none-eabi/release/cell-pico");
    let image = std::fs::read(&elf).unwrap();
    let before = tables(&target, "cell-pico");

    // Edit the manifest (E7 dropped), build again: new tables, new image, no other step.
    let manifest = dir.join("model/cell.toml");
    let edited = std::fs::read_to_string(&manifest).unwrap().replace("  \"specs/E7.xmd\",\n", "");
    std::fs::write(&manifest, edited).unwrap();
    let rebuilt = cargo_build(&dir);
    assert!(rebuilt.status.success(), "{}", text(&rebuilt));
    let after = tables(&target, "cell-pico");
    assert_ne!(before, after, "the tables follow the manifest");
    assert!(!after.contains("E7") && before.contains("E7"));
    assert_ne!(std::fs::read(&elf).unwrap(), image, "the image follows the tables");

    // A broken model fails the build, naming the file as the CLI does.
    std::fs::write(dir.join("model/plants/G1.xmd"), "<Automaton broken").unwrap();
    let failed = cargo_build(&dir);
    assert!(!failed.status.success());
    assert!(
        text(&failed).contains("error: model/cell.toml: plants[0]: model/plants/G1.xmd: line 1"),
        "{}",
        text(&failed)
    );
}

/// Flash and static RAM of `elf` from `llvm-size -A` (the toolchain's llvm-tools, as
/// `scripts/measure/footprint.py` reads them): flash is what is programmed (`.vector_table`, `.text`,
/// `.rodata`, `.data`'s initial values), RAM what is reserved (`.data`, `.bss`, `.uninit`). A section
/// `.text`, `.rodata` or `.bss` not found fails: a measurement that finds nothing is no measurement.
fn footprint(elf: &Path) -> [(&'static str, u64); 2] {
    let rustc =
        |args: &[&str]| String::from_utf8(Command::new("rustc").args(args).output().unwrap().stdout).unwrap();
    let sysroot = rustc(&["--print", "sysroot"]);
    let host = rustc(&["-vV"]).lines().find_map(|l| l.strip_prefix("host: ")).unwrap().to_owned();
    let size = Path::new(sysroot.trim()).join("lib/rustlib").join(host).join("bin/llvm-size");
    let out =
        Command::new(&size).arg("-A").arg(elf).output().unwrap_or_else(|e| panic!("{}: {e}", size.display()));
    assert!(out.status.success(), "{}", text(&out));
    let listing = String::from_utf8(out.stdout).unwrap();
    let section = |name: &str| {
        listing.lines().find_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 3 && f[0] == name).then(|| f[1].parse::<u64>().unwrap())
        })
    };
    for required in [".vector_table", ".text", ".rodata", ".bss"] {
        assert!(section(required).is_some_and(|s| s > 0), "{}: no {required}:\n{listing}", elf.display());
    }
    let sum = |names: &[&str]| names.iter().map(|n| section(n).unwrap_or(0)).sum();
    [
        ("flash", sum(&[".vector_table", ".text", ".rodata", ".data"])),
        ("static_ram", sum(&[".data", ".bss", ".uninit"])),
    ]
}

/// Checks `measured` against `.ci/expected/NAME.size` (`NAME VALUE TOLERANCE%` lines, `#` comments, the
/// format of `scripts/measure/expect.py`): every figure listed, each within its tolerance.
fn check_expected(name: &str, measured: &[(&str, u64)]) {
    let path = repo(&format!(".ci/expected/{name}.size"));
    let file = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut seen = 0;
    for line in file.lines().map(|l| l.split('#').next().unwrap().trim()).filter(|l| !l.is_empty()) {
        let f: Vec<&str> = line.split_whitespace().collect();
        let (figure, value, tolerance) = (f[0], f[1].parse::<f64>().unwrap(), f[2]);
        let allowed = match tolerance.strip_suffix('%') {
            Some(pct) => value * pct.parse::<f64>().unwrap() / 100.0,
            None => tolerance.parse::<f64>().unwrap(),
        };
        let (_, got) = measured
            .iter()
            .find(|(n, _)| *n == figure)
            .unwrap_or_else(|| panic!("{}: {figure} is not measured", path.display()));
        assert!(
            (*got as f64 - value).abs() <= allowed,
            "{}: {figure} = {got}, expected {value} ± {tolerance}",
            path.display()
        );
        seen += 1;
    }
    assert_eq!(seen, measured.len(), "{}: every measured figure is expected", path.display());
}

/// The boards with no emulator here: `codegen new`'s name, the Rust target, probe-rs's chip.
const OTHER_BOARDS: &[(&str, &str, &str)] = &[
    ("nucleo-f401re", "thumbv7em-none-eabihf", "STM32F401RETx"),
    ("nrf52840-dk", "thumbv7em-none-eabihf", "nRF52840_xxAA"),
];

/// The boards with no emulator here: each project is written from the starter manifest outside the
/// checkout, builds for its target with the chip's probe-rs runner, and its flash and RAM stay within
/// `.ci/expected/cell-<board>.size`.
#[test]
fn the_other_boards_projects_build_within_their_recorded_size() {
    let temp = Temp(std::env::temp_dir().join(format!("codegen-new-boards-{}", std::process::id())));
    std::fs::create_dir_all(&temp.0).unwrap();
    for &(board, target, chip) in OTHER_BOARDS {
        let name = format!("cell-{board}");
        let out = codegen(&temp.0, &["new", &name, "--board", board]);
        assert!(out.status.success(), "{}", text(&out));
        let dir = temp.0.join(&name);
        let config = std::fs::read_to_string(dir.join(".cargo/config.toml")).unwrap();
        assert!(
            config.contains(&format!("probe-rs run --chip {chip}")) && config.contains(target),
            "{config}"
        );
        let built = cargo_build(&dir);
        assert!(built.status.success(), "{board}: {}", text(&built));
        check_expected(&name, &footprint(&shared().0.join(target).join("release").join(&name)));
    }
}
