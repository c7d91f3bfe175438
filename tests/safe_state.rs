//! The fault policy on the real firmware under QEMU: an uncontrollable event the automata cannot take
//! from where they are. With `on_fault = "continue"` it is counted and the firmware goes on deciding;
//! with `"safe-state"` it answers SAFE, fires nothing more, and leaves with status 1.

use std::time::{Duration, Instant};

use codegen::closed_loop::Options;
use codegen::config::OnFault;
use codegen::link::protocol::{Counters, Decoder, Frame, EXIT, GO, RESET, STATUS, SYNC};
use codegen::link::ByteLink;
use codegen::project::Project;
use codegen::target::qemu::Qemu;
use end_to_end::{example, firmware_image, Scratch};

/// An uncontrollable event of the cell that some automaton holding it cannot take in its initial state.
fn unexpected_at_start(project: &Project) -> u8 {
    let set = &project.set;
    let events = set.events();
    let name = set
        .members()
        .iter()
        .find_map(|m| {
            let a = &m.automaton;
            let initial = a.initial?;
            a.events.iter().enumerate().find_map(|(i, e)| {
                let leaves = a.transitions.iter().any(|t| t.source == initial && t.event.index() == i);
                (!e.controllable && !leaves).then(|| e.name.clone())
            })
        })
        .expect("the cell has an uncontrollable event not possible at the start");
    events.id(&name).unwrap().as_u32() as u8
}

/// Boots the cell built with `on_fault` (on hold), resets it, sends the unexpected event, asks for STATUS,
/// lets it decide until it has nothing left to decide (SYNC: answered once nothing is enabled, or in the
/// safe state) and tells it to leave; returns (frames before the STATUS answer, the counters, frames
/// after it up to the SYNC answer, QEMU's exit code). Each answer is awaited for up to 20 s: QEMU gives
/// it in milliseconds, and the margin is for a loaded machine.
fn run(on_fault: OnFault) -> (Vec<Frame>, Counters, Vec<Frame>, Option<i32>) {
    let mut project = Project::load(&example("cell/cell.toml")).unwrap();
    project.runtime.on_fault = on_fault;
    let scratch = Scratch::new("safe-state");
    let elf = firmware_image(&project, &scratch);
    let (mut qemu, mut link) = Qemu::start(&elf, &Options::default().qemu).unwrap();
    let mut decoder = Decoder::default();
    let mut frames = Vec::new();
    let mut read = |link: &mut dyn ByteLink, frames: &mut Vec<Frame>, until: &dyn Fn(&[Frame]) -> bool| {
        let deadline = Instant::now() + Duration::from_secs(20);
        let mut buf = [0u8; 64];
        while !until(frames) {
            assert!(Instant::now() < deadline, "no answer: {frames:?}");
            let n = link.recv(&mut buf, Duration::from_millis(20)).unwrap();
            frames.extend(buf[..n].iter().filter_map(|&b| decoder.push(b)));
        }
    };
    read(&mut link, &mut frames, &|f| f.contains(&Frame::Ready));
    // Back at the start. It boots on hold: though the cell's first commands are enabled at the start, it
    // fired none before this RESET (so a seeded run repeats exactly).
    link.send(&[RESET]).unwrap();
    read(&mut link, &mut frames, &|f| f.iter().filter(|&&x| x == Frame::Ready).count() == 2);
    assert_eq!(frames, [Frame::Ready, Frame::Ready], "decided before its first GO");
    frames.clear();
    link.send(&[unexpected_at_start(&project), STATUS]).unwrap();
    read(&mut link, &mut frames, &|f| f.iter().any(|x| matches!(x, Frame::Status(_))));
    let at = frames.iter().position(|x| matches!(x, Frame::Status(_))).unwrap();
    let Frame::Status(counters) = frames[at] else { unreachable!() };
    let before = frames[..at].to_vec();
    // What came after the answer, in the same read, is the first of what follows.
    frames.drain(..=at);
    // Let it decide until it is idle: the cell's first commands are enabled at the start.
    link.send(&[SYNC, GO]).unwrap();
    read(&mut link, &mut frames, &|f| f.contains(&Frame::Sync));
    assert_eq!(frames.pop(), Some(Frame::Sync), "nothing after the SYNC answer, before EXIT");
    link.send(&[EXIT]).unwrap();
    let code = qemu.wait(Duration::from_secs(10)).and_then(|s| s.code());
    assert!(!frames.contains(&Frame::Ready), "{frames:?}");
    (before, counters, frames, code)
}

#[test]
fn continue_counts_the_fault_and_goes_on_deciding() {
    let (before, counters, after, code) = run(OnFault::Continue);
    assert_eq!((counters.events_in, counters.unexpected), (1, 1));
    assert!(before.is_empty(), "{before:?}");
    assert!(!after.contains(&Frame::Safe), "{after:?}");
    assert!(after.iter().any(|f| matches!(f, Frame::Command(_))), "no command after the fault: {after:?}");
    assert_eq!(code, Some(0));
}

#[test]
fn safe_state_announces_itself_stops_deciding_and_exits_1() {
    let (before, counters, after, code) = run(OnFault::SafeState);
    assert_eq!((counters.events_in, counters.unexpected), (1, 1));
    // SAFE goes out at the end of the loop's turn that applied the event: before the STATUS answer or
    // after it, as the two bytes arrived together or not.
    let frames: Vec<Frame> = before.into_iter().chain(after).collect();
    assert_eq!(frames, [Frame::Safe], "SAFE once, then nothing fired in the safe state");
    assert_eq!(code, Some(1));
}
