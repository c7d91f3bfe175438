//! Runs a firmware image under `qemu-system-arm` with its UART0 on a Unix socket, and makes sure the
//! emulator never outlives its owner.
//!
//! QEMU is started with `-serial unix:<dir>/uart0.sock,server=on,wait=on` (no port to allocate, so tests
//! run in parallel; the guest waits until the host connects), semihosting on (the firmware exits QEMU
//! with a status and logs to QEMU's stdout) and, by default, `-icount shift=7,sleep=off` (deterministic
//! virtual time that races ahead while the guest sleeps in `wfi`). The child is killed when the [`Qemu`]
//! value is dropped, when its deadline passes, and when the thread that started it dies
//! ([`super::child`]).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

use super::child::{ConnectError, Emulator, CONNECT_WITHIN};
use crate::link::StreamLink;

/// How to start QEMU.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct QemuConfig {
    /// The emulator binary.
    pub program: String,
    /// Machine (`-machine`).
    pub machine: String,
    /// CPU (`-cpu`).
    pub cpu: String,
    /// `-icount shift=N,sleep=off` when set.
    pub icount_shift: Option<u8>,
    /// Hard limit on the emulator's life.
    pub timeout: Duration,
}

impl Default for QemuConfig {
    fn default() -> Self {
        QemuConfig {
            program: "qemu-system-arm".into(),
            machine: "lm3s6965evb".into(),
            cpu: "cortex-m3".into(),
            icount_shift: Some(7),
            timeout: Duration::from_secs(600),
        }
    }
}

/// QEMU could not be started or connected to.
#[derive(Debug, thiserror::Error)]
pub enum QemuError {
    /// Spawning failed (not installed?).
    #[error("cannot start {program}: {source} (run scripts/setup.sh to install it)")]
    Spawn {
        /// The program.
        program: String,
        /// Why.
        source: std::io::Error,
    },
    /// The scratch directory for the socket could not be made.
    #[error("cannot create {}: {source}", path.display())]
    Scratch {
        /// The directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// QEMU exited before its UART socket accepted a connection.
    #[error("qemu exited early ({status}): {stderr}")]
    Exited {
        /// Exit status.
        status: ExitStatus,
        /// What it printed on stderr.
        stderr: String,
    },
    /// The socket did not accept a connection in time.
    #[error("qemu's UART socket {} did not come up: {source}", path.display())]
    Connect {
        /// The socket.
        path: PathBuf,
        /// The last connection error.
        source: std::io::Error,
    },
}

/// A running emulator; see the module documentation.
#[derive(Debug)]
pub struct Qemu {
    process: Emulator,
    dir: PathBuf,
}

impl Qemu {
    /// Boots `kernel` (an ELF) and connects to its UART0.
    pub fn start(kernel: &Path, config: &QemuConfig) -> Result<(Self, StreamLink), QemuError> {
        static COUNTER: AtomicU32 = AtomicU32::new(0);
        let dir = std::env::temp_dir().join(format!(
            "codegen-qemu-{}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir).map_err(|source| QemuError::Scratch { path: dir.clone(), source })?;
        let socket = dir.join("uart0.sock");
        let mut cmd = Command::new(&config.program);
        cmd.args(["-cpu", &config.cpu, "-machine", &config.machine, "-display", "none", "-monitor", "none"])
            .arg("-serial")
            .arg(format!("unix:{},server=on,wait=on", socket.display()))
            .args(["-semihosting-config", "enable=on,target=native"]);
        if let Some(shift) = config.icount_shift {
            cmd.arg("-icount").arg(format!("shift={shift},sleep=off"));
        }
        cmd.arg("-kernel").arg(kernel);
        let process = Emulator::spawn(&mut cmd, config.timeout)
            .map_err(|source| QemuError::Spawn { program: config.program.clone(), source })?;
        let mut qemu = Qemu { process, dir };
        let link = qemu.process.connect(&socket, CONNECT_WITHIN).map_err(|e| match e {
            ConnectError::Exited { status, stderr } => QemuError::Exited { status, stderr },
            ConnectError::Timeout { path, source } => QemuError::Connect { path, source },
        })?;
        Ok((qemu, link))
    }

    /// The exit status, if QEMU has exited.
    pub fn try_status(&self) -> Option<ExitStatus> {
        self.process.try_status()
    }

    /// Waits up to `timeout` for QEMU to exit (after the firmware was told to leave); kills it when the
    /// time is up and returns `None`.
    pub fn wait(&mut self, timeout: Duration) -> Option<ExitStatus> {
        self.process.wait(timeout)
    }

    /// What QEMU printed on stdout so far (semihosting output of the firmware).
    pub fn stdout(&self) -> String {
        self.process.stdout()
    }

    /// What QEMU printed on stderr so far.
    pub fn stderr(&self) -> String {
        self.process.stderr()
    }
}

impl Drop for Qemu {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stand-in for QEMU: a shell script that runs `body` where the wrapper starts the emulator.
    /// (The deadline that kills a hung emulator is tested on the process wrapper, `child.rs`.)
    fn fake_qemu(dir: &Path, body: &str) -> String {
        let path = dir.join("fake-qemu.sh");
        std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
        std::fs::set_permissions(&path, std::os::unix::fs::PermissionsExt::from_mode(0o755)).unwrap();
        path.display().to_string()
    }

    #[test]
    fn missing_emulator_is_a_clear_error() {
        let config = QemuConfig { program: "/nonexistent/qemu".into(), ..QemuConfig::default() };
        let err = Qemu::start(Path::new("fw.elf"), &config).unwrap_err().to_string();
        assert!(err.starts_with("cannot start /nonexistent/qemu"), "{err}");
    }

    #[test]
    fn early_exit_reports_stderr() {
        let scratch = std::env::temp_dir().join(format!("qemu-test-{}-a", std::process::id()));
        std::fs::create_dir_all(&scratch).unwrap();
        let program = fake_qemu(&scratch, "echo 'no such machine' >&2; exit 3");
        let err = Qemu::start(Path::new("fw.elf"), &QemuConfig { program, ..QemuConfig::default() })
            .unwrap_err()
            .to_string();
        assert!(err.contains("no such machine"), "{err}");
        std::fs::remove_dir_all(scratch).unwrap();
    }
}
