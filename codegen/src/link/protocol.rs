//! The UART protocol between the virtual plant (host) and the firmware: one byte per event, a few
//! control bytes, and a decoder for what the firmware sends.
//!
//! Bytes `0x00..=0xEF` are event ids: host → firmware an uncontrollable event the plant produced,
//! firmware → host a command the firmware fired. Control bytes: [`RESET`], [`STATUS`], [`EXIT`],
//! [`READY`], [`SAFE`], [`HOLD`], [`GO`], [`SYNC`], [`STEP`], [`TABLES`], [`TIME`] (see each; TIME is
//! written by [`time`]). The firmware's side is in `firmware/src/link.rs`.

// The byte values and the STATUS answer's format are the firmware's own (`firmware::link`), so the two
// ends cannot drift apart.
pub use firmware::link::{
    EXIT, GO, HOLD, MAX_EVENT, READY, RESET, SAFE, STATUS, STATUS_BYTES, STEP, SYNC, TABLES, TABLES_BYTES,
    TIME,
};
pub use firmware::runtime::Counters;

/// Most milliseconds one [`TIME`] message carries.
pub const MAX_TIME_MS: u64 = u16::MAX as u64;

/// The [`TIME`] messages that move the target's virtual time on by `ms` milliseconds: one per
/// [`MAX_TIME_MS`] at most (nothing for 0), each `TIME` then Δ as 2 bytes little-endian.
///
/// ```
/// use codegen::link::protocol::{time, TIME};
///
/// assert_eq!(time(2000), [TIME, 0xD0, 0x07]);
/// assert_eq!(time(70_000), [TIME, 0xFF, 0xFF, TIME, 0x71, 0x11]);
/// assert!(time(0).is_empty());
/// ```
pub fn time(ms: u64) -> Vec<u8> {
    let mut out = Vec::new();
    let mut left = ms;
    while left > 0 {
        let d = left.min(MAX_TIME_MS);
        out.push(TIME);
        out.extend((d as u16).to_le_bytes());
        left -= d;
    }
    out
}

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
    /// A complete [`TABLES`] answer: the hex digits of the digest of the tables the firmware runs.
    Tables([u8; TABLES_BYTES]),
    /// A byte the protocol does not define in this direction.
    Unknown(u8),
}

/// Turns the firmware's byte stream into [`Frame`]s, one byte at a time (a STATUS or TABLES answer may
/// arrive split over several reads).
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
    /// An answer under way: its leading byte ([`STATUS`] or [`TABLES`]) and its bytes so far.
    answer: Option<(u8, Vec<u8>)>,
}

impl Decoder {
    /// Feeds one byte; returns a frame when one is complete.
    pub fn push(&mut self, byte: u8) -> Option<Frame> {
        if let Some((lead, buf)) = &mut self.answer {
            buf.push(byte);
            let frame = match *lead {
                STATUS => Frame::Status(Counters::from_status(buf.as_slice().try_into().ok()?)),
                _ => Frame::Tables(buf.as_slice().try_into().ok()?),
            };
            self.answer = None;
            return Some(frame);
        }
        Some(match byte {
            0..=MAX_EVENT => Frame::Command(byte),
            READY => Frame::Ready,
            SAFE => Frame::Safe,
            SYNC => Frame::Sync,
            STATUS => {
                self.answer = Some((STATUS, Vec::with_capacity(STATUS_BYTES)));
                return None;
            }
            TABLES => {
                self.answer = Some((TABLES, Vec::with_capacity(TABLES_BYTES)));
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
    fn tables_answer_split_anywhere_decodes() {
        let mut bytes = vec![TABLES];
        bytes.extend_from_slice(b"0123456789abcde\xf1");
        bytes.extend([STATUS, 0xF1]);
        let mut d = Decoder::default();
        let mut frames = Vec::new();
        for chunk in bytes.chunks(3) {
            frames.extend(chunk.iter().filter_map(|&b| d.push(b)));
        }
        // A digest byte may be any value: one equal to STATUS is the answer's, not a new answer.
        assert_eq!(frames, [Frame::Tables(*b"0123456789abcde\xf1")]);
        assert_eq!(d.push(SAFE), None, "inside the STATUS answer that followed");
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
