//! What the commands that build products share: the memory limit option and progress on stderr.

use std::io::IsTerminal;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use codegen::synth::memory::default_limit;
use codegen::synth::Observer;

/// A `--memory-limit` as given: bytes, or none.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryLimit(pub Option<u64>);

/// `--memory-limit`: a size in bytes with an optional K, M or G suffix (binary), `none` for no limit.
pub fn parse_size(text: &str) -> Result<MemoryLimit, String> {
    if text.eq_ignore_ascii_case("none") {
        return Ok(MemoryLimit(None));
    }
    let (digits, unit) = match text.char_indices().find(|(_, c)| !c.is_ascii_digit()) {
        Some((i, _)) => text.split_at(i),
        None => (text, ""),
    };
    let shift = match unit.to_ascii_uppercase().trim_end_matches(['B', 'I']) {
        "" => 0,
        "K" => 10,
        "M" => 20,
        "G" => 30,
        _ => return Err(format!("'{text}': a size is a number with K, M or G (for example 512M), or none")),
    };
    let n: u64 =
        digits.parse().map_err(|_| format!("'{text}': a size is a number with K, M or G, or none"))?;
    n.checked_mul(1 << shift).map(|b| MemoryLimit(Some(b))).ok_or_else(|| format!("'{text}': too large"))
}

/// The limit a command runs with: the one given, else three quarters of the machine's RAM.
pub fn memory_limit(given: Option<MemoryLimit>) -> Option<u64> {
    given.map_or_else(default_limit, |m| m.0)
}

/// Progress on stderr: a spinner on a terminal, else a line every few seconds (readable in CI logs).
pub fn progress() -> (Arc<dyn Observer>, Option<indicatif::ProgressBar>) {
    if std::io::stderr().is_terminal() {
        let b = indicatif::ProgressBar::new_spinner();
        b.enable_steady_tick(Duration::from_millis(120));
        (Arc::new(Spinner(b.clone())), Some(b))
    } else {
        (Arc::new(Lines { last: Mutex::new(Instant::now()) }), None)
    }
}

/// Spinner on stderr naming the stage and the states built so far.
struct Spinner(indicatif::ProgressBar);

impl Observer for Spinner {
    fn states(&self, what: &str, states: usize) {
        self.0.set_message(format!("{what}: {states} states"));
    }

    fn stage(&self, what: &str) {
        self.0.set_message(what.to_owned());
    }
}

/// A line on stderr at most every [`LINE_EVERY`].
struct Lines {
    last: Mutex<Instant>,
}

/// Time between two progress lines when stderr is not a terminal.
const LINE_EVERY: Duration = Duration::from_secs(5);

impl Lines {
    fn say(&self, line: String) {
        let Ok(mut last) = self.last.lock() else { return };
        if last.elapsed() >= LINE_EVERY {
            *last = Instant::now();
            eprintln!("progress: {line}");
        }
    }
}

impl Observer for Lines {
    fn states(&self, what: &str, states: usize) {
        self.say(format!("{what}: {states} states"));
    }

    fn stage(&self, what: &str) {
        self.say(what.to_owned());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_with_their_units() {
        let bytes = |s| parse_size(s).map(|m| m.0);
        assert_eq!(bytes("512M"), Ok(Some(512 << 20)));
        assert_eq!(bytes("2G"), Ok(Some(2 << 30)));
        assert_eq!(bytes("64KiB"), Ok(Some(64 << 10)));
        assert_eq!(bytes("1000"), Ok(Some(1000)));
        assert_eq!(bytes("none"), Ok(None));
        assert!(parse_size("12X").is_err() && parse_size("M").is_err());
    }
}
