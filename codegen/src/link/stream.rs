//! Byte links over operating-system streams: Unix sockets (QEMU's UART), TCP, and serial ports (boards).

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::os::unix::net::UnixStream;
use std::time::Duration;

use super::ByteLink;

/// A stream that can wait a bounded time for input.
trait TimedRead: Read + Write {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()>;
}

impl TimedRead for UnixStream {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.set_read_timeout(Some(timeout.max(Duration::from_micros(1))))
    }
}

impl TimedRead for TcpStream {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.set_read_timeout(Some(timeout.max(Duration::from_micros(1))))
    }
}

impl TimedRead for Box<dyn serialport::SerialPort> {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        serialport::SerialPort::set_timeout(self.as_mut(), timeout).map_err(io::Error::from)
    }
}

/// A [`ByteLink`] over a Unix socket, a TCP connection or a serial port.
pub struct StreamLink {
    inner: Box<dyn TimedRead + Send>,
    /// Last timeout set, to skip the system call when it does not change.
    timeout: Option<Duration>,
}

impl std::fmt::Debug for StreamLink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StreamLink").field("timeout", &self.timeout).finish_non_exhaustive()
    }
}

impl StreamLink {
    /// Connects to the Unix socket at `path` (QEMU's `-serial unix:…,server=on`).
    pub fn unix(path: &std::path::Path) -> io::Result<Self> {
        Ok(Self::wrap(UnixStream::connect(path)?))
    }

    /// Connects to `addr` (`host:port`) over TCP, with Nagle's delay off: the protocol is one byte per event.
    pub fn tcp(addr: &str) -> io::Result<Self> {
        let stream = TcpStream::connect(addr)?;
        stream.set_nodelay(true)?;
        Ok(Self::wrap(stream))
    }

    /// Opens the serial port `device` at `baud` baud, 8N1.
    pub fn serial(device: &str, baud: u32) -> io::Result<Self> {
        let port = serialport::new(device, baud)
            .timeout(Duration::from_millis(10))
            .open()
            .map_err(io::Error::from)?;
        Ok(Self::wrap(port))
    }

    /// Wraps an already connected Unix stream (e.g. one end of `UnixStream::pair`).
    pub fn from_unix(stream: UnixStream) -> Self {
        Self::wrap(stream)
    }

    fn wrap(inner: impl TimedRead + Send + 'static) -> Self {
        StreamLink { inner: Box::new(inner), timeout: None }
    }
}

impl ByteLink for StreamLink {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.inner.write_all(bytes)?;
        self.inner.flush()
    }

    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        if self.timeout != Some(timeout) {
            self.inner.set_timeout(timeout)?;
            self.timeout = Some(timeout);
        }
        match self.inner.read(buf) {
            Ok(0) if !buf.is_empty() => Err(io::ErrorKind::UnexpectedEof.into()),
            Ok(n) => Ok(n),
            Err(e) if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => Ok(0),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => Ok(0),
            Err(e) => Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unix_pair_round_trip_timeout_and_eof() {
        let (a, b) = UnixStream::pair().unwrap();
        let (mut a, mut b) = (StreamLink::from_unix(a), StreamLink::from_unix(b));
        a.send(&[0xF3, 5]).unwrap();
        let mut buf = [0; 4];
        let mut got = Vec::new();
        while got.len() < 2 {
            let n = b.recv(&mut buf, Duration::from_millis(50)).unwrap();
            got.extend_from_slice(&buf[..n]);
        }
        assert_eq!(got, [0xF3, 5]);
        assert_eq!(b.recv(&mut buf, Duration::from_millis(1)).unwrap(), 0);
        drop(a);
        assert_eq!(
            b.recv(&mut buf, Duration::from_millis(50)).unwrap_err().kind(),
            io::ErrorKind::UnexpectedEof
        );
    }

    #[test]
    fn tcp_round_trip() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        let echo = std::thread::spawn(move || {
            let (mut s, _) = listener.accept().unwrap();
            let mut b = [0; 1];
            s.read_exact(&mut b).unwrap();
            s.write_all(&b).unwrap();
        });
        let mut link = StreamLink::tcp(&addr).unwrap();
        link.send(&[42]).unwrap();
        let mut buf = [0; 1];
        let mut n = 0;
        while n == 0 {
            n = link.recv(&mut buf, Duration::from_millis(100)).unwrap();
        }
        assert_eq!(buf, [42]);
        echo.join().unwrap();
    }
}
