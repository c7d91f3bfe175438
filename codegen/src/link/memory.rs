//! An in-memory byte link, for driving a host-compiled firmware runtime (or a test double) in process.

use std::io;
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, Sender};
use std::time::Duration;

use super::ByteLink;

/// One end of an in-memory duplex byte link made by [`pair`].
#[derive(Debug)]
pub struct MemoryLink {
    tx: Sender<Vec<u8>>,
    rx: Receiver<Vec<u8>>,
    pending: Vec<u8>,
}

/// Two connected ends: what one sends the other receives, in order.
///
/// # Examples
///
/// ```
/// use std::time::Duration;
/// use codegen::link::{memory, ByteLink};
///
/// let (mut a, mut b) = memory::pair();
/// a.send(&[1, 2, 3]).unwrap();
/// let mut buf = [0; 8];
/// assert_eq!(b.recv(&mut buf, Duration::from_millis(10)).unwrap(), 3);
/// assert_eq!(b.recv(&mut buf, Duration::from_millis(1)).unwrap(), 0, "nothing more: a timeout");
/// ```
pub fn pair() -> (MemoryLink, MemoryLink) {
    let (a_tx, b_rx) = channel();
    let (b_tx, a_rx) = channel();
    (
        MemoryLink { tx: a_tx, rx: a_rx, pending: Vec::new() },
        MemoryLink { tx: b_tx, rx: b_rx, pending: Vec::new() },
    )
}

impl ByteLink for MemoryLink {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.tx.send(bytes.to_vec()).map_err(|_| io::Error::from(io::ErrorKind::BrokenPipe))
    }

    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        if self.pending.is_empty() {
            match self.rx.recv_timeout(timeout) {
                Ok(bytes) => self.pending = bytes,
                Err(RecvTimeoutError::Timeout) => return Ok(0),
                Err(RecvTimeoutError::Disconnected) => return Err(io::ErrorKind::UnexpectedEof.into()),
            }
        }
        let n = self.pending.len().min(buf.len());
        buf[..n].copy_from_slice(&self.pending[..n]);
        self.pending.drain(..n);
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_reads_keep_order_and_a_dropped_peer_is_eof() {
        let (mut a, mut b) = pair();
        a.send(&[1, 2, 3]).unwrap();
        a.send(&[4]).unwrap();
        let mut buf = [0; 2];
        let mut got = Vec::new();
        while got.len() < 4 {
            let n = b.recv(&mut buf, Duration::from_millis(10)).unwrap();
            got.extend_from_slice(&buf[..n]);
        }
        assert_eq!(got, [1, 2, 3, 4]);
        drop(a);
        assert_eq!(
            b.recv(&mut buf, Duration::from_millis(10)).unwrap_err().kind(),
            io::ErrorKind::UnexpectedEof
        );
    }
}
