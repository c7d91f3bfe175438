//! An exclusive lock on a file (`flock`), held until dropped: what serialises the firmware builds that
//! share one target directory and the unpacking of the RP2040 harness's packages, across processes.

use std::fs::File;
use std::os::fd::AsRawFd;
use std::path::Path;

/// An exclusive `flock` on a file, released when dropped.
#[derive(Debug)]
pub struct FileLock(File);

impl FileLock {
    /// Creates `path` if needed and waits until this process holds it exclusively.
    pub fn exclusive(path: &Path) -> std::io::Result<Self> {
        let file = File::create(path)?;
        // SAFETY: `flock` only reads the descriptor, which `file` keeps open for the guard's lifetime.
        if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) } != 0 {
            return Err(std::io::Error::last_os_error());
        }
        Ok(FileLock(file))
    }
}

impl Drop for FileLock {
    fn drop(&mut self) {
        // SAFETY: as in `exclusive`; unlocking a descriptor we locked.
        unsafe {
            libc::flock(self.0.as_raw_fd(), libc::LOCK_UN);
        }
    }
}
