//! The UART protocol between the virtual plant (host) and the firmware: one byte per event, a few
//! control bytes, and a decoder for what the firmware sends.
//!
//! Bytes `0x00..=0xEF` are event ids: host → firmware an uncontrollable event the plant produced,
//! firmware → host a command the firmware fired. Control bytes: [`RESET`], [`STATUS`], [`EXIT`],
//! [`READY`], [`SAFE`], [`HOLD`], [`GO`], [`SYNC`], [`STEP`] (see each). The firmware's side is in `firmware/src/link.rs`.

// The byte values and the STATUS answer's format are the firmware's own (`firmware::link`), so the two
// ends cannot drift apart.
pub use firmware::link::{EXIT, GO, HOLD, MAX_EVENT, READY, RESET, SAFE, STATUS, STATUS_BYTES, STEP, SYNC};
pub use firmware::runtime::Counters;

/// One message from the firmware.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// A command (event id) the firmware fired.
    Command(u8),
    /// [`READY`].
    Ready,
    /// [`SAFE`].
    Safe,
    /// [`SYNC`]: the firmware is idle (the answer to a SYNC request).
    Sync,
    /// A complete [`STATUS`] answer: the firmware's counters since its last reset.
    Status(Counters),
    /// A byte the protocol does not define in this direction.
    Unknown(u8),
}

/// Turns the firmware's byte stream into [`Frame`]s, one byte at a time (a STATUS answer may arrive
/// split over several reads).
///
/// # Examples
///
/// ```
/// use codegen::link::protocol::{Decoder, Frame, READY};
///
/// let mut d = Decoder::default();
/// assert_eq!(d.push(READY), Some(Frame::Ready));
/// assert_eq!(d.push(3), Some(Frame::Command(3)));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Decoder {
    status: Option<Vec<u8>>,
}

impl Decoder {
    /// Feeds one byte; returns a frame when one is complete.
    pub fn push(&mut self, byte: u8) -> Option<Frame> {
        if let Some(buf) = &mut self.status {
            buf.push(byte);
            let answer: &[u8; STATUS_BYTES] = buf.as_slice().try_into().ok()?;
            let counters = Counters::from_status(answer);
            self.status = None;
            return Some(Frame::Status(counters));
        }
        Some(match byte {
            0..=MAX_EVENT => Frame::Command(byte),
            READY => Frame::Ready,
            SAFE => Frame::Safe,
            SYNC => Frame::Sync,
            STATUS => {
                self.status = Some(Vec::with_capacity(STATUS_BYTES));
                return None;
            }
            other => Frame::Unknown(other),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_answer_split_anywhere_decodes() {
        let mut bytes = vec![7, STATUS];
        for v in [1u32, 2, 3, 4, 5, 0x0102_0304] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes.push(SAFE);
        let mut d = Decoder::default();
        let frames: Vec<_> = bytes.iter().filter_map(|&b| d.push(b)).collect();
        let expected = Counters {
            events_in: 1,
            commands_out: 2,
            unexpected: 3,
            overflows: 4,
            guard_redecisions: 5,
            unknown_bytes: 0x0102_0304,
        };
        assert_eq!(frames, [Frame::Command(7), Frame::Status(expected), Frame::Safe]);
    }

    #[test]
    fn reserved_bytes_are_unknown_in_this_direction() {
        let mut d = Decoder::default();
        assert_eq!(d.push(HOLD), Some(Frame::Unknown(HOLD)));
        assert_eq!(d.push(SYNC), Some(Frame::Sync));
        assert_eq!(d.push(0xFF), Some(Frame::Unknown(0xFF)));
        assert_eq!(d.push(MAX_EVENT), Some(Frame::Command(MAX_EVENT)));
    }
}
