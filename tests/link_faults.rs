//! What a misbehaving firmware does to a run, over the in-memory link: a scripted stand-in that speaks
//! the protocol (READY, STATUS answers, RESET) but restarts in mid-run, or fires what no supervisor
//! allows just before the run's last STATUS answer. Neither may pass unnoticed.

use std::thread::JoinHandle;
use std::time::Duration;

use codegen::closed_loop::{attach, Options};
use codegen::link::memory::{self, MemoryLink};
use codegen::link::protocol::{GO, HOLD, READY, RESET, STATUS, STATUS_BYTES, STEP, SYNC};
use codegen::link::ByteLink;
use codegen::monitor::Report;
use codegen::pack::PackSet;
use end_to_end::ticker;

/// What the stand-in does wrong.
#[derive(Clone, Copy)]
enum Fault {
    /// Sends READY, unasked, after this many events.
    RebootAfter(u64),
    /// Sends `tick` as a command (an uncontrollable event: never a command) right before every STATUS
    /// answer.
    TickBeforeStatus,
}

/// A stand-in firmware for the ticker: takes every event, never decides on its own, answers STATUS
/// with its events count, RESET with READY, SYNC and STEP with SYNC (it is always idle) — and commits
/// `fault`. Ends when the host hangs up.
fn stand_in(mut link: MemoryLink, tick: u8, fault: Fault) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let mut events_in = 0u32;
        let mut rebooted = false;
        let mut buf = [0u8; 256];
        if link.send(&[READY]).is_err() {
            return;
        }
        loop {
            let Ok(n) = link.recv(&mut buf, Duration::from_millis(5)) else { return };
            for &b in &buf[..n] {
                let reply: Vec<u8> = match b {
                    RESET => {
                        events_in = 0;
                        vec![READY]
                    }
                    STATUS => {
                        let mut answer = Vec::with_capacity(STATUS_BYTES + 2);
                        if matches!(fault, Fault::TickBeforeStatus) {
                            answer.push(tick);
                        }
                        answer.push(STATUS);
                        answer.extend(events_in.to_le_bytes());
                        let commands = u32::from(matches!(fault, Fault::TickBeforeStatus));
                        answer.extend(commands.to_le_bytes());
                        answer.extend([0u8; STATUS_BYTES - 8]);
                        answer
                    }
                    SYNC | STEP => vec![SYNC],
                    HOLD | GO => vec![],
                    _ => {
                        events_in += 1;
                        match fault {
                            Fault::RebootAfter(k) if !rebooted && u64::from(events_in) == k => {
                                rebooted = true;
                                events_in = 0;
                                vec![READY]
                            }
                            _ => vec![],
                        }
                    }
                };
                if !reply.is_empty() && link.send(&reply).is_err() {
                    return;
                }
            }
        }
    })
}

fn run(fault: Fault) -> Report {
    let set = PackSet::new(vec![ticker()], vec![]).unwrap();
    let tick = set.events().id("tick").unwrap().as_u32() as u8;
    let (mut host, target) = memory::pair();
    let firmware = stand_in(target, tick, fault);
    let options = Options { events: 200, ..Options::default() };
    let report = attach(&mut host, &set, "ticker", &options, &mut |_| {}).unwrap();
    drop(host);
    firmware.join().unwrap();
    report
}

#[test]
fn a_firmware_that_restarts_in_mid_run_is_counted_and_resynchronised() {
    let report = run(Fault::RebootAfter(50));
    assert_eq!((report.reboots, report.resyncs), (1, 1), "{report}");
    assert_eq!(report.violations, 0, "{report}");
}

#[test]
fn a_wrong_command_just_before_the_last_status_answer_is_judged() {
    let report = run(Fault::TickBeforeStatus);
    assert_eq!(report.violations, 1, "{report}");
    assert!(report.findings.iter().any(|f| f.contains("is uncontrollable")), "{report}");
    assert_eq!(report.reboots, 0, "{report}");
}
