//! Support for the end-to-end tests: where the examples are, the cell with its published supervisors,
//! and the firmware's runtime run in a thread on the host behind an in-memory byte link.
#![deny(missing_docs)]

use std::path::{Path, PathBuf};
use std::thread::JoinHandle;
use std::time::Duration;

use codegen::closed_loop::{run_on_rp2040, run_on_rp2040_link, run_under_qemu, Options};
use codegen::config::SamplingSpec;
use codegen::formats::read_path;
use codegen::link::memory::MemoryLink;
use codegen::link::ByteLink;
use codegen::model::{Automaton, Kind};
use codegen::monitor::{ChoiceModel, Report};
use codegen::pack::PackSet;
use codegen::project::Project;
use codegen::target::rp2040::pin_map;
use firmware::build::HostTables;
use firmware::choice::Choose;
use firmware::event_loop::{EventLoop, Poll, Port};
use firmware::input_queue::InputQueue;
use firmware::link::{Hold, READY};
use firmware::rng::SeedEntropy;
use firmware::runtime::{Config, Runtime};
use firmware::table::CheckedSet;

/// The repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().map(Path::to_path_buf).unwrap_or_default()
}

/// A file under `examples/`.
pub fn example(path: &str) -> PathBuf {
    root().join("examples").join(path)
}

fn read_all(paths: &[&str]) -> Vec<Automaton> {
    paths.iter().flat_map(|p| read_path(&example(p)).unwrap_or_else(|e| panic!("{p}: {e}"))).collect()
}

/// The manufacturing cell: plants G1..G4 and the paper's published local modular supervisors.
pub fn published_cell() -> PackSet {
    let plants =
        read_all(&["cell/plants/G1.xmd", "cell/plants/G2.xmd", "cell/plants/G3.xmd", "cell/plants/G4.xmd"]);
    let sups = read_all(&[
        "cell/published/S1.xmd",
        "cell/published/S2_6.xmd",
        "cell/published/S3.xmd",
        "cell/published/S4.xmd",
        "cell/published/S5.xmd",
        "cell/published/S7.xmd",
    ]);
    PackSet::new(plants, sups).unwrap_or_else(|e| panic!("cell: {e}"))
}

/// Collects what the runtime sends, for the thread to forward in one write.
struct Outbox(Vec<u8>);

impl Port for Outbox {
    fn send(&mut self, byte: u8) {
        self.0.push(byte);
    }
}

/// Runs the firmware's runtime and event loop on `tables` in a thread, as the QEMU application does,
/// behind `link`: every chunk of bytes received is pushed into an input buffer of `Q - 1` slots before
/// the loop runs (so a burst larger than the buffer overflows, which the runtime reports), then the loop
/// serves until it is idle. The thread ends on EXIT (returning its status) or when the host hangs up.
/// `W`, `N`, `WIDE`, `MASK` and `LAYOUT` are the tables' shape ([`CheckedSet`]), `Q` the input buffer's
/// slots.
pub fn spawn_host_firmware<
    P,
    const W: usize,
    const N: usize,
    const WIDE: bool,
    const MASK: usize,
    const LAYOUT: u8,
    const Q: usize,
