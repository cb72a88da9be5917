//! The spread of one serial step of `keylo ros2` without DDS: its "prepare" step, making the
//! frame of a `sensor_msgs/PointCloud2` (x, y, z, intensity as FLOAT32, as the latency bench's
//! peer sends KITTI scans) for raw KISS-ICP (points only), on the same KITTI scans, one every
//! 30 ms as a node sees them. Two ways, alternating: decoding into a `RawCloud` and framing it
//! (`to_raw_cloud` + `CloudFramer::frame`), and framing straight from the bytes
//! (`CloudFramer::frame_message`, what the node does); the frames must be equal. Prints
//! median, p90, p99 and max in ms as JSON, so the node's latency tail can be told from the
//! machine's own (docs/results/ros2.md).
//!
//! Usage: framer_jitter VELODYNE_DIR [REPEATS]

use std::path::Path;
use std::time::{Duration, Instant};

use keylo_io::cloud::{ProjectionConfig, Projector, Sensor};
use keylo_io::kitti_bin::read_kitti_cloud;
use keylo_io::ros::{to_raw_cloud, CloudFramer, Header, PointCloud2, PointField};

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
    let bytes: Vec<Vec<u8>> = clouds.iter().map(message_data).collect();
    // Per path: the whole step, and (two-step path) its decoding part.
    let (mut two_step, mut decode, mut direct) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..repeats {
        let msg = message(&bytes[k % bytes.len()]);
        let t = Instant::now();
        let cloud = to_raw_cloud(&msg)?;
        let decoded = t.elapsed();
        let frame = framer.frame(&cloud, k as u64)?;
        two_step.push(t.elapsed().as_secs_f64() * 1e3);
        decode.push(decoded.as_secs_f64() * 1e3);
        std::thread::sleep(Duration::from_millis(15));
        let t = Instant::now();
        let same = framer.frame_message(&msg, k as u64)?;
        direct.push(t.elapsed().as_secs_f64() * 1e3);
        if same != frame {
            return Err(format!("frame {k}: the direct path made another frame").into());
        }
        std::thread::sleep(Duration::from_millis(15));
    }
    let stats = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        format!(
            "{{\"median_ms\": {:.3}, \"p90_ms\": {:.3}, \"p99_ms\": {:.3}, \"max_ms\": {:.3}}}",
            at(0.5),
            at(0.9),
            at(0.99),
            at(1.0)
        )
    };
    println!(
        "{{\"frames\": {repeats}, \"points\": {}, \"decode_then_frame\": {}, \"of_which_decode\": {}, \
         \"frame_message\": {}}}",
        clouds[0].points.len(),
        stats(two_step),
        stats(decode),
        stats(direct),
    );
    Ok(())
}

/// The point bytes of `cloud` as a PointCloud2 holds them: x, y, z, intensity, FLOAT32, little
/// endian, 16 bytes a point.
fn message_data(cloud: &keylo_io::cloud::RawCloud) -> Vec<u8> {
    let intensity = cloud.intensity.as_deref();
    let mut data = Vec::with_capacity(16 * cloud.points.len());
    for (i, p) in cloud.points.iter().enumerate() {
        let v = intensity.map_or(0.0, |v| v[i]);
        for x in [p[0], p[1], p[2], v] {
            data.extend_from_slice(&x.to_le_bytes());
        }
    }
    data
}

/// An unorganised PointCloud2 over `data` (made by [`message_data`]).
fn message(data: &[u8]) -> PointCloud2<'_> {
    let field = |name, offset| PointField {
        name,
        offset,
        datatype: 7,
        count: 1,
    };
    let n = (data.len() / 16) as u32;
    PointCloud2 {
        header: Header {
            stamp_ns: 0,
            frame_id: "velodyne",
        },
        height: 1,
        width: n,
        fields: vec![
            field("x", 0),
            field("y", 4),
            field("z", 8),
            field("intensity", 12),
        ],
        is_bigendian: false,
        point_step: 16,
        row_step: 16 * n,
        data,
        is_dense: true,
    }
}
