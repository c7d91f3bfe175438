//! The timer table of the emitted tables (`TIMERS`): per `[[timers]]` entry of the manifest, the ids of
//! the events that start and stop it, its timeout's id and its delay, as the firmware's
//! [`firmware::timer::TimerSpec`]s. The event loop runs them (`firmware::event_loop::EventLoop::with_timers`):
//! time from the link's TIME under a host, from a hardware millisecond tick on a board.
//!
//! Every tables file ends with it, a project without timers with an empty one (`[…; 0]`), so every
//! application compiles against the same names. It lies outside the table image: the image's bytes are
//! those of the set alone. Its `DIGEST` — what the firmware answers the link's TABLES with — covers the
//! timers too when there are any ([`seal`]), so a firmware whose timer runs another delay is refused as
//! one on other tables is; without timers it is the image's, as before timers.

use std::fmt::Write as _;

use super::EmitError;
use crate::manifest::TimerSpec;

/// The `TIMERS` item for `timers` over the events `names` (by global id), with a blank line before it.
/// Refused: an event of a timer that `names` does not hold (the manifest's check refuses it first).
///
/// ```
/// use codegen::manifest::TimerSpec;
/// let t = TimerSpec { name: "T".into(), start: vec!["go".into()], stop: vec![], timeout: None, ms: 5 };
/// let names = ["go".to_string(), "T_timeout".to_string()];
/// let text = codegen::emit::timers::rust(&[t], &names).unwrap();
/// assert!(text.contains("pub static TIMERS: [firmware::timer::TimerSpec; 1] = ["));
/// assert!(text.contains("firmware::timer::TimerSpec { start: &[0], stop: &[], timeout: 1, ms: 5 }, // T"));
/// assert!(codegen::emit::timers::rust(&[], &names).unwrap().contains("TimerSpec; 0] = [];"));
/// ```
pub fn rust(timers: &[TimerSpec], names: &[String]) -> Result<String, EmitError> {
    let id = |timer: &TimerSpec, event: &str| {
        names
            .iter()
            .position(|n| n == event)
            .ok_or_else(|| EmitError::TimerEvent { timer: timer.name.clone(), event: event.to_owned() })
    };
    let ids = |timer: &TimerSpec, events: &[String]| -> Result<String, EmitError> {
        let ids: Result<Vec<String>, EmitError> =
            events.iter().map(|e| id(timer, e).map(|i| i.to_string())).collect();
        Ok(ids?.join(", "))
    };
    let mut out = String::new();
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "/// The manifest's timers (`[[timers]]`): start and stop event ids, the timeout's id, its delay in \
         ms (`firmware::timer`)."
    );
    if timers.is_empty() {
        let _ = writeln!(out, "pub static TIMERS: [firmware::timer::TimerSpec; 0] = [];");
        return Ok(out);
    }
    let _ = writeln!(out, "pub static TIMERS: [firmware::timer::TimerSpec; {}] = [", timers.len());
    for t in timers {
        let _ = writeln!(
            out,
            "    firmware::timer::TimerSpec {{ start: &[{}], stop: &[{}], timeout: {}, ms: {} }}, // {}",
            ids(t, &t.start)?,
            ids(t, &t.stop)?,
            id(t, &t.timeout_event())?,
            t.ms,
            t.name
        );
    }
    let _ = writeln!(out, "];");
    Ok(out)
}

/// The tables file `text` (ending with its [`rust`] timer table) with every `DIGEST` covering the timer
/// table as well, when it holds a timer ([`firmware::build::image::tables_digest`]: the build script's
/// check, `firmware::build::image::check_source`, proves the same digests); unchanged without timers.
pub fn seal(text: String) -> String {
    let Some(timers) = firmware::build::image::timers_item(&text) else { return text };
    let mut out = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let item = line.trim_start();
        let digest =
            item.strip_prefix(super::DIGEST_ITEM).and_then(|rest| rest.trim_end().strip_suffix("\";"));
        match digest {
            Some(digest) => {
                let indent = &line[..line.len() - item.len()];
                let sealed = firmware::build::image::tables_digest(digest, Some(timers));
                let end = if line.ends_with('\n') { "\n" } else { "" };
                out.push_str(&format!("{indent}{}{sealed}\";{end}", super::DIGEST_ITEM));
            }
            None => out.push_str(line),
        }
    }
    out
}
