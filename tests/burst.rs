//! Bursts under QEMU: the plant holds the firmware, sends several events back to back, and lets it go.
//! Up to the input buffer's capacity nothing is lost; beyond it nothing is lost silently either — under
//! QEMU the firmware masks its receive interrupt while the buffer is full, so the emulated UART holds the
//! rest back (backpressure), and every event arrives. (The overflow path itself, for a line that cannot
//! be held back, is exercised against the host-compiled runtime in `loopback.rs`.)

use codegen::closed_loop::{parts, Options, Session, SessionConfig};
use codegen::config::RuntimeConfig;
use codegen::project::Project;
use codegen::target::qemu::Qemu;
use end_to_end::{firmware_image, ticker, Scratch};

/// Input buffer capacity of the test firmware.
const CAPACITY: usize = 8;

#[test]
fn bursts_between_two_decisions_lose_nothing() {
    let runtime = RuntimeConfig { input_buffer: CAPACITY, ..RuntimeConfig::default() };
    let project = Project::new("ticker", vec![ticker()], vec![], runtime).unwrap();
    let scratch = Scratch::new("burst");
    let elf = firmware_image(&project, &scratch);
    let options = Options::default();
    let (mut qemu, mut link) = Qemu::start(&elf, &options.qemu).unwrap();
    let (mut plant, mut monitor) = parts(&project.set, &options).unwrap();
    let mut session = Session::new(&mut link, &mut plant, &mut monitor, SessionConfig::default());
    session.sync(false).unwrap();
    for n in [1, CAPACITY, 3 * CAPACITY, 200] {
        let before = session.hold_and_collect(false).unwrap();
        assert_eq!(session.burst(n).unwrap(), n);
        let after = session.hold_and_collect(false).unwrap();
        let taken = after.events_in - before.events_in;
        let overflowed = after.overflows - before.overflows;
        // Backpressure: a burst of any length arrives whole, none of it overflows — the firmware masks its
        // receive interrupt while the buffer is full and the emulated UART holds the rest back.
        assert_eq!((taken, overflowed), (n as u64, 0), "burst of {n}: taken, overflowed");
    }
    drop(session);
    assert!(qemu.wait(std::time::Duration::from_millis(10)).is_none(), "still running until killed");
}
