//! The memory a synthesis run may take: the process's resident size, read from the kernel as products
//! grow, against a limit — so that a runaway product stops with an error naming it instead of meeting
//! the kernel's out-of-memory killer.

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
}
