//! The board in the loop: the Pico's link builds — `cell-pico-usb` (the supervisors driven over the
//! Pico's USB port, a CDC-ACM serial device) and `cell-pico-link` (over UART0) — on the emulated RP2040,
//! and **the `codegen` binary** attached to each through a serial port — `codegen plant --project DIR
//! --connect serial:DEVICE`, as a user runs it against a flashed Pico.
//!
//! `DIR` is a project `codegen new DIR --board pico` wrote (the cell starter: `examples/cell/cell.toml`);
//! the link build is built on the tables of that project's manifest. The harness
//! (`harness/rp2040/src/main.js --usb`: the USB port enumerated by rp2040js's CDC host; `--uart`: UART0)
//! wires the link to a Unix socket; the test makes a pseudo-terminal pair and copies bytes between its
//! master and that socket, so `codegen plant` opens the terminal's device path as it opens
//! `/dev/ttyACM0` (the `serialport` crate, raw 8N1, TIOCEXCL) — the serial path, not a socket standing
//! in for it.
//!
//! Lock-step rounds (the firmware answers SYNC and STEP, as under QEMU): 0 violations, full coverage and
//! the marked-state liveness the pin runs cannot measure. Then the plant's own timing at different answer
//! rates — a fixed delay; a uniform range with two commands answered at rates of their own — where
//! verdicts could depend on time: the monitor's read window (0.5 s) and stall timeout (10 s) are the
//! margins; the emulator answers a byte in well under a millisecond of wall time when it is not starved.

mod common;

use std::io::{Read, Write};
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use codegen::project::user_project::UserProject;
use codegen::project::Project;
use common::{repo, Temp};
use serde_json::Value;
use serialport::{SerialPort, TTYPort};

/// Which link build, and the harness's mode that carries its link.
#[derive(Clone, Copy)]
enum Link {
    /// `cell-pico-usb`, `--usb`.
    Usb,
    /// `cell-pico-link`, `--uart`.
    Uart,
}

impl Link {
    /// The link build on `project`'s tables, built in `dir`.
    fn image(self, project: &Project, dir: &Path) -> PathBuf {
        match self {
            Link::Usb => project.pico_usb_image(dir),
            Link::Uart => project.pico_link_image(dir),
        }
        .unwrap_or_else(|e| panic!("{e}"))
    }

    /// The harness's option.
    fn mode(self) -> &'static str {
        match self {
            Link::Usb => "--usb",
            Link::Uart => "--uart",
        }
    }
}

/// The harness in `--usb` or `--uart` mode on `elf`, killed when dropped.
struct LinkHarness(Child);

impl LinkHarness {
    fn start(link: Link, elf: &Path, socket: &Path, stats: &Path) -> (Self, UnixStream) {
        let child = Command::new("node")
            .arg(repo("harness/rp2040/src/main.js"))
            .arg(link.mode())
            .arg("--elf")
            .arg(elf)
            .arg("--socket")
            .arg(socket)
            .arg("--stats")
            .arg(stats)
            .stdin(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("node: {e} (scripts/setup.sh installs Node and the harness)"));
        let harness = LinkHarness(child);
        let deadline = Instant::now() + Duration::from_secs(30);
        loop {
            match UnixStream::connect(socket) {
                Ok(stream) => return (harness, stream),
                Err(e) if Instant::now() > deadline => panic!("{}: {e}", socket.display()),
                Err(_) => std::thread::sleep(Duration::from_millis(20)),
            }
        }
    }
}

impl Drop for LinkHarness {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Copies bytes from `from` to `to` until either side closes or fails.
fn pump(mut from: impl Read + Send + 'static, mut to: impl Write + Send + 'static) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let mut buf = [0u8; 256];
        loop {
            match from.read(&mut buf) {
                Ok(0) => return,
                Ok(n) => {
                    if to.write_all(&buf[..n]).and_then(|()| to.flush()).is_err() {
                        return;
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(_) => return,
            }
        }
    })
}

/// `codegen new DIR --board pico` in `temp`: the cell starter, its sources unpacked in the cache the
/// firmware images are built from (`SCT_CODEGEN_CACHE`, inherited).
fn new_pico_project(temp: &Path) -> PathBuf {
    let dir = temp.join("my-cell");
    let out = Command::new(env!("CARGO_BIN_EXE_codegen"))
        .args(["new", &dir.display().to_string(), "--board", "pico"])
        .output()
        .expect("run codegen new");
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    dir
}

