//! The spread of one serial step of `keylo ros2` without DDS: making the frame of an
//! unorganised cloud (`CloudFramer`, points-only, as for raw KISS-ICP), on the same KITTI
//! scans, one every 30 ms as a node sees them. Prints median, p90, p99 and max in ms as JSON,
//! so the node's latency tail can be told from the machine's own (docs/results/ros2.md).
//!
//! Usage: framer_jitter VELODYNE_DIR [REPEATS]

use std::path::Path;
use std::time::{Duration, Instant};

use keylo_io::cloud::{ProjectionConfig, Projector, Sensor};
use keylo_io::kitti_bin::read_kitti_cloud;
use keylo_io::ros::CloudFramer;

// The allocator the `keylo` binary uses.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = args
        .next()
        .ok_or("usage: framer_jitter VELODYNE_DIR [REPEATS]")?;
    let repeats: usize = args.next().map_or(Ok(300), |r| r.parse())?;
    if repeats == 0 {
        return Err("REPEATS: expected at least 1".into());
    }
    let mut scans: Vec<_> = std::fs::read_dir(&dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bin"))
        .collect();
    scans.sort();
    let clouds = (scans.iter().enumerate())
        .map(|(i, p)| read_kitti_cloud(Path::new(p), 0.1 * i as f64))
        .collect::<Result<Vec<_>, _>>()?;
    if clouds.is_empty() {
        return Err(format!("{dir}: no .bin scans").into());
    }
    let projector = Projector::from_config(&ProjectionConfig::default(), Sensor::Generic)?;
    let mut framer = CloudFramer::new(projector, None, "jitter");
    framer.set_grid_needed(false);
    let mut ms = Vec::with_capacity(repeats);
    for k in 0..repeats {
        let cloud = &clouds[k % clouds.len()];
        let t = Instant::now();
        let frame = framer.frame(cloud, k as u64)?;
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(frame);
        std::thread::sleep(Duration::from_millis(30));
    }
    ms.sort_by(f64::total_cmp);
    let at = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
    println!(
        "{{\"frames\": {repeats}, \"points\": {}, \"median_ms\": {:.3}, \"p90_ms\": {:.3}, \
         \"p99_ms\": {:.3}, \"max_ms\": {:.3}}}",
        clouds[0].points.len(),
        at(0.5),
        at(0.9),
        at(0.99),
        at(1.0)
    );
    Ok(())
}
