//! The board in the loop: the Pico's link build (`cell-pico-link`, the supervisors driven over UART0)
//! on the emulated RP2040, and the virtual plant and monitor attached to it through a **serial port** —
//! what `codegen plant --connect serial:DEVICE` does against a flashed Pico.
//!
//! The harness (`harness/rp2040/src/main.js --uart`) wires UART0 to a Unix socket; the test makes a
//! pseudo-terminal pair and copies bytes between its master and that socket, so the plant opens the
//! terminal's device path as it opens `/dev/ttyACM0` (`Endpoint::Serial`: the `serialport` crate, raw
//! 8N1, TIOCEXCL) — the serial path, not a socket standing in for it.
//!
//! Lock-step rounds (the firmware answers SYNC and STEP, as under QEMU): 0 violations, full coverage and
//! the marked-state liveness the pin runs cannot measure. Then the plant's own timing at different answer
//! rates — a fixed delay; a uniform range with two commands answered at rates of their own — where
//! verdicts could depend on time: the monitor's read
//! window (0.5 s) and stall timeout (10 s) are the margins; the emulator answers a byte in well under a
//! millisecond of wall time when it is not starved.

use std::io::{Read, Write};
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use codegen::closed_loop::{attach, Options, SessionConfig};
use codegen::link::Endpoint;
use codegen::monitor::{ChoiceModel, Report};
use codegen::project::Project;
use end_to_end::{example, root, Scratch};
use serialport::{SerialPort, TTYPort};

/// The harness in `--uart` mode on `elf`, killed when dropped.
struct UartHarness(Child);

impl UartHarness {
    fn start(elf: &Path, socket: &Path, stats: &Path) -> (Self, UnixStream) {
        let child = Command::new("node")
            .arg(root().join("harness/rp2040/src/main.js"))
            .arg("--uart")
            .arg("--elf")
            .arg(elf)
            .arg("--socket")
            .arg(socket)
            .arg("--stats")
            .arg(stats)
            .stdin(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("node: {e} (scripts/setup.sh installs Node and the harness)"));
        let harness = UartHarness(child);
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

impl Drop for UartHarness {
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

/// The cell's link build, built once per test.
fn link_image(project: &Project, scratch: &Scratch) -> PathBuf {
    project.pico_link_image(scratch.path()).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs the closed loop with `options` against `elf` on the emulated RP2040, through a pseudo-terminal.
fn run_over_serial(project: &Project, elf: &Path, scratch: &Scratch, tag: &str, options: &Options) -> Report {
    let socket = scratch.path().join(format!("{tag}.sock"));
    let stats = scratch.path().join(format!("{tag}.json"));
    let (harness, stream) = UartHarness::start(elf, &socket, &stats);
    // The slave end stays open here for the whole run, so the master never reads a hang-up.
    let (master, slave) = TTYPort::pair().expect("a pseudo-terminal pair");
    let device = slave.name().expect("the pseudo-terminal's device path");
    let to_board = pump(master.try_clone_native().unwrap(), stream.try_clone().unwrap());
    let from_board = pump(stream.try_clone().unwrap(), master);
    let endpoint: Endpoint = format!("serial:{device}").parse().unwrap();
    let mut link = endpoint.connect().unwrap_or_else(|e| panic!("{device}: {e}"));
    // As `codegen plant` does: the link build must report the project's (Cortex-M0+) tables.
    let tables = project.table_digests().unwrap_or_else(|e| panic!("{e}"));
    let options = Options { choices: ChoiceModel::of(project.runtime.policy), tables, ..options.clone() };
    let report = attach(&mut link, &project.set, &project.name, &options, &mut |_| {})
        .unwrap_or_else(|e| panic!("{tag}: {e}"));
    drop(link);
    let _ = stream.shutdown(std::net::Shutdown::Both);
    let _ = from_board.join();
    drop(harness);
    drop(to_board);
    eprintln!("{tag}: {report}");
    report
}

/// Safe, in step, every reachable controllable supervisor transition taken.
fn check(report: &Report, events: u64, what: &str) {
    assert_eq!(report.target, "link", "{what}");
    assert!(report.events >= events, "{what}: {report}");
    assert_eq!(report.violations, 0, "{what}: {report}");
    let fw = &report.firmware;
    assert_eq!((report.lost, report.overflows, report.stalls), (0, 0, 0), "{what}: {report}");
    assert_eq!((fw.unexpected, fw.unknown_bytes, fw.overflows), (0, 0, 0), "{what}: {report}");
    assert!(report.full_coverage(), "{what}: {report}");
}

#[test]
fn the_pico_link_build_runs_the_cell_closed_loop_over_a_serial_port() {
    let project = Project::load(&example("cell/cell.toml")).unwrap();
    let scratch = Scratch::new("pico-link");
    let elf = link_image(&project, &scratch);

    // Lock-step: the same trace for the same seeds, and the liveness the pin runs cannot measure.
    let events = 5_000;
    let lockstep = run_over_serial(&project, &elf, &scratch, "lockstep", &Options::for_events(events));
    check(&lockstep, events, "lock-step");
    assert!(lockstep.marked_visits >= events / 100, "{lockstep}");
    assert!(lockstep.longest_marked_gap < 2_000, "{lockstep}");
    let fw = &lockstep.firmware;
    assert_eq!(fw.events_in, lockstep.uncontrollable, "events taken by the firmware: {lockstep}");
    assert_eq!(fw.commands_out, lockstep.commands, "commands fired by the firmware: {lockstep}");

    // The plant's own timing at different answer rates: a fixed 500 µs; uniform in 0..3 ms with two
    // devices answering at rates of their own (the robot's r_c1b1 after a fixed 2 ms, the machine's
    // m1_ini_a after 1..5 ms), as `--answer-delay-us COMMAND=MIN..MAX` sets them.
    let events = 3_000;
    let own = vec![("r_c1b1".to_owned(), (2_000, 2_000)), ("m1_ini_a".to_owned(), (1_000, 5_000))];
    for (tag, delay_us, answer_delay_us) in
        [("fixed-500us", (500, 500), Vec::new()), ("uniform-0-3ms-per-command", (0, 3_000), own)]
    {
        let mut options = Options::for_events(events);
        options.session = SessionConfig::realtime();
        options.plant.delay_us = delay_us;
        options.plant.answer_delay_us = answer_delay_us;
        check(&run_over_serial(&project, &elf, &scratch, tag, &options), events, tag);
    }
}
