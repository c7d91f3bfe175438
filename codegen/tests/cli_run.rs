//! `codegen run` as a binary: a clean run's exit status and JSON (under QEMU, and on the emulated
//! RP2040 over its link), and exit 2 with a message for a file that is no project, for options that go
//! with another target, for an emulator that cannot start and for a firmware built from other tables.
//! (Exit 1 on a violation: `tests/mutants.rs`
//! kills wrong firmware through the same `run_under_qemu` the command calls.)

use std::path::Path;
use std::process::{Command, Output};

use codegen::project::Project;

fn codegen(args: &[&str], path: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_codegen"));
    cmd.args(args);
    if let Some(p) = path {
        cmd.env("PATH", p);
    }
    cmd.output().expect("run codegen")
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel).display().to_string()
}

#[test]
fn a_clean_run_exits_0_with_the_json_report() {
    let out = codegen(&["run", &repo("examples/factory/factory.toml"), "--events", "600", "--json"], None);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((json["schema"].as_u64(), json["target"].as_str()), (Some(3), Some("qemu")));
    assert_eq!((json["name"].as_str(), json["violations"].as_u64()), (Some("factory"), Some(0)));
    assert!(json["events"].as_u64().unwrap() >= 600);
    assert_eq!(json["firmware"]["events_in"], json["uncontrollable"]);
}

