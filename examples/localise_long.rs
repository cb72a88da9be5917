//! Localisation over a long run (docs/maps.md, "Localisation"): a map saved from one simulated
//! run (the ground-truth poses, so the map is right), then a second run localised in it from
//! an initial pose 0.3 m and 5° off, beside raw KISS-ICP odometry on the same frames. Prints
//! the position error against the ground truth per block of frames, for both.
//!
//! Usage: localise_long [SCENE] [FRAMES] [SEED_B] [SPEED_B] [VOXEL]
//!        (defaults: lab 1000 3 1.0 0.3; on the road use seed 0 and another speed: another
//!        seed is another road)

use keylo::config::RawConfig;
use keylo::map::localise::{LocaliseConfig, Localiser};
use keylo::map::{MapBuilder, MapConfig};
use keylo::sim::{SceneKind, SimConfig, Simulator};
use nalgebra::{Point3, Translation3, UnitQuaternion, Vector3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene: SceneKind = match args.next() {
        Some(s) => toml::Value::String(s).try_into()?,
        None => SceneKind::Lab,
    };
    let frames: usize = args.next().map_or(Ok(1000), |s| s.parse())?;
    let seed_b: u64 = args.next().map_or(Ok(3), |s| s.parse())?;
    let speed_b: f64 = args.next().map_or(Ok(1.0), |s| s.parse())?;
    let voxel: f64 = args.next().map_or(Ok(0.3), |s| s.parse())?;
    let sim = |seed, speed_scale| {
        Simulator::new(&SimConfig {
            scene,
            frames,
            seed,
            speed_scale,
            ..SimConfig::default()
        })
    };
    let (a, b) = (sim(0, 1.0)?, sim(seed_b, speed_b)?);
    // The map of run A from its true poses.
    let dir = std::env::temp_dir().join(format!("keylo-localise-long-{}", std::process::id()));
    let mut builder = MapBuilder::create(&dir, MapConfig::default(), "run A")?;
    for k in 0..a.len() {
        let frame = a.frame(k);
        let r = keylo::FrameResult {
            index: k as u64,
            stamp: frame.end_stamp(),
            pose: a.relative_pose_at(a.gt_stamp(k)),
            keypoints: 0,
            cloud_points: 0,
            registered_points: 0,
            map_points: 0,
            iterations: 0,
            converged: true,
            degeneracy: None,
            timings: Default::default(),
        };
        builder.add(&frame, &r, None)?;
    }
    builder.finish()?;
    let map = keylo::map::Map::open(&dir)?;
    let points: Vec<Point3<f64>> = (map.cloud()?.iter())
        .map(|r| Point3::new(f64::from(r[0]), f64::from(r[1]), f64::from(r[2])))
        .collect();
    std::fs::remove_dir_all(&dir)?;
    let map_from_scene = a.pose_at(a.gt_stamp(0)).inverse();
    let truth = |k: usize| map_from_scene * b.pose_at(b.gt_stamp(k));
    let off = keylo::Pose::from_parts(
        Translation3::new(0.3, 0.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 5f64.to_radians()),
    );
    let settings = LocaliseConfig {
        voxel_size: voxel,
        ..LocaliseConfig::default()
    };
    let mut localiser = Localiser::new(&points, truth(0) * off, settings);
    let registry = keylo::registry();
    let config = registry.resolve(&RawConfig::parse(
        "odometry",
        "[registrar]\nkind = \"kiss-icp\"\n",
    )?)?;
    let mut odometry = keylo::Odometry::build(&config, &registry)?;
    let (mut loc, mut odo, mut lost) = (Vec::new(), Vec::new(), 0);
    let (mut loc_s, mut odo_s) = (0.0, 0.0);
    for k in 0..b.len() {
        let frame = b.frame(k);
        let t = std::time::Instant::now();
        let l = localiser.localise(&frame, k == 0);
        loc_s += t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let o = odometry.process(&frame)?;
        odo_s += t.elapsed().as_secs_f64();
        let truth_k = truth(k);
        loc.push((l.pose.translation.vector - truth_k.translation.vector).norm());
        let o_true = truth(0).inverse() * truth_k;
        odo.push((o.pose.translation.vector - o_true.translation.vector).norm());
        lost += usize::from(!l.tracking);
    }
    println!("{scene:?}, {frames} frames (run B: seed {seed_b}, speed ×{speed_b}), voxel {voxel} m: {lost} frames not tracking; localisation {:.0} Hz, odometry {:.0} Hz", frames as f64 / loc_s, frames as f64 / odo_s);
    println!("| frames | localisation: mean / max error (m) | odometry: mean / max error (m) |");
    println!("|---|---|---|");
    let block = (frames / 10).max(1);
    for (i, (l, o)) in loc.chunks(block).zip(odo.chunks(block)).enumerate() {
        let stat = |v: &[f64]| {
            (
                v.iter().sum::<f64>() / v.len() as f64,
                v.iter().copied().fold(0.0, f64::max),
            )
        };
        let ((lm, lx), (om, ox)) = (stat(l), stat(o));
        println!(
            "| {}–{} | {lm:.3} / {lx:.3} | {om:.3} / {ox:.3} |",
            i * block,
            i * block + l.len() - 1
        );
    }
    Ok(())
}
