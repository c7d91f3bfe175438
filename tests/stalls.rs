//! Stalls are judged on what the two sides did, not on the clock, so that a loaded machine can neither
//! make one nor hide one: a loop that is blocked (the plant has nothing to do, plants ‖ supervisors
//! enable no command) is a stall in lock-step and in realtime however long the stall timeout, and a
//! firmware that is only slow to fire an enabled command is none. Over the in-memory link, against a
//! scripted stand-in firmware.

use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use codegen::closed_loop::{attach, Options, SessionConfig};
use codegen::link::memory::{self, MemoryLink};
use codegen::link::protocol::{GO, HOLD, READY, RESET, STATUS, STATUS_BYTES, STEP, SYNC};
use codegen::link::ByteLink;
use codegen::model::{Automaton, Kind};
use codegen::monitor::Report;
use codegen::pack::PackSet;

/// A fuse that blows (uncontrollable `blow`) and is then dead: after one event the loop is blocked.
fn fuse() -> Automaton {
    let mut a = Automaton::new("Fuse", Kind::Plant);
    let whole = a.add_state("whole", true).unwrap();
    let blown = a.add_state("blown", false).unwrap();
    let blow = a.add_event("blow", false).unwrap();
    a.initial = Some(whole);
    a.add_transition(whole, blow, blown);
    a
}

/// A button pressed by the plant (uncontrollable `press`) that only the controller releases
/// (`release`): after a press the loop waits for the firmware.
fn button() -> Automaton {
    let mut a = Automaton::new("Button", Kind::Plant);
    let up = a.add_state("up", true).unwrap();
    let down = a.add_state("down", false).unwrap();
    let press = a.add_event("press", false).unwrap();
    let release = a.add_event("release", true).unwrap();
    a.initial = Some(up);
    a.add_transition(up, press, down);
    a.add_transition(down, release, up);
    a
}

/// A stand-in firmware: takes every event; with `answer` = (trigger, command, delay) it fires `command`
/// `delay` after each `trigger` came in (holding it or not); answers STATUS with its counts, RESET with
/// READY, SYNC and STEP with SYNC once no answer is due. Ends when the host hangs up.
fn stand_in(mut link: MemoryLink, answer: Option<(u8, u8, Duration)>) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let (mut events_in, mut commands_out) = (0u32, 0u32);
        let mut due: Option<Instant> = None;
        let mut sync_asked = false;
        let mut buf = [0u8; 256];
        if link.send(&[READY]).is_err() {
            return;
        }
        loop {
            let Ok(n) = link.recv(&mut buf, Duration::from_millis(5)) else { return };
            let mut out = Vec::new();
            for &b in &buf[..n] {
                match b {
                    RESET => {
                        (events_in, commands_out, due) = (0, 0, None);
                        out.push(READY);
                    }
                    STATUS => {
                        out.push(STATUS);
                        out.extend(events_in.to_le_bytes());
                        out.extend(commands_out.to_le_bytes());
                        out.extend([0u8; STATUS_BYTES - 8]);
                    }
                    SYNC | STEP => sync_asked = true,
                    HOLD | GO => {}
                    event => {
                        events_in += 1;
                        if answer.is_some_and(|(trigger, _, _)| trigger == event) {
                            due = answer.map(|(_, _, delay)| Instant::now() + delay);
                        }
                    }
                }
            }
            if let (Some(at), Some((_, command, _))) = (due, answer) {
                if Instant::now() >= at {
                    out.push(command);
                    commands_out += 1;
                    due = None;
                }
            }
            if sync_asked && due.is_none() {
                sync_asked = false;
                out.push(SYNC);
            }
            if !out.is_empty() && link.send(&out).is_err() {
                return;
            }
        }
    })
}

/// Runs `plant` alone (no supervisor) against the stand-in for `events` events with `session`.
fn run(
    plant: Automaton,
    answer: Option<(&str, &str, Duration)>,
    events: u64,
    session: SessionConfig,
) -> Report {
    let set = PackSet::new(vec![plant], vec![]).unwrap();
    let id = |name: &str| set.events().id(name).unwrap().as_u32() as u8;
    let answer = answer.map(|(trigger, command, delay)| (id(trigger), id(command), delay));
    let (mut host, target) = memory::pair();
    let firmware = stand_in(target, answer);
    let options = Options { events, session, ..Options::default() };
    let report = attach(&mut host, &set, "stand-in", &options, &mut |_| {}).unwrap();
    drop(host);
    firmware.join().unwrap();
    report
}

/// The fuse blows, and nothing can happen any more: every blow but the run's last is followed by a
/// stall and a resynchronisation, in lock-step (a round in which neither side moved) and in realtime
/// (asked, the firmware fired nothing and no command is enabled) — with a stall timeout of an hour,
/// which the run never waits for.
#[test]
fn a_blocked_loop_is_a_stall_in_either_timing_whatever_the_stall_timeout() {
    let hour = Duration::from_secs(3600);
    for session in [SessionConfig::default(), SessionConfig::realtime()] {
        let session = SessionConfig { stall_timeout: hour, ..session };
        let lockstep = session.lockstep;
        let report = run(fuse(), None, 5, session);
        assert_eq!(report.events, 5, "lock-step {lockstep}: {report}");
        assert_eq!((report.stalls, report.resyncs), (4, 4), "lock-step {lockstep}: {report}");
        assert_eq!(report.violations, 0, "lock-step {lockstep}: {report}");
    }
}

/// The button is pressed and the firmware releases it half a second later — five times the silence
/// after which the realtime session asks the firmware where it is (0.1 s): the command is enabled, so
/// the firmware is slow, not blocked, and no stall is counted. Load can only make the firmware slower
/// still; the margin is the stall timeout (10 s) against the half second.
#[test]
fn a_slow_firmware_with_a_command_to_fire_is_no_stall() {
    let slow = Some(("press", "release", Duration::from_millis(500)));
    let report = run(button(), slow, 6, SessionConfig::realtime());
    assert_eq!((report.uncontrollable, report.commands), (3, 3), "{report}");
    assert_eq!((report.stalls, report.resyncs, report.violations), (0, 0, 0), "{report}");
}