/// Runs `codegen plant --project DIR --connect serial:/dev/pts/N --json ARGS` against `elf` on the
/// emulated RP2040, its `link` through a pseudo-terminal; returns the JSON report.
fn plant_over_serial(link: Link, dir: &Path, elf: &Path, temp: &Path, tag: &str, args: &[&str]) -> Value {
    let socket = temp.join(format!("{tag}.sock"));
    let stats = temp.join(format!("{tag}.json"));
    let (harness, stream) = LinkHarness::start(link, elf, &socket, &stats);
    // The slave end stays open here for the whole run, so the master never reads a hang-up.
    let (master, slave) = TTYPort::pair().expect("a pseudo-terminal pair");
    let device = slave.name().expect("the pseudo-terminal's device path");
    let to_board = pump(master.try_clone_native().unwrap(), stream.try_clone().unwrap());
    let from_board = pump(stream.try_clone().unwrap(), master);
    let out = Command::new(env!("CARGO_BIN_EXE_codegen"))
        .args(["plant", "--project", &dir.display().to_string(), "--connect", &format!("serial:{device}")])
        .arg("--json")
        .args(args)
        .output()
        .expect("run codegen plant");
    let _ = stream.shutdown(std::net::Shutdown::Both);
    let _ = from_board.join();
    drop(harness);
    drop(to_board);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{tag}: {stderr}\n{}", String::from_utf8_lossy(&out.stdout));
    let report: Value =
        serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{tag}: {e}: {stderr}"));
    eprintln!(
        "{tag}: {} events, {} violations, coverage at {}",
        report["events"], report["violations"], report["full_coverage_at"]
    );
    report
}

/// The report's field `key` as a number.
fn n(report: &Value, key: &str) -> u64 {
    report[key].as_u64().unwrap_or_else(|| panic!("{key} in {report}"))
}

/// Safe, in step, every reachable controllable supervisor transition taken.
fn check(report: &Value, events: u64, what: &str) {
    assert_eq!(report["target"], "link", "{what}");
    assert!(n(report, "events") >= events, "{what}: {report}");
    assert_eq!(n(report, "violations"), 0, "{what}: {report}");
    for key in ["lost", "overflows", "stalls"] {
        assert_eq!(n(report, key), 0, "{what}: {key}: {report}");
    }
    let fw = &report["firmware"];
    for key in ["unexpected", "unknown_bytes", "overflows"] {
        assert_eq!(n(fw, key), 0, "{what}: firmware.{key}: {report}");
    }
    let coverage = report["coverage"].as_array().expect("coverage");
    assert!(!coverage.is_empty(), "{what}: {report}");
    for line in coverage {
        assert_eq!(line["reachable"], line["taken"], "{what}: full coverage: {report}");
    }
    assert!(report["full_coverage_at"].is_u64(), "{what}: {report}");
}

/// One emulated RP2040 at a time: the realtime runs race the emulator against the plant's wall-clock
/// timing, and two emulators and two plants on a 2-core machine would only slow each other down.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// A fresh `codegen new --board pico` project in a temporary directory named for `tag`, and `link`'s
/// build on its tables: the directory (removed when dropped), the project's and the image's paths.
fn project_and_image(link: Link, tag: &str) -> (Temp, PathBuf, PathBuf) {
    let temp = Temp(std::env::temp_dir().join(format!("codegen-pico-{tag}-{}", std::process::id())));
    let _ = std::fs::remove_dir_all(&temp.0);
    std::fs::create_dir_all(&temp.0).unwrap();
    let dir = new_pico_project(&temp.0);
    let manifest = UserProject::open(&dir).unwrap_or_else(|e| panic!("{e}")).manifest;
    let project = Project::load(&manifest).unwrap_or_else(|e| panic!("{e}"));
    let elf = link.image(&project, &temp.0);
    (temp, dir, elf)
}

