//! Where UDP datagrams come from: a pcap capture ([`super::UdpReader`]) or a live socket
//! ([`super::LiveUdp`]). The batcher reads either the same way, so a capture and the sensor
//! streaming the same packets give the same frames.

use super::pcap::{Datagram, UdpReader};
use crate::IoError;

/// A stream of UDP datagrams.
pub trait Datagrams: Send {
    /// The next datagram; `None` at the end (of the capture, or of a live stream: idle timeout
    /// or stop); an `Err` ends the stream.
    fn next_datagram(&mut self) -> Option<Result<Datagram, IoError>>;
}

impl Datagrams for UdpReader {
    fn next_datagram(&mut self) -> Option<Result<Datagram, IoError>> {
        UdpReader::next_datagram(self)
    }
}
