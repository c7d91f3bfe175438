//! The memory a synthesis run may take: the process's resident size, read from the kernel as products
//! grow, against a limit — so that a runaway product stops with an error naming it instead of meeting
//! the kernel's out-of-memory killer.
//!
//! The limit holds *before* memory is taken, not after: a product's hash index grows by doubling, and the
//! new index is written whole while the old one is still held, so a look made only now and then let the
//! process overshoot by the index's size (35 % past a 1 GiB limit on three AGV copies). Every walk asks
//! `admit` with the bytes it is about to take — before a new index, and before the predecessor lists
//! of a backward walk are built.

use super::{Config, SynthError};

/// The resident set size of this process in bytes (`/proc/self/statm`), or `None` where the kernel does
/// not tell.
pub fn resident_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * page_size())
}

/// The machine's RAM in bytes (`MemTotal` of `/proc/meminfo`), or `None` where the kernel does not tell.
pub fn total_ram() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// The default limit: three quarters of the machine's RAM (leaving the rest to the system and to
/// whatever else runs), or no limit where the RAM is unknown.
pub fn default_limit() -> Option<u64> {
    total_ram().map(|ram| ram / 4 * 3)
}

/// Stops building `what` (`states` states so far) when the process's resident size plus the `extra`
/// bytes about to be taken would pass the run's memory limit.
pub(crate) fn admit(cfg: &Config, what: &str, states: usize, extra: u64) -> Result<(), SynthError> {
    let Some(limit) = cfg.memory_limit else { return Ok(()) };
    match resident_bytes() {
        Some(resident) if resident.saturating_add(extra) > limit => {
            Err(SynthError::MemoryLimit { what: what.to_owned(), states, resident, limit, extra })
        }
        _ => Ok(()),
    }
}

fn page_size() -> u64 {
    // SAFETY: sysconf reads a constant of the system; it has no preconditions.
    let size = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    u64::try_from(size).ok().filter(|&s| s > 0).unwrap_or(4096)
}

/// `bytes` for people: MiB or GiB with one decimal.
pub fn human(bytes: u64) -> String {
    const MIB: f64 = 1024.0 * 1024.0;
    let mib = bytes as f64 / MIB;
    if mib >= 1024.0 {
        format!("{:.1} GiB", mib / 1024.0)
    } else {
        format!("{mib:.1} MiB")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kernel_tells_this_process_its_size_and_the_machine_its_ram() {
        let rss = resident_bytes().unwrap();
        let ram = total_ram().unwrap();
        assert!(rss > 1 << 20 && rss < ram, "{rss} of {ram}");
        assert_eq!(default_limit(), Some(ram / 4 * 3));
        assert_eq!(human(3 << 29), "1.5 GiB");
        assert_eq!(human(5 << 20), "5.0 MiB");
    }

    #[test]
    fn a_limit_is_held_before_the_bytes_are_taken() {
        let rss = resident_bytes().unwrap();
        let cfg = Config { memory_limit: Some(rss + (64 << 20)), ..Config::default() };
        assert!(admit(&cfg, "x", 1, 1 << 20).is_ok());
        let err = admit(&cfg, "x", 7, 1 << 30).unwrap_err();
        assert!(matches!(err, SynthError::MemoryLimit { states: 7, extra, .. } if extra == 1 << 30), "{err}");
        assert!(admit(&Config::default(), "x", 1, u64::MAX).is_ok(), "no limit");
    }
}