/// `codegen plant` against `link`'s build: lock-step, then the plant's timing at different rates.
fn closed_loop_over_serial(link: Link, tag: &str) {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let (temp, dir, elf) = project_and_image(link, tag);
    let run = |what: &str, args: &[&str]| {
        plant_over_serial(link, &dir, &elf, &temp.0, &format!("{tag}-{what}"), args)
    };

    // Lock-step (the default): the same trace for the same seeds, and the liveness the pin runs cannot
    // measure.
    let events = 5_000;
    let lockstep = run("lockstep", &["--events", &events.to_string()]);
    check(&lockstep, events, "lock-step");
    assert!(n(&lockstep, "marked_visits") >= events / 100, "{lockstep}");
    assert!(n(&lockstep, "longest_marked_gap") < 2_000, "{lockstep}");
    let fw = &lockstep["firmware"];
    assert_eq!(
        n(fw, "events_in"),
        n(&lockstep, "uncontrollable"),
        "events taken by the firmware: {lockstep}"
    );
    assert_eq!(n(fw, "commands_out"), n(&lockstep, "commands"), "commands fired by the firmware: {lockstep}");

    // The plant's own timing at different answer rates: a fixed 500 µs; uniform in 0..3 ms with two
    // devices answering at rates of their own (the robot's r_c1b1 after a fixed 2 ms, the machine's
    // m1_ini_a after 1..5 ms).
    let events = 3_000.to_string();
    let realtime = ["--events", &events, "--timing", "realtime"];
    let fixed = [&realtime[..], &["--delay-us", "500..500"]].concat();
    let own = [
        &realtime[..],
        &[
            "--delay-us",
            "0..3000",
            "--answer-delay-us",
            "r_c1b1=2000..2000",
            "--answer-delay-us",
            "m1_ini_a=1000..5000",
        ],
    ]
    .concat();
    for (what, args) in [("fixed-500us", fixed), ("uniform-0-3ms-per-command", own)] {
        check(&run(what, &args), 3_000, what);
    }
}

#[test]
fn codegen_plant_runs_the_cell_closed_loop_against_the_pico_usb_link_build_over_a_serial_port() {
    closed_loop_over_serial(Link::Usb, "usb");
}

#[test]
fn codegen_plant_runs_the_cell_closed_loop_against_the_pico_uart_link_build_over_a_serial_port() {
    closed_loop_over_serial(Link::Uart, "uart");
}

/// A host far ahead of the firmware: a burst many times the input buffer's size (1 000 unknown bytes,
/// held) reaches the USB link build at once. The input buffer fills, the rest waits in the USB stack
/// (its packets refused until the loop has drained the buffer), and every byte is taken in the end:
/// the STATUS that follows is answered, counting each byte once as unknown and none lost. Before the
/// buffer-status interrupt was switched off while the buffer was full, a packet left in the endpoint
/// kept that interrupt running and the firmware never answered (a realtime run's "no STATUS answer").
#[test]
fn a_burst_far_beyond_the_input_buffer_waits_in_the_usb_stack_and_is_all_taken() {
    use codegen::link::protocol::{Decoder, Frame, HOLD, RESET, STATUS};
    /// Not an event of the cell's set: counted as unknown, nothing else happens.
    const UNKNOWN: u8 = 0xEF;
    const BURST: usize = 1_000;

    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let (temp, _, elf) = project_and_image(Link::Usb, "burst");
    let (_harness, mut stream) =
        LinkHarness::start(Link::Usb, &elf, &temp.0.join("burst.sock"), &temp.0.join("burst.json"));
    // Not a timing margin: a firmware that stopped answering fails here instead of hanging the test.
    stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut decoder = Decoder::default();
    let mut next_frame = |stream: &mut UnixStream| loop {
        let mut byte = [0u8];
        match stream.read(&mut byte) {
            Ok(1) => {
                if let Some(frame) = decoder.push(byte[0]) {
                    return frame;
                }
            }
            other => panic!("the link build stopped answering: {other:?}"),
        }
    };

    stream.write_all(&[RESET]).unwrap();
    while next_frame(&mut stream) != Frame::Ready {}
    let mut burst = vec![HOLD];
    burst.extend([UNKNOWN; BURST]);
    burst.push(STATUS);
    stream.write_all(&burst).unwrap();
    let counters = loop {
        if let Frame::Status(counters) = next_frame(&mut stream) {
            break counters;
        }
    };
    assert_eq!(counters.unknown_bytes, BURST as u32, "{counters:?}");
    assert_eq!(counters.overflows, 0, "{counters:?}");
}