/// `run --target rp2040` runs the Pico's link build over UART0 in lock-step rounds (the default `--io
/// link`): the QEMU run's report, liveness included, and — the trace being a function of the seeds alone
/// in lock-step — the very trace the Cortex-M3 takes. `--io` is refused beside another target, and the
/// pin options beside the link build.
#[test]
fn the_pico_link_build_runs_in_lock_step_and_takes_the_qemu_runs_trace() {
    let factory = repo("examples/factory/factory.toml");
    let json_of = |target: &str| {
        let out =
            codegen(&["run", &factory, "--target", target, "--events", "600", "--seed", "2", "--json"], None);
        assert_eq!(out.status.code(), Some(0), "{target}: {}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let (qemu, pico) = (json_of("qemu"), json_of("rp2040"));
    assert_eq!((pico["target"].as_str(), pico["violations"].as_u64()), (Some("rp2040"), Some(0)), "{pico}");
    assert!(pico["board"].is_null(), "no pin figures over the link: {pico}");
    assert!(pico["marked_visits"].as_u64().unwrap() > 0, "liveness measured: {pico}");
    assert_eq!(pico["firmware"]["events_in"], pico["uncontrollable"], "{pico}");
    assert!(pico["full_coverage_at"].as_u64().is_some(), "{pico}");
    assert_eq!(pico["events"], qemu["events"], "{pico}\n{qemu}");
    assert_eq!(pico["trace_sha256"], qemu["trace_sha256"], "one trace on both cores: {pico}\n{qemu}");

    for (args, says) in [
        (&["--target", "qemu", "--io", "pins"][..], "--io goes with --target rp2040"),
        (&["--target", "rp2040", "--sampling", "timer"][..], "go with --io pins"),
    ] {
        let out = codegen(&[&["run", factory.as_str(), "--events", "10"][..], args].concat(), None);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(says),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// `run --elf` with a firmware built from other tables — the factory's, booted for the cell's manifest —
/// is refused over the link before anything runs (exit 2), naming both tables' digests; it used to run
/// and report thousands of violations (issue 35).
#[test]
fn a_firmware_built_from_other_tables_is_refused_naming_both() {
    let factory = Project::load(Path::new(&repo("examples/factory/factory.toml"))).unwrap();
    let cell = Project::load(Path::new(&repo("examples/cell/cell.toml"))).unwrap();
    let scratch = std::env::temp_dir().join(format!("codegen-cli-other-tables-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    let elf = factory.image(&scratch).unwrap_or_else(|e| panic!("{e}"));
    let elf = elf.display().to_string();
    let out = codegen(&["run", &repo("examples/cell/cell.toml"), "--elf", &elf, "--events", "100"], None);
    std::fs::remove_dir_all(&scratch).ok();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    let (theirs, ours) = (factory.table_digests().unwrap(), cell.table_digests().unwrap());
    assert_eq!(ours.len(), 2, "the Cortex-M3's and the Cortex-M0+'s tables: {ours:?}");
    let named = format!("the firmware runs tables {}, the project's are {}", theirs[0], ours.join(" or "));
    assert!(err.contains(&named), "{err}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!stdout.contains("violations"), "refused before the run, no report: {stdout}");
}

/// A project with `[[timers]]` runs closed loop under QEMU: the session's virtual clock sent as TIME,
/// the firmware raising each timeout on its millisecond, the monitor judging them (slack 0). The
/// cylinder, 200 events: timeouts fall due (the fault path), every one on time, no violation, and
/// every supervisor transition taken (the alarm after a late end switch included).
#[test]
fn a_project_with_timers_runs_under_qemu_with_its_timeouts_on_time() {
    let json = cylinder_runs_clean("qemu", "200");
    assert_eq!(json["firmware"]["unknown_bytes"], 0, "TIME is no unknown byte to the firmware");
    assert!(json["full_coverage_at"].as_u64().is_some(), "{}", json["coverage"]);
}

/// The cylinder run on `target` for `events` events, its JSON report checked: exit 0, no violation,
/// some timeout fell due, every one on time, and every supervisor transition taken — the late end
/// switch's path too (after the timeout, before the alarm).
fn cylinder_runs_clean(target: &str, events: &str) -> serde_json::Value {
    let cylinder = repo("examples/cylinder/cylinder.toml");
    let out = codegen(&["run", &cylinder, "--target", target, "--events", events, "--json"], None);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((json["name"].as_str(), json["target"].as_str()), (Some("cylinder"), Some(target)));
    assert_eq!(json["violations"].as_u64(), Some(0), "{json}");
    let t = &json["timeouts"];
    assert!(t["on_time"].as_u64().unwrap() > 0, "no timeout fell due: {t}");
    assert_eq!((t["early"].as_u64(), t["late"].as_u64(), t["missing"].as_u64()), (Some(0), Some(0), Some(0)));
    assert_eq!(json["uncovered"], serde_json::json!([]), "{}", json["coverage"]);
    json
}

/// The Pico's link build runs the tables' timers on the host's TIME as QEMU's firmware does: the
/// cylinder on the emulated RP2040 over UART0, 100 events (about 10 s, the link image built once into
/// the cache), every timeout on time and every transition taken. Its pin build runs them on its own
/// tick in the emulator's wall-clock time: refused before anything is built (exit 2).
#[test]
fn a_project_with_timers_runs_on_the_picos_link_build_and_is_refused_on_its_pins() {
    cylinder_runs_clean("rp2040", "100");
    let cylinder = repo("examples/cylinder/cylinder.toml");
    let out = codegen(&["run", &cylinder, "--target", "rp2040", "--io", "pins", "--events", "10"], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("cylinder.toml: [[timers]] with --io pins"), "{err}");
}

#[test]
fn a_model_file_is_no_project_to_run() {
    let out = codegen(&["run", &repo("examples/cell/plants/G1.xmd")], None);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a project"));
}

#[test]
fn an_emulator_that_cannot_start_is_exit_2_naming_it() {
    // cargo and the host's C toolchain (a cold firmware build links build scripts with `cc`) stay
    // reachable; qemu-system-arm does not.
    let tools = std::env::temp_dir().join(format!("sct-no-qemu-{}", std::process::id()));
    std::fs::create_dir_all(&tools).unwrap();
    let path = std::env::var_os("PATH").unwrap_or_default();
    for tool in ["cc", "gcc", "ld", "ar", "as"] {
        let found = std::env::split_paths(&path).map(|d| d.join(tool)).find(|p| p.is_file());
        if let Some(found) = found {
            let _ = std::os::unix::fs::symlink(found, tools.join(tool));
        }
    }
    let cargo = std::env::var("CARGO").unwrap();
    let cargo_dir = Path::new(&cargo).parent().unwrap().display();
    let search = format!("{}:{cargo_dir}", tools.display());
    let out = codegen(&["run", &repo("examples/factory/factory.toml"), "--events", "10"], Some(&search));
    let _ = std::fs::remove_dir_all(&tools);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot start qemu-system-arm"), "{err}");
}

/// `run --project` and `plant --project` on a project `codegen new` wrote (no build: its board has no
/// emulator here). `run` refuses the board with exit 2 before building anything; the positional manifest
/// cannot be given beside `--project`; `plant` takes the project's manifest (it loads, and the run stops
/// at the socket that does not exist; broken, it is named).
#[test]
fn a_project_of_your_own_is_run_on_its_boards_emulator_or_refused() {
    let temp = std::env::temp_dir().join(format!("codegen-cli-project-{}", std::process::id()));
    std::fs::create_dir_all(&temp).unwrap();
    let dir = temp.join("nrf");
    let dir_arg = dir.display().to_string();
    let codegen_in = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_codegen"))
            .args(args)
            .env("SCT_CODEGEN_CACHE", repo("target/new-project/cache"))
            .output()
            .expect("run codegen")
    };
    let stderr = |out: &Output| String::from_utf8_lossy(&out.stderr).into_owned();
    let out = codegen_in(&["new", &dir_arg, "--board", "nrf52840-dk"]);
    assert!(out.status.success(), "{}", stderr(&out));

    let out = codegen_in(&["run", "--project", &dir_arg]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("for the nrf52840-dk board, which has no emulator here"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.join("target").exists(), "refused before building");

    let out = codegen_in(&["run", "--project", &dir_arg, &repo("examples/cell/cell.toml")]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("cannot be used with"), "{}", stderr(&out));

    let socket = temp.join("no-such-socket");
    let connect = format!("unix:{}", socket.display());
    // A project with timers is taken too (a link build runs them on the session's TIME): the run
    // stops at the socket, not at the timers.
    let out = codegen_in(&["plant", &repo("examples/cylinder/cylinder.toml"), "--connect", &connect]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("connecting to"), "{}", stderr(&out));
    let out = codegen_in(&["plant", "--project", &dir_arg, "--connect", &connect]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("connecting to") && stderr(&out).contains("no-such-socket"),
        "{}",
        stderr(&out)
    );

    std::fs::write(dir.join("model/cell.toml"), "name = ").unwrap();
    let out = codegen_in(&["plant", "--project", &dir_arg, "--connect", &connect]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains(&format!("{}", dir.join("model/cell.toml").display())), "{}", stderr(&out));
    std::fs::remove_dir_all(&temp).ok();
}
