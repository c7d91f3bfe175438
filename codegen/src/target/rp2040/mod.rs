//! Runs the Pico firmware on an emulated RP2040: the harness process (`harness/rp2040/`, Node and
//! rp2040js), which the closed loop talks to as it talks to QEMU, in one of two modes.
//!
//! - **Pins** ([`Harness::start`]): the harness loads the pin application (`cargo pico-build`, or a
//!   `codegen new` project's build), listens on a Unix socket and speaks the firmware link protocol there
//!   (`firmware::link`) on the firmware's behalf: the plant's uncontrollable events become edges on the
//!   input pins the manifest's `[board]` section names ([`pin_map`]), output pin changes become the
//!   commands the monitor judges, RESET powers the board on afresh, STATUS answers the counters the
//!   firmware publishes (`firmware::status`), EXIT ends the run. What only pins show it counts, and
//!   writes with the cost of the runtime's entry points to a stats file ([`Harness::figures`]). No SYNC
//!   nor STEP: the run takes the plant's own timing.
//! - **Link** ([`Harness::start_uart`], the harness's `--uart`): it loads the link build
//!   (`cargo pico-link-build`) and wires UART0 to the socket byte for byte; the firmware answers the
//!   protocol itself, SYNC and STEP included, so the closed loop runs in lock-step as under QEMU.
//!
//! The harness's README documents both.
//!
//! As with [`super::qemu`], the child is killed when the [`Harness`] value is dropped, when its deadline
//! passes and when the thread that started it dies ([`super::child`]).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

use serde_json::json;

use super::child::{ConnectError, Emulator, CONNECT_WITHIN};
use super::sources::{self, SourcesError};
use crate::config::{BoardSpec, SamplingSpec};
use crate::link::StreamLink;
use crate::model::EventTable;

/// How to start the harness.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HarnessConfig {
    /// The Node binary.
    pub node: String,
    /// The harness script (`main.js`); none: the harness this binary carries ([`sources`]), its
    /// packages installed on first use.
    pub script: Option<PathBuf>,
    /// Seed of the ring oscillator's random bit.
    pub seed: u64,
    /// Where to save the raw defmt frames the firmware writes over RTT (none: not drained).
    pub rtt: Option<PathBuf>,
    /// Width of an input pulse in µs (none: the harness's default for the sampling mode).
    pub input_pulse_us: Option<u32>,
    /// Let edges arrive before the firmware has read the one before, so that their order is lost as
    /// on real pins (`--together`).
    pub together: bool,
    /// Let input edges arrive while a command pulse is high (`--overlap`).
    pub overlap: bool,
    /// Hard limit on the harness's life.
    pub timeout: Duration,
}

impl Default for HarnessConfig {
    fn default() -> Self {
        HarnessConfig {
            node: "node".into(),
            script: None,
            seed: 1,
            rtt: None,
            input_pulse_us: None,
            together: false,
            overlap: false,
            timeout: Duration::from_secs(600),
        }
    }
}

/// The pin map cannot carry the closed loop.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum PinMapError {
    /// No `[board]` section.
    #[error("the manifest has no [board] section: the board's pins are not known")]
    NoBoard,
    /// The section names an event the set does not have.
    #[error("board: event '{0}' is not an event of the set")]
    UnknownEvent(String),
    /// An event of the set that no pin carries: the plant could not make it, or not see it.
    #[error("board: {what} '{event}' has no {pin}, so the closed loop cannot carry it")]
    Unmapped {
        /// `uncontrollable event` or `command`.
        what: &'static str,
        /// Its name.
        event: String,
        /// `input pin` or `output pin`.
        pin: &'static str,
    },
    /// A pin the RP2040 does not have (its GPIOs are 0 to [`LAST_GPIO`]).
    #[error("board: pin {0}: the RP2040 has GPIO 0 to {LAST_GPIO}")]
    NoSuchPin(u8),
}

/// The RP2040's last GPIO of bank 0.
pub const LAST_GPIO: u8 = 29;

