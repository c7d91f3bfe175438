//! Bursts under QEMU: the plant holds the firmware, sends several events back to back, and lets it go.
//! Up to the input buffer's capacity nothing is lost; beyond it nothing is lost silently either — under
//! QEMU the firmware masks its receive interrupt while the buffer is full, so the emulated UART holds the
//! rest back (backpressure), and every event arrives. (The overflow path itself, for a line that cannot
//! be held back, is exercised against the host-compiled runtime in `loopback.rs`.) A burst that fills the
//! buffer exactly leaves GO alone in the UART until the loop drains the buffer; the firmware must still
//! decide after it.

use codegen::closed_loop::{parts, Options, Session, SessionConfig};
use codegen::config::RuntimeConfig;
use codegen::link::{ByteLink, StreamLink};
use codegen::monitor::Monitor;
use codegen::plant::VirtualPlant;
use codegen::project::Project;
use codegen::target::qemu::Qemu;
use end_to_end::{firmware_image, ticker, Scratch};
use std::time::{Duration, Instant};

/// Input buffer capacity of the test firmware; odd, so that a burst of that many ticks leaves the
/// counter where only the firmware's `ack` can follow.
const CAPACITY: usize = 7;

/// The ticker's firmware with an input buffer of [`CAPACITY`], booted under QEMU, with the plant and the
/// monitor a session drives it with.
struct Ticker {
    project: Project,
    qemu: Qemu,
    link: StreamLink,
    plant: VirtualPlant,
    monitor: Monitor,
    /// Holds the image until the test ends.
    _scratch: Scratch,
}

impl Ticker {
    fn boot(tag: &str) -> Ticker {
        let runtime = RuntimeConfig { input_buffer: CAPACITY, ..RuntimeConfig::default() };
        let project = Project::new("ticker", vec![ticker()], vec![], runtime).unwrap();
        let scratch = Scratch::new(tag);
        let elf = firmware_image(&project, &scratch);
        let options = Options::default();
        let (qemu, link) = Qemu::start(&elf, &options.qemu).unwrap();
        let (plant, monitor) = parts(&project.set, &options).unwrap();
        Ticker { project, qemu, link, plant, monitor, _scratch: scratch }
    }

    /// A session on the firmware, synchronised, in the plant's own timing (no lock-step rounds): a
    /// burst is the subject, and what the firmware sends after it is its answer alone, no SYNC.
    fn session(&mut self) -> Session<'_, StreamLink> {
        let mut session =
            Session::new(&mut self.link, &mut self.plant, &mut self.monitor, SessionConfig::realtime());
        session.sync(false).unwrap();
        session
    }
}

#[test]
fn bursts_between_two_decisions_lose_nothing() {
    let mut ticker = Ticker::boot("burst");
    let mut session = ticker.session();
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
    assert!(ticker.qemu.wait(Duration::from_millis(10)).is_none(), "still running until killed");
}

#[test]
fn a_burst_that_fills_the_buffer_is_decided_on_when_go_comes_last() {
    let mut ticker = Ticker::boot("burst-go");
    let ack = ticker.project.set.events().id("ack").unwrap().as_u32() as u8;
    let mut session = ticker.session();
    // HOLD, 7 ticks, GO in one write: the receive interrupt fills the buffer with the ticks and masks
    // itself, GO still in the UART; the loop takes the ticks on hold, and GO arrives once it unmasks.
    assert_eq!(session.burst(CAPACITY).unwrap(), CAPACITY);
    drop(session);
    // The counter is odd: the firmware acks with nothing more from the host (a loop that slept through
    // GO would wait for the next byte, which the host, waiting for the ack, never sends). The ack comes
    // within milliseconds; the 30 s of the session's answer timeout are margin for a loaded machine.
    let deadline = Instant::now() + SessionConfig::default().answer_timeout;
    let mut got = Vec::new();
    while got.is_empty() && Instant::now() < deadline {
        let mut buf = [0u8; 16];
        let n = ticker.link.recv(&mut buf, Duration::from_millis(50)).unwrap();
        got.extend_from_slice(&buf[..n]);
    }
    assert_eq!(got, [ack], "the firmware's answer to the released burst");
    assert!(ticker.qemu.wait(Duration::from_millis(10)).is_none(), "still running until killed");
}
