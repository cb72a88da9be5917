//! Lidar packets straight from the sensor: a UDP socket on the lidar port (and one on the IMU
//! port, drained and counted so the sensor's IMU stream is received, not refused).

use std::net::{SocketAddr, UdpSocket};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::datagrams::Datagrams;
use super::pcap::Datagram;
use crate::IoError;

/// Set by [`stop_live_sources`]: every live stream ends at its next wait (Ctrl-C, SIGTERM).
static STOP: AtomicBool = AtomicBool::new(false);

/// Ends every live Ouster stream of the process: their sources flush the frame in progress
/// and end. Call it from a Ctrl-C / SIGTERM handler.
pub fn stop_live_sources() {
    STOP.store(true, Ordering::SeqCst);
}

/// How long one wait for a packet lasts before the stop flag and idle time are checked.
const POLL: Duration = Duration::from_millis(50);
/// The largest UDP payload.
const MAX_DATAGRAM: usize = 65_536;
/// Receive buffer asked for on the lidar socket: a second of an OS0-128 at 2048×10 (64 MB/s
/// would need more; the kernel caps it at `net.core.rmem_max`). The default (~200 kB, eight
/// 128-beam packets) overflows whenever registration holds both cores for ~10 ms.
const RECEIVE_BUFFER: usize = 32 << 20;

/// Datagrams arriving on a bound UDP port.
pub struct LiveUdp {
    label: PathBuf,
    lidar: UdpSocket,
    lidar_port: u16,
    imu: Option<UdpSocket>,
    idle: Option<Duration>,
    last: Instant,
    buf: Vec<u8>,
    imu_packets: Arc<AtomicU64>,
}

impl LiveUdp {
    /// Binds `bind:lidar_port` (and `bind:imu_port` unless 0). The stream ends when nothing
    /// came for `idle` (never when `None`) or [`stop_live_sources`] is called.
    pub fn bind(
        bind: &str,
        lidar_port: u16,
        imu_port: u16,
        idle: Option<Duration>,
    ) -> Result<Self, IoError> {
        let label = PathBuf::from(format!("udp://{bind}:{lidar_port}"));
        let open = |port: u16| -> Result<UdpSocket, IoError> {
            let addr: SocketAddr = format!("{bind}:{port}").parse().map_err(|_| {
                IoError::format(
                    Path::new("source.bind"),
                    format!("`{bind}` is not an IP address (e.g. 0.0.0.0 or 192.168.1.5)"),
                )
            })?;
            let socket = UdpSocket::bind(addr).map_err(|e| {
                IoError::format(
                    Path::new(&format!("udp://{addr}")),
                    format!("cannot bind the port ({e}); is another driver or keylo using it?"),
                )
            })?;
            socket
                .set_read_timeout(Some(POLL))
                .map_err(|e| IoError::io(Path::new(&format!("udp://{addr}")), e))?;
            Ok(socket)
        };
        let lidar = open(lidar_port)?;
        let sock = socket2::SockRef::from(&lidar);
        if sock.set_recv_buffer_size(RECEIVE_BUFFER).is_err() {
            tracing::warn!("udp://{bind}:{lidar_port}: could not enlarge the receive buffer");
        }
        let got = sock.recv_buffer_size().unwrap_or(0);
        if got < 4 << 20 {
            tracing::warn!(
                "udp://{bind}:{lidar_port}: receive buffer {} kB (net.core.rmem_max caps it); \
                 packets may be lost while registration is busy: raise it with `sysctl -w \
                 net.core.rmem_max=33554432`",
                got >> 10
            );
        }
        let lidar_port = lidar.local_addr().map_or(lidar_port, |a| a.port());
        let imu = match imu_port {
            0 => None,
            p => {
                let s = open(p)?;
                s.set_nonblocking(true)
                    .map_err(|e| IoError::io(Path::new(&format!("udp://{bind}:{p}")), e))?;
                Some(s)
            }
        };
        Ok(Self {
            label,
            lidar,
            lidar_port,
            imu,
            idle,
            last: Instant::now(),
            buf: vec![0; MAX_DATAGRAM],
            imu_packets: Arc::new(AtomicU64::new(0)),
        })
    }

    /// What the stream is, for messages (`udp://ADDRESS:PORT`).
    pub fn label(&self) -> &Path {
        &self.label
    }

    /// The lidar port bound (the one asked for, or the system's choice for 0).
    pub fn lidar_port(&self) -> u16 {
        self.lidar_port
    }

    /// IMU packets received so far (shared: it keeps counting after the stream is moved).
    pub fn imu_packets(&self) -> Arc<AtomicU64> {
        Arc::clone(&self.imu_packets)
    }

    fn drain_imu(&mut self) {
        if let Some(imu) = &self.imu {
            let mut small = [0u8; 256];
            while imu.recv_from(&mut small).is_ok() {
                self.imu_packets.fetch_add(1, Ordering::Relaxed);
            }
        }
    }
}

impl Datagrams for LiveUdp {
    fn next_datagram(&mut self) -> Option<Result<Datagram, IoError>> {
        loop {
            if STOP.load(Ordering::SeqCst) {
                return None;
            }
            self.drain_imu();
            match self.lidar.recv_from(&mut self.buf) {
                Ok((n, _from)) => {
                    self.last = Instant::now();
                    let time = std::time::SystemTime::now()
                        .duration_since(std::time::UNIX_EPOCH)
                        .map_or(0.0, |d| d.as_secs_f64());
                    return Some(Ok(Datagram {
                        time,
                        dst_port: self.lidar_port,
                        payload: self.buf[..n].to_vec(),
                    }));
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock
                            | std::io::ErrorKind::TimedOut
                            | std::io::ErrorKind::Interrupted
                    ) =>
                {
                    if self.idle.is_some_and(|d| self.last.elapsed() >= d) {
                        return None;
                    }
                }
                Err(e) => return Some(Err(IoError::io(&self.label, e))),
            }
        }
    }
}

// Receiving is tested in a private network namespace (tests/ouster_live.rs), as every test
// that sends or receives UDP.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_addresses_name_the_key() {
        let e = LiveUdp::bind("not-an-ip", 7502, 0, None)
            .err()
            .expect("refused");
        assert!(e.to_string().contains("source.bind"), "{e}");
    }
}