>(
    tables: HostTables<W>,
    config: Config,
    policy: P,
    seed: u64,
    mut link: MemoryLink,
) -> JoinHandle<Option<u8>>
where
    P: Choose<W> + Send + 'static,
{
    std::thread::spawn(move || {
        let set = tables.set();
        let checked = CheckedSet::<W, N, WIDE, MASK, LAYOUT>::new(&set).unwrap_or_else(|e| {
            panic!("tables do not fit W={W}, N={N}, WIDE={WIDE}, MASK={MASK}, LAYOUT={LAYOUT}: {e:?}")
        });
        let mut rt = Runtime::new(checked, config, policy, SeedEntropy::new(seed));
        let mut queue = InputQueue::<Q>::new();
        let (mut tx, mut rx) = queue.split();
        // On hold from boot, as the QEMU application: nothing is decided before the session releases it.
        let hold = Hold::on_hold();
        let mut event_loop = EventLoop::new();
        let mut out = Outbox(Vec::new());
        link.send(&[READY]).ok()?;
        let mut buf = [0u8; 512];
        let mut idle = false;
        loop {
            let wait = if idle { Duration::from_millis(5) } else { Duration::ZERO };
            let n = link.recv(&mut buf, wait).ok()?;
            for &b in &buf[..n] {
                if let Some(b) = hold.filter(b) {
                    if tx.push(b).is_err() {
                        tx.count_overflow();
                    }
                }
            }
            let poll = event_loop.turn(&mut rt, &mut rx, &hold, &mut out);
            if !out.0.is_empty() {
                link.send(&out.0).ok()?;
                out.0.clear();
            }
            match poll {
                Poll::Busy => idle = false,
                Poll::Idle | Poll::Held => idle = n == 0,
                Poll::Exit(status) => return Some(status),
            }
        }
    })
}

/// A scratch directory of one test, removed when dropped.
pub struct Scratch(PathBuf);

