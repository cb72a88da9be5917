//! Process resource figures from /proc (Linux): peak RSS and CPU time.

/// Peak resident set size in MB (VmHWM), if known.
pub fn peak_rss_mb() -> Option<f64> {
    status_kb("VmHWM:").map(|kb| kb / 1024.0)
}

/// Current resident set size in MB (VmRSS), if known.
pub fn rss_mb() -> Option<f64> {
    status_kb("VmRSS:").map(|kb| kb / 1024.0)
}

fn status_kb(field: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// User + system CPU seconds of this process so far, if known.
pub fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which is in parentheses and may hold spaces).
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    const CLOCK_TICKS_PER_SECOND: f64 = 100.0;
    Some((utime + stime) / CLOCK_TICKS_PER_SECOND)
}

/// Wall and CPU time since a run started, for its summary's rates.
pub struct RunClock {
    start: std::time::Instant,
    cpu0: Option<f64>,
}

impl RunClock {
    /// Starts counting now.
    pub fn start() -> Self {
        Self {
            cpu0: cpu_seconds(),
            start: std::time::Instant::now(),
        }
    }

    /// Measured now: `frames` per second of wall time, and the CPU % over that time.
    pub fn rates(&self, frames: usize) -> (f64, Option<f64>) {
        let wall = self.start.elapsed().as_secs_f64();
        let hz = if wall > 0.0 {
            frames as f64 / wall
        } else {
            0.0
        };
        let cpu = self
            .cpu0
            .zip(cpu_seconds())
            .map(|(a, b)| 100.0 * (b - a) / wall.max(1e-9));
        (hz, cpu)
    }
}
