//! Waiting for a `keylo run` child with an optional time limit: past it, the child gets
//! SIGTERM (it stops after its current frame and writes what it has), then SIGKILL after a
//! grace period.

use std::process::{Child, ExitStatus};
use std::time::{Duration, Instant};

/// How long a child may take to stop after SIGTERM before it is killed.
const GRACE: Duration = Duration::from_secs(10);
/// How often a running child is polled.
const POLL: Duration = Duration::from_millis(20);

/// How a child ended.
pub struct Ended {
    pub status: ExitStatus,
    /// The time limit was reached and the child was told to stop.
    pub timed_out: bool,
}

/// Waits for `child`; with `limit`, stops it once it has run that long.
pub fn wait(child: &mut Child, limit: Option<Duration>) -> std::io::Result<Ended> {
    let Some(limit) = limit else {
        return Ok(Ended {
            status: child.wait()?,
            timed_out: false,
        });
    };
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok(Ended {
                status,
                timed_out: false,
            });
        }
        if start.elapsed() >= limit {
            break;
        }
        std::thread::sleep(POLL);
    }
    terminate(child);
    let stop_asked = Instant::now();
    while stop_asked.elapsed() < GRACE {
        if let Some(status) = child.try_wait()? {
            return Ok(Ended {
                status,
                timed_out: true,
            });
        }
        std::thread::sleep(POLL);
    }
    // It did not stop in time: SIGKILL (an error here means it has just exited).
    let _ = child.kill();
    Ok(Ended {
        status: child.wait()?,
        timed_out: true,
    })
}

/// Asks the child to stop (SIGTERM on Unix; elsewhere there is only kill).
#[cfg(unix)]
fn terminate(child: &mut Child) {
    match libc::pid_t::try_from(child.id()) {
        // SAFETY: kill(2) on the pid of a child we have not yet reaped (so the pid is ours).
        Ok(pid) => unsafe {
            libc::kill(pid, libc::SIGTERM);
        },
        Err(_) => {
            let _ = child.kill();
        }
    }
}

#[cfg(not(unix))]
fn terminate(child: &mut Child) {
    let _ = child.kill();
}