impl Scratch {
    /// A fresh directory named after `tag`, the process and a counter.
    pub fn new(tag: &str) -> Scratch {
        static COUNTER: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("end-to-end-{tag}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        Scratch(dir)
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Emits `project`'s tables and builds the QEMU firmware on them, in `scratch`; returns the ELF.
pub fn firmware_image(project: &Project, scratch: &Scratch) -> PathBuf {
    project.image(scratch.path()).unwrap_or_else(|e| panic!("{e}"))
}

/// Builds `project`'s firmware, boots it under QEMU and runs the closed loop with `options`.
pub fn qemu_closed_loop(project: &Project, options: &Options) -> Report {
    let seed = options.plant.seed;
    qemu_closed_loops(project, options, &[seed]).remove(0)
}

/// Builds `project`'s firmware once and runs the closed loop under QEMU with `options` for each of `seeds`
/// (the plant's seed), two runs at a time; the reports in the order of `seeds`.
pub fn qemu_closed_loops(project: &Project, options: &Options, seeds: &[u64]) -> Vec<Report> {
    qemu_closed_loops_judged(project, &project.set, options, seeds)
}

/// [`qemu_closed_loops`] with the monitor judging against `judged`, a set over the same events as
/// `project`'s (its supervisors with an observer added, say, whose coverage the report then counts).
pub fn qemu_closed_loops_judged(
    project: &Project,
    judged: &PackSet,
    options: &Options,
    seeds: &[u64],
) -> Vec<Report> {
    let scratch = Scratch::new(&project.name);
    let elf = firmware_image(project, &scratch);
    // The firmware must report the project's tables (it does: built from them here).
    let tables = project.table_digests().unwrap_or_else(|e| panic!("{e}"));
    let options = Options { tables, ..steered_for(project, options) };
    let run = |seed: u64| {
        let mut options = options.clone();
        options.plant.seed = seed;
        run_under_qemu(&elf, judged, &project.name, &options, &mut |_| {})
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"))
    };
    seeds
        .chunks(2)
        .flat_map(|pair| {
            std::thread::scope(|s| {
                let runs: Vec<_> = pair.iter().map(|&seed| s.spawn(move || run(seed))).collect();
                runs.into_iter()
                    .map(|r| r.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                    .collect::<Vec<_>>()
            })
        })
        .collect()
}

/// Emits `project`'s tables and pin map with the board reading its inputs by `sampling` (timer sampling
/// every millisecond), builds the Pico firmware on them in `scratch`; returns the ELF and the pin map file.
pub fn pico_image(project: &Project, sampling: SamplingSpec, scratch: &Scratch) -> (PathBuf, PathBuf) {
    let mut project = project.clone();
    let board = project.board.as_mut().unwrap_or_else(|| panic!("{}: no [board]", project.name));
    board.sampling = sampling;
    board.sample_period_us = (sampling == SamplingSpec::Timer).then_some(1000);
    let pins = scratch.path().join("pins.json");
    std::fs::write(&pins, pin_map(board, project.set.events()).unwrap_or_else(|e| panic!("{e}"))).unwrap();
    let elf = project.pico_image(scratch.path()).unwrap_or_else(|e| panic!("{e}"));
    (elf, pins)
}

/// Builds `project`'s Pico firmware for `sampling` and runs the closed loop with `options` on the emulated
/// RP2040, through the board's pins.
pub fn pico_closed_loop(project: &Project, sampling: SamplingSpec, options: &Options) -> Report {
    let scratch = Scratch::new(&format!("{}-pico", project.name));
    let (elf, pins) = pico_image(project, sampling, &scratch);
    let options = steered_for(project, options);
    run_on_rp2040(&elf, &pins, &project.set, &project.name, &options, &mut |_| {})
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Builds `project`'s Pico link build (`cell-pico-link`, the link protocol on UART0) and runs the closed
/// loop with `options` on the emulated RP2040 — in lock-step rounds and steps, as under QEMU.
pub fn pico_link_closed_loop(project: &Project, options: &Options) -> Report {
    let scratch = Scratch::new(&format!("{}-pico-link", project.name));
    let elf = project.pico_link_image(scratch.path()).unwrap_or_else(|e| panic!("{e}"));
    // The link build must report the project's (Cortex-M0+) tables, as `codegen run` asks.
    let tables = project.table_digests().unwrap_or_else(|e| panic!("{e}"));
    let options = Options { tables, ..steered_for(project, options) };
    run_on_rp2040_link(&elf, &project.set, &project.name, &options, &mut |_| {})
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Asserts that a closed-loop run under `what` was clean end to end: no violation, and the link in step
/// throughout — nothing lost, garbled, unexpected or unknown, no resynchronisation, stall or restart, and
/// the firmware's own counts of events taken and commands fired equal to what the host sent and judged.
/// None of these counts depends on the machine's load: a stall is judged on what plant and firmware
/// did, never on how long they took (`codegen::closed_loop::SessionConfig`).
pub fn assert_clean(report: &Report, what: &str) {
    assert_eq!(report.violations, 0, "{what}: {report}");
    assert!(report.findings.is_empty(), "{what}: {report}");
    let link = (report.lost, report.overflows, report.stalls, report.reboots, report.resyncs, report.garbled);
    assert_eq!(
        link,
        (0, 0, 0, 0, 0, 0),
        "{what}: lost, overflows, stalls, reboots, resyncs, garbled: {report}"
    );
    let fw = &report.firmware;
    assert_eq!((fw.unexpected, fw.unknown_bytes), (0, 0), "{what}: {report}");
    assert_eq!(fw.events_in, report.uncontrollable, "{what}: events taken by the firmware: {report}");
    assert_eq!(fw.commands_out, report.commands, "{what}: commands fired by the firmware: {report}");
}

/// `options` with the steering modelling `project`'s choice policy, as `codegen run` does.
fn steered_for(project: &Project, options: &Options) -> Options {
    Options { choices: ChoiceModel::of(project.runtime.policy), ..options.clone() }
}

/// A sensor that ticks freely (uncontrollable `tick`) and a controllable acknowledgement `ack` after an odd
/// tick: the smallest plant whose input buffer a burst of ticks can fill.
pub fn ticker() -> Automaton {
    let mut a = Automaton::new("Counter", Kind::Plant);
    let even = a.add_state("even", true).unwrap();
    let odd = a.add_state("odd", false).unwrap();
    let tick = a.add_event("tick", false).unwrap();
    let ack = a.add_event("ack", true).unwrap();
    a.initial = Some(even);
    a.add_transition(even, tick, odd);
    a.add_transition(odd, tick, even);
    a.add_transition(odd, ack, even);
    a
}
