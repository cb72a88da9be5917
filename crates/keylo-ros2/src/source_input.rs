//! The node fed by the config's own source (a live `ouster-udp` sensor) instead of the points
//! topic: odometry straight from the sensor's packets, no driver in between.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use keylo_core::{ImageSource, Odometry};

use crate::inbox::Inbox;
use crate::runner::{Held, NodeStats, Published, Ros2Node};

impl Ros2Node {
    /// Runs on the frames of `source` (a live sensor, e.g. `ouster-udp`) instead of the points
    /// topic: a thread reads them into a drop-oldest queue as they come, this one registers
    /// and publishes them (in `sensor_frame`), until the source ends or `stop` is set.
    pub fn run_source(
        &mut self,
        odometry: &mut Odometry,
        mut source: Box<dyn ImageSource>,
        stop: &AtomicBool,
        mut on_frame: impl FnMut(&Published),
    ) -> (NodeStats, Box<dyn ImageSource>) {
        source.set_grid_needed(odometry.needs_grid());
        let frames = Inbox::new(self.config.max_pending_clouds);
        let ended = AtomicBool::new(false);
        let sensor_frame = self.config.sensor_frame.clone();
        let source = std::thread::scope(|scope| {
            let reader = scope.spawn(|| {
                while let Some(next) = source.next_frame() {
                    match next {
                        Ok(f) => {
                            frames.push((Instant::now(), f));
                        }
                        Err(e) => {
                            tracing::error!("ros2: the source stopped: {e}");
                            break;
                        }
                    }
                }
                ended.store(true, Ordering::SeqCst);
                source
            });
            loop {
                while let Ok(c) = self.dds.commands.try_recv() {
                    self.command(odometry, c);
                }
                let Some((taken, frame)) = frames.pop(Duration::from_millis(50)) else {
                    if ended.load(Ordering::SeqCst) && frames.is_empty() {
                        break;
                    }
                    if stop.load(Ordering::SeqCst) {
                        keylo_io::ouster::stop_live_sources();
                    }
                    continue;
                };
                let stamp_ns = (frame.timestamp * 1e9).round() as i64;
                let held = Held {
                    taken,
                    started: Instant::now(),
                };
                if let Err(e) = self.register(
                    odometry,
                    &frame,
                    (stamp_ns, &sensor_frame),
                    held,
                    &mut on_frame,
                ) {
                    self.stats.clouds_refused += 1;
                    tracing::warn!("source frame {}: {e}; skipped", frame.index);
                }
            }
            reader
                .join()
                .unwrap_or_else(|p| std::panic::resume_unwind(p))
        });
        let (received, dropped) = frames.counts();
        let mut stats = self.stats();
        stats.clouds_received = received;
        stats.clouds_dropped = dropped;
        (stats, source)
    }
}
