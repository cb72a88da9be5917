//! Localisation over a long run (docs/maps.md, "Localisation"): a map saved from one simulated
//! run (the ground-truth poses, so the map is right), then a second run localised in it from
//! an initial pose 0.3 m and 5° off, beside raw KISS-ICP odometry on the same frames. Prints
//! the position error against the ground truth per block of frames, for both.
//! `tests/map_sim.rs` runs [`run`] on shorter runs.
//!
//! Usage: localise_long [SCENE] [FRAMES] [SEED_B] [SPEED_B] [VOXEL] [METHOD] [NDT_RESOLUTION] [NDT_SOURCE_VOXEL]
//!        (defaults: lab 1000 3 1.0 0.3 icp; on the road use seed 0 and another speed:
//!        another seed is another road; METHOD icp or ndt)

use keylo::config::RawConfig;
use keylo::map::localise::{LocaliseConfig, LocaliseMethod, Localiser};
use keylo::map::{MapBuilder, MapConfig};
use keylo::sim::{SceneKind, SimConfig, Simulator};
use nalgebra::{Point3, Translation3, UnitQuaternion, Vector3};

/// The second run of [`run`]: its seed and speed (the first run has seed 0, speed 1).
pub struct SecondRun {
    pub seed: u64,
    pub speed_scale: f64,
}

/// Per frame of the second run: the localiser's and the odometry's position errors (m), and
/// whether the localiser was tracking; with the registration rates (Hz).
pub struct Errors {
    pub localised: Vec<f64>,
    pub odometry: Vec<f64>,
    pub tracking: Vec<bool>,
    /// The localiser's fitness per frame.
    pub fitness: Vec<f64>,
    pub rates_hz: (f64, f64),
}

/// Maps `frames` frames of `scene` from the true poses, then localises `second` in it with
/// `settings` from 0.3 m and 5° off, beside raw KISS-ICP.
pub fn run(
    scene: SceneKind,
    frames: usize,
    second: &SecondRun,
    settings: &LocaliseConfig,
) -> Result<Errors, Box<dyn std::error::Error>> {
    let sim = |seed, speed_scale| {
        Simulator::new(&SimConfig {
            scene,
            frames,
            seed,
            speed_scale,
            ..SimConfig::default()
        })
    };
    let (a, b) = (sim(0, 1.0)?, sim(second.seed, second.speed_scale)?);
    let points = true_map(&a)?;
    // The map's world frame in the scene: the first run's sensor at its first frame's end.
    let map_from_scene = a.pose_at(a.gt_stamp(0)).inverse();
    let truth = |k: usize| map_from_scene * b.pose_at(b.gt_stamp(k));
    let off = keylo::Pose::from_parts(
        Translation3::new(0.3, 0.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 5f64.to_radians()),
    );
    let mut localiser = Localiser::new(&points, truth(0) * off, settings.clone())?;
    let registry = keylo::registry();
    let config = registry.resolve(&RawConfig::parse(
        "odometry",
        "[registrar]\nkind = \"kiss-icp\"\n",
    )?)?;
    let mut odometry = keylo::Odometry::build(&config, &registry)?;
    let mut e = Errors {
        localised: Vec::new(),
        odometry: Vec::new(),
        tracking: Vec::new(),
        fitness: Vec::new(),
        rates_hz: (0.0, 0.0),
    };
    let (mut loc_s, mut odo_s) = (0.0, 0.0);
    for k in 0..b.len() {
        let frame = b.frame(k);
        let t = std::time::Instant::now();
        let l = localiser.localise(&frame);
        loc_s += t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let o = odometry.process(&frame)?;
        odo_s += t.elapsed().as_secs_f64();
        let truth_k = truth(k);
        e.localised
            .push((l.pose.translation.vector - truth_k.translation.vector).norm());
        // The odometry starts at the identity: compare it in its own frame.
        let o_true = truth(0).inverse() * truth_k;
        e.odometry
            .push((o.pose.translation.vector - o_true.translation.vector).norm());
        e.tracking.push(l.tracking);
        e.fitness.push(l.fitness);
    }
    e.rates_hz = (frames as f64 / loc_s, frames as f64 / odo_s);
    Ok(e)
}

/// The global cloud of a map saved from `sim`'s frames with its true poses.
fn true_map(sim: &Simulator) -> Result<Vec<Point3<f64>>, Box<dyn std::error::Error>> {
    let dir = std::env::temp_dir().join(format!(
        "keylo-true-map-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    let mut builder = MapBuilder::create(&dir, MapConfig::default(), "true poses")?;
    for k in 0..sim.len() {
        let frame = sim.frame(k);
        let pose = sim.relative_pose_at(sim.gt_stamp(k));
        let r = keylo::FrameResult::with_pose(k as u64, frame.end_stamp(), pose);
        builder.add(&frame, &r, None)?;
    }
    builder.finish()?;
    let points = keylo::map::Map::open(&dir)?.points()?;
    std::fs::remove_dir_all(&dir)?;
    Ok(points)
}

#[allow(dead_code)] // a module of tests/map_sim.rs too
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene: SceneKind = match args.next() {
        Some(s) => toml::Value::String(s).try_into()?,
        None => SceneKind::Lab,
    };
    let frames: usize = args.next().map_or(Ok(1000), |s| s.parse())?;
    let seed: u64 = args.next().map_or(Ok(3), |s| s.parse())?;
    let speed_scale: f64 = args.next().map_or(Ok(1.0), |s| s.parse())?;
    let voxel: f64 = args.next().map_or(Ok(0.3), |s| s.parse())?;
    let method: LocaliseMethod = match args.next() {
        Some(s) => toml::Value::String(s).try_into()?,
        None => LocaliseMethod::Icp,
    };
    let mut settings = LocaliseConfig {
        voxel_size: voxel,
        method,
        ..LocaliseConfig::default()
    };
    if let Some(r) = args.next() {
        settings.ndt.resolution = r.parse()?;
    }
    if let Some(v) = args.next() {
        settings.ndt.source_voxel_size = v.parse()?;
    }
    let e = run(scene, frames, &SecondRun { seed, speed_scale }, &settings)?;
    let lost = e.tracking.iter().filter(|t| !**t).count();
    println!(
        "{scene:?}, {frames} frames (run B: seed {seed}, speed ×{speed_scale}), {method:?} (NDT resolution {} m, source voxel {} m), voxel {voxel} m: {lost} frames not tracking; localisation {:.0} Hz, odometry {:.0} Hz",
        settings.ndt.resolution, settings.ndt.source_voxel_size, e.rates_hz.0, e.rates_hz.1
    );
    println!("| frames | localisation: mean / max error (m) | odometry: mean / max error (m) |");
    println!("|---|---|---|");
    let block = (frames / 10).max(1);
    for (i, (l, o)) in e
        .localised
        .chunks(block)
        .zip(e.odometry.chunks(block))
        .enumerate()
    {
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
