//! An emulator process run for the length of a job (QEMU, the RP2040 harness), and the Unix socket the
//! host talks to it on, made sure never to outlive its owner: the child is killed when the [`Emulator`]
//! value is dropped, when its deadline passes (a watchdog thread), and — on Linux — when the thread that
//! started it dies (`PR_SET_PDEATHSIG`). Its stdout and stderr are collected for the owner's messages.

use std::io::Read;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use crate::link::StreamLink;

/// How long an emulator has to open its socket: it does so in well under a second; the rest is margin
/// for a loaded machine (an emulator that exits instead is seen at once).
pub const CONNECT_WITHIN: Duration = Duration::from_secs(60);

/// The emulator's socket did not come up.
#[derive(Debug)]
pub enum ConnectError {
    /// It exited before accepting a connection.
    Exited {
        /// Exit status.
        status: ExitStatus,
        /// What it printed on stderr.
        stderr: String,
    },
    /// The socket did not accept a connection in time.
    Timeout {
        /// The socket.
        path: PathBuf,
        /// The last connection error.
        source: std::io::Error,
    },
}

/// A running emulator process; see the module documentation.
#[derive(Debug)]
pub struct Emulator {
    child: Arc<Mutex<Child>>,
    /// Set (and notified) when the owner is done, so the watchdog stops.
    done: Arc<(Mutex<bool>, Condvar)>,
    stdout: Arc<Mutex<Vec<u8>>>,
    stderr: Arc<Mutex<Vec<u8>>>,
    /// The thread reading stderr, joined when the child exits so its message is complete.
    stderr_reader: Option<std::thread::JoinHandle<()>>,
}

impl Emulator {
    /// Spawns `cmd` (stdin closed, stdout and stderr collected), to be killed after `timeout` at the latest.
    pub fn spawn(cmd: &mut Command, timeout: Duration) -> std::io::Result<Self> {
        cmd.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped());
        // SAFETY: the closure runs in the forked child before exec and only calls `prctl`, which is
        // async-signal-safe; it touches no memory of the parent.
        unsafe {
            cmd.pre_exec(|| {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let mut child = cmd.spawn()?;
        let (stdout, _) = collect(child.stdout.take());
        let (stderr, stderr_reader) = collect(child.stderr.take());
        let child = Arc::new(Mutex::new(child));
        let done = Arc::new((Mutex::new(false), Condvar::new()));
        watchdog(Arc::clone(&child), Arc::clone(&done), timeout);
        Ok(Emulator { child, done, stdout, stderr, stderr_reader })
    }

    /// Connects to the Unix socket `socket` the child serves, retrying for up to `within`.
    pub fn connect(&mut self, socket: &Path, within: Duration) -> Result<StreamLink, ConnectError> {
        let deadline = Instant::now() + within;
        loop {
            match StreamLink::unix(socket) {
                Ok(link) => return Ok(link),
                Err(source) => {
                    if let Some(status) = self.try_status() {
                        self.join_stderr();
                        return Err(ConnectError::Exited { status, stderr: self.stderr() });
                    }
                    if Instant::now() >= deadline {
                        return Err(ConnectError::Timeout { path: socket.to_owned(), source });
                    }
                    std::thread::sleep(Duration::from_millis(10));
                }
            }
        }
    }

    fn join_stderr(&mut self) {
        if let Some(reader) = self.stderr_reader.take() {
            let _ = reader.join();
        }
    }

    /// The exit status, if the child has exited.
    pub fn try_status(&self) -> Option<ExitStatus> {
        self.child.lock().ok()?.try_wait().ok().flatten()
    }

    /// Waits up to `timeout` for the child to exit; kills it when the time is up and returns `None`.
    pub fn wait(&mut self, timeout: Duration) -> Option<ExitStatus> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(status) = self.try_status() {
                self.join_stderr();
                return Some(status);
            }
            if Instant::now() >= deadline {
                self.kill();
                return None;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// What the child printed on stdout so far.
    pub fn stdout(&self) -> String {
        self.stdout.lock().map(|b| String::from_utf8_lossy(&b).into_owned()).unwrap_or_default()
    }

    /// What the child printed on stderr so far.
    pub fn stderr(&self) -> String {
        self.stderr.lock().map(|b| String::from_utf8_lossy(&b).into_owned()).unwrap_or_default()
    }

    fn kill(&self) {
        if let Ok(mut child) = self.child.lock() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        self.kill();
        let (flag, cvar) = &*self.done;
        if let Ok(mut done) = flag.lock() {
            *done = true;
            cvar.notify_all();
        }
    }
}

/// Reads a child's pipe to the end in a thread, into a shared buffer.
fn collect(
    pipe: Option<impl Read + Send + 'static>,
) -> (Arc<Mutex<Vec<u8>>>, Option<std::thread::JoinHandle<()>>) {
    let buf = Arc::new(Mutex::new(Vec::new()));
    let mut reader = None;
    if let Some(mut pipe) = pipe {
        let out = Arc::clone(&buf);
        reader = Some(std::thread::spawn(move || {
            let mut chunk = [0u8; 4096];
            while let Ok(n) = pipe.read(&mut chunk) {
                if n == 0 {
                    break;
                }
                if let Ok(mut b) = out.lock() {
                    b.extend_from_slice(&chunk[..n]);
                }
            }
        }));
    }
    (buf, reader)
}

/// Kills `child` after `timeout` unless `done` is set first.
fn watchdog(child: Arc<Mutex<Child>>, done: Arc<(Mutex<bool>, Condvar)>, timeout: Duration) {
    std::thread::spawn(move || {
        let (flag, cvar) = &*done;
        let Ok(guard) = flag.lock() else { return };
        let Ok((guard, _)) = cvar.wait_timeout_while(guard, timeout, |d| !*d) else { return };
        if !*guard {
            if let Ok(mut c) = child.lock() {
                let _ = c.kill();
                let _ = c.wait();
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Judged on order, not on the clock's margins, so that load cannot fail it: the process (one
    /// that would live ten minutes) is killed no sooner than its deadline after it started, and seen
    /// gone within a minute (the margin for a loaded machine; the kill takes milliseconds). A wait
    /// that ran out would have killed it itself and returned `None`.
    #[test]
    fn the_watchdog_kills_a_hung_emulator_at_its_deadline() {
        use std::os::unix::process::ExitStatusExt;
        let deadline = Duration::from_secs(1);
        let started = Instant::now();
        let mut hung = Emulator::spawn(Command::new("sleep").arg("600"), deadline).unwrap();
        let status = hung.wait(Duration::from_secs(60)).expect("killed by the watchdog, not by the wait");
        assert!(started.elapsed() >= deadline, "killed before its deadline: {:?}", started.elapsed());
        assert_eq!(status.signal(), Some(libc::SIGKILL), "{status}");
    }
}
