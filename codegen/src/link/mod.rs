//! Byte links between the virtual plant and a firmware: QEMU's UART on a Unix socket, TCP, a serial port
//! to a board, or an in-memory pair for in-process tests; and the [`protocol`] spoken over them.

pub mod memory;
pub mod protocol;
mod stream;

use std::io;
use std::path::PathBuf;
use std::str::FromStr;
use std::time::Duration;

pub use stream::StreamLink;

/// Baud rate of a serial endpoint that does not name one.
pub const DEFAULT_BAUD: u32 = 115_200;

/// A duplex byte stream with bounded waits.
pub trait ByteLink {
    /// Sends all of `bytes`, in order, as one write (a burst reaches the peer back to back).
    fn send(&mut self, bytes: &[u8]) -> io::Result<()>;
    /// Receives what has arrived, waiting at most `timeout` for the first byte; `Ok(0)` when nothing came.
    /// A closed peer is an [`io::ErrorKind::UnexpectedEof`] error.
    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize>;
}

impl<L: ByteLink + ?Sized> ByteLink for Box<L> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        (**self).send(bytes)
    }

    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        (**self).recv(buf, timeout)
    }
}

/// Where a firmware's link is: `unix:PATH`, `tcp:HOST:PORT` or `serial:DEVICE[@BAUD]`.
///
/// # Examples
///
/// ```
/// use codegen::link::Endpoint;
///
/// let e: Endpoint = "serial:/dev/ttyACM0@9600".parse().unwrap();
/// assert_eq!(e, Endpoint::Serial { device: "/dev/ttyACM0".into(), baud: 9600 });
/// assert!("usb:1".parse::<Endpoint>().is_err());
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Endpoint {
    /// A Unix socket, e.g. QEMU's `-serial unix:PATH,server=on`.
    Unix(PathBuf),
    /// A TCP address `host:port`.
    Tcp(String),
    /// A serial device and its baud rate.
    Serial {
        /// Device path, e.g. `/dev/ttyACM0`.
        device: String,
        /// Baud rate.
        baud: u32,
    },
}

/// An endpoint string that does not follow `unix:PATH`, `tcp:HOST:PORT` or `serial:DEVICE[@BAUD]`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("bad endpoint '{0}': expected unix:PATH, tcp:HOST:PORT or serial:DEVICE[@BAUD]")]
pub struct EndpointError(String);

impl FromStr for Endpoint {
    type Err = EndpointError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || EndpointError(s.to_owned());
        let (scheme, rest) = s.split_once(':').ok_or_else(bad)?;
        if rest.is_empty() {
            return Err(bad());
        }
        match scheme {
            "unix" => Ok(Endpoint::Unix(rest.into())),
            "tcp"
                if rest.rsplit_once(':').is_some_and(|(h, p)| !h.is_empty() && p.parse::<u16>().is_ok()) =>
            {
                Ok(Endpoint::Tcp(rest.to_owned()))
            }
            "serial" => match rest.rsplit_once('@') {
                Some((device, baud)) if !device.is_empty() => {
                    Ok(Endpoint::Serial { device: device.to_owned(), baud: baud.parse().map_err(|_| bad())? })
                }
                Some(_) => Err(bad()),
                None => Ok(Endpoint::Serial { device: rest.to_owned(), baud: DEFAULT_BAUD }),
            },
            _ => Err(bad()),
        }
    }
}

impl Endpoint {
    /// Opens the link.
    pub fn connect(&self) -> io::Result<StreamLink> {
        match self {
            Endpoint::Unix(path) => StreamLink::unix(path),
            Endpoint::Tcp(addr) => StreamLink::tcp(addr),
            Endpoint::Serial { device, baud } => StreamLink::serial(device, *baud),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_parse_and_refuse() {
        assert_eq!("unix:/tmp/u.sock".parse(), Ok(Endpoint::Unix("/tmp/u.sock".into())));
        assert_eq!("tcp:localhost:4000".parse(), Ok(Endpoint::Tcp("localhost:4000".into())));
        assert_eq!(
            "serial:/dev/ttyUSB0".parse(),
            Ok(Endpoint::Serial { device: "/dev/ttyUSB0".into(), baud: DEFAULT_BAUD })
        );
        for bad in
            ["unix:", "tcp:host", "tcp::80", "tcp:h:port", "serial:@9600", "serial:/dev/x@fast", "nope"]
        {
            assert!(bad.parse::<Endpoint>().is_err(), "{bad}");
        }
    }
}