/// The harness could not be run, or its figures not read.
#[derive(Debug, thiserror::Error)]
pub enum HarnessError {
    /// Spawning failed (Node not installed?).
    #[error("cannot start {program}: {source} (run scripts/setup.sh to install Node and the harness)")]
    Spawn {
        /// The program.
        program: String,
        /// Why.
        source: std::io::Error,
    },
    /// A scratch file or directory failed.
    #[error("{}: {source}", path.display())]
    File {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The harness exited before its socket accepted a connection.
    #[error("the rp2040 harness exited early ({status}): {stderr}")]
    Exited {
        /// Exit status.
        status: ExitStatus,
        /// What it printed on stderr.
        stderr: String,
    },
    /// The socket did not accept a connection in time.
    #[error("the rp2040 harness's socket {} did not come up: {source}", path.display())]
    Connect {
        /// The socket.
        path: PathBuf,
        /// The last connection error.
        source: std::io::Error,
    },
    /// The harness ended without writing its figures.
    #[error("the rp2040 harness wrote no figures to {}: {source}\n{stderr}", path.display())]
    NoFigures {
        /// The stats file.
        path: PathBuf,
        /// Why it could not be read.
        source: std::io::Error,
        /// What the harness printed on stderr.
        stderr: String,
    },
    /// The carried harness could not be unpacked or its packages installed.
    #[error(transparent)]
    Sources(#[from] SourcesError),
    /// The stats file is not what the harness writes.
    #[error("{}: {source}", path.display())]
    Stats {
        /// The file.
        path: PathBuf,
        /// Why.
        source: serde_json::Error,
    },
}

/// The JSON pin map the harness reads: `board` from the manifest, event names resolved to the ids the
/// firmware uses (`events`). Every uncontrollable event must have an input pin and every command an
/// output pin, or the closed loop could not carry it.
pub fn pin_map(board: &BoardSpec, events: &EventTable) -> Result<String, PinMapError> {
    let id = |name: &str| events.id(name).ok_or_else(|| PinMapError::UnknownEvent(name.to_owned()));
    let pins = board.inputs.iter().map(|i| i.pin).chain(board.outputs.iter().map(|o| o.pin));
    if let Some(pin) = pins.into_iter().find(|&p| p > LAST_GPIO) {
        return Err(PinMapError::NoSuchPin(pin));
    }
    let mut inputs = Vec::new();
    for i in &board.inputs {
        inputs.push(json!({ "event": id(&i.event)?.as_u32(), "name": i.event, "pin": i.pin, "edge": i.edge, "pull": i.pull }));
    }
    let mut outputs = Vec::new();
    for o in &board.outputs {
        outputs.push(json!({
            "event": id(&o.event)?.as_u32(), "name": o.event, "pin": o.pin, "action": o.action, "pulse_ms": o.pulse_ms,
        }));
    }
    for e in events.ids() {
        let name = events.name(e);
        let (what, pin, mapped) = if events.is_controllable(e) {
            ("command", "output pin", board.outputs.iter().any(|o| o.event == name))
        } else {
            ("uncontrollable event", "input pin", board.inputs.iter().any(|i| i.event == name))
        };
        if !mapped {
            return Err(PinMapError::Unmapped { what, event: name.to_owned(), pin });
        }
    }
    let sampling = match board.sampling {
        SamplingSpec::Interrupt => "interrupt",
        SamplingSpec::Timer => "timer",
    };
    let map = json!({
        "board": board.name,
        "sampling": sampling,
        "sample_period_us": board.sample_period_us,
        "inputs": inputs,
        "outputs": outputs,
    });
    Ok(format!("{map:#}\n"))
}

/// A running harness; see the module documentation.
#[derive(Debug)]
pub struct Harness {
    process: Emulator,
    dir: PathBuf,
    stats: PathBuf,
}

impl Harness {
    /// Starts the harness on `elf` (the pin application, `cell-pico`) with the pin map file `pins`, and
    /// connects to it: the harness speaks the link protocol on the firmware's behalf, through its pins.
    pub fn start(
        elf: &Path,
        pins: &Path,
        config: &HarnessConfig,
    ) -> Result<(Self, StreamLink), HarnessError> {
        Self::spawn(elf, config, |cmd| {
            cmd.arg("--pins").arg(pins);
            if let Some(us) = config.input_pulse_us {
                cmd.arg("--input-pulse-us").arg(us.to_string());
            }
            if config.together {
                cmd.arg("--together");
            }
            if config.overlap {
                cmd.arg("--overlap");
            }
        })
    }

    /// Starts the harness in its `--uart` mode on `elf` (the link build, `cell-pico-link`), and connects
    /// to it: the link is UART0's bytes, which the firmware answers itself (SYNC and STEP included, so
    /// the closed loop runs in lock-step as under QEMU). The pin options of `config` do not apply. The
    /// board cannot obey EXIT: the harness ends when the link is closed.
    pub fn start_uart(elf: &Path, config: &HarnessConfig) -> Result<(Self, StreamLink), HarnessError> {
        Self::spawn(elf, config, |cmd| {
            cmd.arg("--uart");
        })
    }

    /// Spawns the harness on `elf` with the options common to both modes and those `mode` adds, and
    /// connects to its socket.
    fn spawn(
        elf: &Path,
        config: &HarnessConfig,
        mode: impl FnOnce(&mut Command),
    ) -> Result<(Self, StreamLink), HarnessError> {
        static COUNTER: AtomicU32 = AtomicU32::new(0);
        let dir = std::env::temp_dir().join(format!(
            "codegen-rp2040-{}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir).map_err(|source| HarnessError::File { path: dir.clone(), source })?;
        let socket = dir.join("board.sock");
        let stats = dir.join("stats.json");
        let script = match &config.script {
            Some(script) => script.clone(),
            None => sources::harness_script()?,
        };
        let mut cmd = Command::new(&config.node);
        cmd.arg(&script).arg("--elf").arg(elf).arg("--socket").arg(&socket);
        cmd.arg("--stats").arg(&stats).arg("--seed").arg(config.seed.to_string());
        if let Some(rtt) = &config.rtt {
            cmd.arg("--rtt").arg(rtt);
        }
        mode(&mut cmd);
        let process = Emulator::spawn(&mut cmd, config.timeout)
            .map_err(|source| HarnessError::Spawn { program: config.node.clone(), source })?;
        let mut harness = Harness { process, dir, stats };
        let link = harness.process.connect(&socket, CONNECT_WITHIN).map_err(|e| match e {
            ConnectError::Exited { status, stderr } => HarnessError::Exited { status, stderr },
            ConnectError::Timeout { path, source } => HarnessError::Connect { path, source },
        })?;
        Ok((harness, link))
    }

    /// Waits up to `timeout` for the harness to exit (after EXIT, or once the link is closed); kills it
    /// when the time is up and returns `None`.
    pub fn wait(&mut self, timeout: Duration) -> Option<ExitStatus> {
        self.process.wait(timeout)
    }

    /// The figures the harness wrote when the run ended (call after [`Harness::wait`]), read as `T`
    /// (the report's `monitor::BoardFigures`: the harness writes them, the report carries them).
    pub fn figures<T: serde::de::DeserializeOwned>(&self) -> Result<T, HarnessError> {
        let path = self.stats.clone();
        let text = std::fs::read_to_string(&path).map_err(|source| HarnessError::NoFigures {
            path: path.clone(),
            source,
            stderr: self.stderr(),
        })?;
        serde_json::from_str(&text).map_err(|source| HarnessError::Stats { path, source })
    }

    /// What the harness printed on stderr so far (its settings, its summary, its errors).
    pub fn stderr(&self) -> String {
        self.process.stderr()
    }
}

impl Drop for Harness {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{InputSpec, OutputSpec};
    use crate::model::{Automaton, Kind};

    fn events() -> EventTable {
        let mut a = Automaton::new("M", Kind::Plant);
        a.add_event("go", true).unwrap();
        a.add_event("done", false).unwrap();
        EventTable::build([&a]).unwrap()
    }

    fn board() -> BoardSpec {
        BoardSpec {
            name: "t".into(),
            sampling: SamplingSpec::Timer,
            sample_period_us: Some(500),
            inputs: vec![InputSpec {
                event: "done".into(),
                pin: 3,
                edge: "rising".into(),
                pull: "down".into(),
            }],
            outputs: vec![OutputSpec {
                event: "go".into(),
                pin: 5,
                action: "pulse".into(),
                pulse_ms: Some(20),
            }],
            internal: vec![],
        }
    }

    #[test]
    fn pin_map_names_events_by_their_firmware_ids() {
        let map: serde_json::Value = serde_json::from_str(&pin_map(&board(), &events()).unwrap()).unwrap();
        assert_eq!(map["sampling"], "timer");
        assert_eq!(map["sample_period_us"], 500);
        assert_eq!(
            map["inputs"][0],
            json!({"event": 1, "name": "done", "pin": 3, "edge": "rising", "pull": "down"})
        );
        assert_eq!(
            map["outputs"][0],
            json!({"event": 0, "name": "go", "pin": 5, "action": "pulse", "pulse_ms": 20})
        );
    }

    #[test]
    fn pin_map_refuses_an_event_no_pin_carries() {
        let no_output = BoardSpec { outputs: vec![], ..board() };
        assert_eq!(
            pin_map(&no_output, &events()),
            Err(PinMapError::Unmapped { what: "command", event: "go".into(), pin: "output pin" })
        );
        let mut stranger = board();
        stranger.inputs[0].event = "nope".into();
        assert_eq!(pin_map(&stranger, &events()), Err(PinMapError::UnknownEvent("nope".into())));
        let mut past = board();
        past.outputs[0].pin = 30;
        assert_eq!(pin_map(&past, &events()), Err(PinMapError::NoSuchPin(30)));
    }

    #[test]
    fn missing_node_is_a_clear_error() {
        let config = HarnessConfig {
            node: "/nonexistent/node".into(),
            script: Some(PathBuf::from("main.js")),
            ..HarnessConfig::default()
        };
        let err =
            Harness::start(Path::new("fw.elf"), Path::new("pins.json"), &config).unwrap_err().to_string();
        assert!(err.starts_with("cannot start /nonexistent/node"), "{err}");
    }
}
