//! Timeouts (`[[timers]]`) in the PLC program: the cylinder's end-switch timer (2 s) as a `TON`, the
//! emitted ST run scan by scan under the interpreter (10 ms a scan). The timeout must fall due no earlier
//! than 2 s after the `extend` that started it and at most two scans later, never when the end switch
//! answers in time; a program whose timer was shortened or lengthened in its text fails the same judge.

use codegen::emit::Provenance;
use codegen::interpreter::Plc;
use codegen::model::EventId;
use codegen::plc::{generate, PlcOptions};
use codegen::project::Project;
use end_to_end::example;

/// The timer's delay in the manifest, and the scan cycle.
const MS: u64 = 2000;
const CYCLE_MS: u64 = 10;

/// The cylinder's event-based program (ST) and its event names by id.
fn cylinder() -> (String, Vec<String>) {
    let p = Project::load(&example("cylinder/cylinder.toml")).unwrap();
    let opts = PlcOptions::new(&p.name, &p.runtime, p.plc.as_ref(), None).unwrap();
    let opts = PlcOptions { timers: p.timers.clone(), ..opts };
    let out = generate(&p.set, &opts, &Provenance::default()).unwrap();
    let events = p.set.events();
    let names = events.ids().map(|e| events.name(e).to_owned()).collect();
    (out.files[0].1.clone(), names)
}

/// Scans `text` for `until_ms`, the end switch rising `end_after_ms` after the first `extend` (`None`:
/// never), the operator's reset button never pressed; returns each command fired and each timeout
/// taken with the ms of its scan.
fn scans(text: &str, names: &[String], end_after_ms: Option<u64>, until_ms: u64) -> Vec<(u64, String)> {
    let mut plc = Plc::load(text).unwrap();
    plc.set_cycle_ms(CYCLE_MS as u32);
    let mut seen = Vec::new();
    let mut extended = None;
    for scan in 0..until_ms / CYCLE_MS {
        let now = scan * CYCLE_MS;
        if let (Some(t0), Some(d)) = (extended, end_after_ms) {
            plc.set_bool("end_switch", now >= t0 + d).unwrap();
        }
        plc.scan().unwrap();
        // A scan takes its uncontrollable event before it chooses a command.
        if plc.get_bool("sct.ev_ext_timeout").unwrap() {
            seen.push((now, "ext_timeout".to_owned()));
        }
        let fired = plc.get_int("sct.fired").unwrap();
        if let Ok(id) = u32::try_from(fired) {
            let name = names[EventId::from_u32(id).index()].clone();
            if name == "extend" && extended.is_none() {
                extended = Some(now);
            }
            seen.push((now, name));
        }
    }
    seen
}

/// The judge of the timed events: with the end switch silent, exactly one timeout, `ms` or at most two
/// scans more after the `extend`; with the end switch in time, none.
fn judge(seen: &[(u64, String)], end_in_time: bool) -> Result<(), String> {
    let at = |name: &str| seen.iter().filter(|(_, n)| n == name).map(|(t, _)| *t).collect::<Vec<_>>();
    let (extend, timeout) = (at("extend"), at("ext_timeout"));
    let Some(&t0) = extend.first() else { return Err("no extend".into()) };
    match (end_in_time, timeout.as_slice()) {
        (true, []) => Ok(()),
        (true, t) => Err(format!("a timeout at {t:?} ms though the end switch answered in time")),
        (false, [t]) if *t < t0 + MS => Err(format!("timeout {} ms after the extend: early", t - t0)),
        (false, [t]) if *t > t0 + MS + 2 * CYCLE_MS => {
            Err(format!("timeout {} ms after the extend: late", t - t0))
        }
        (false, [_]) => Ok(()),
        (false, t) => Err(format!("{} timeouts (at {t:?} ms), one expected", t.len())),
    }
}

#[test]
fn the_cylinders_program_raises_its_timeout_after_2_s_and_only_without_the_end_switch() {
    let (text, names) = cylinder();
    assert!(text.contains("T#2000ms"), "the timer's TON:\n{text}");
    let stuck = scans(&text, &names, None, 3000);
    judge(&stuck, false).unwrap();
    let after: Vec<&str> = stuck.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(after, ["extend", "ext_timeout", "alarm_on"], "the fault path: the alarm after the timeout");
    let in_time = scans(&text, &names, Some(1500), 5000);
    judge(&in_time, true).unwrap();
    assert!(in_time.iter().any(|(_, n)| n == "retract"), "{in_time:?}");
}

#[test]
fn a_timer_shortened_or_lengthened_in_the_program_is_caught() {
    let (text, names) = cylinder();
    for wrong in ["T#1500ms", "T#2100ms"] {
        let mutant = text.replace("T#2000ms", wrong);
        let seen = scans(&mutant, &names, None, 3000);
        assert!(judge(&seen, false).is_err(), "{wrong} survived: {seen:?}");
    }
}
