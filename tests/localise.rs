//! Localisation in a prior map (docs/maps.md, "Localisation") on simulated scenes, checked
//! against the simulator's ground truth: a second run localised with ICP and with NDT in the
//! map of a first, a lost localiser that says so and recovers, and the `localise` registrar
//! that puts the same into any front end.

mod common;

use common::mapped;
use keylo::map::localise::{LocaliseConfig, LocaliseMethod};
use keylo::map::MapConfig;
use keylo::sim::{SceneKind, SimConfig, Simulator};

/// Localisation in a prior map: a map saved from one run of the lab (the ground-truth poses,
/// so the map itself is right), a second run with another seed localised in it from an
/// initial pose 0.3 m and 5° off. The seed keeps the room's walls but draws the furniture, the
/// loop's axes and the noise anew: a changed room, another path. Its error stays bounded and below the odometry's on the same
/// frames; every frame is tracking.
#[path = "../examples/localise_long.rs"]
mod localise_long;

#[test]
fn a_second_run_is_localised_in_the_first_runs_map() {
    // The lab: another seed (a changed room, another path).
    let second = localise_long::SecondRun {
        seed: 3,
        speed_scale: 1.0,
    };
    check_localised(SceneKind::Lab, &second, &settings(0.3, LocaliseMethod::Icp));
    let mut ndt = settings(0.3, LocaliseMethod::Ndt);
    ndt.ndt.resolution = 1.0; // indoors (docs/maps.md)
    check_localised(SceneKind::Lab, &second, &ndt);
}

#[test]
fn a_slower_run_is_localised_in_the_first_runs_road_map() {
    // The road: the same seed (the same road), driven at 0.8× the speed.
    let second = localise_long::SecondRun {
        seed: 0,
        speed_scale: 0.8,
    };
    check_localised(
        SceneKind::Road,
        &second,
        &settings(1.0, LocaliseMethod::Icp),
    );
    check_localised(
        SceneKind::Road,
        &second,
        &settings(1.0, LocaliseMethod::Ndt),
    );
}

fn settings(voxel: f64, method: LocaliseMethod) -> LocaliseConfig {
    LocaliseConfig {
        voxel_size: voxel,
        method,
        ..LocaliseConfig::default()
    }
}

/// Localisation in a prior map (`examples/localise_long.rs` on 80 frames): a map saved from
/// one run of `scene` with the true poses, a second run localised in it from 0.3 m and 5° off
/// with `settings` (ICP and NDT). In the lab another seed keeps the room's walls but draws the
/// furniture, the loop's axes and the noise anew; on the road it would draw another road, so
/// the road run changes its speed instead. The error stays bounded, does not grow, and stays
/// below the odometry's on the same frames; every frame is tracking.
fn check_localised(scene: SceneKind, second: &localise_long::SecondRun, settings: &LocaliseConfig) {
    let frames = 80;
    let e = localise_long::run(scene, frames, second, settings).unwrap();
    let scene = format!("{scene:?} {:?}", settings.method);
    let (loc, odo) = (&e.localised, &e.odometry);
    assert!(e.tracking.iter().all(|t| *t), "{scene}: {:?}", e.tracking);
    let late = |v: &[f64]| v[frames / 2..].iter().copied().fold(0.0, f64::max);
    let mut fit = e.fitness.clone();
    fit.sort_by(f64::total_cmp);
    println!(
        "{scene}: fitness min {:.3}, median {:.3}",
        fit[0],
        fit[fit.len() / 2]
    );
    println!(
        "{scene}: localisation error: frame 0 {:.3} m, largest after frame 5 {:.3} m, second half \
         {:.3} m; odometry second half {:.3} m",
        loc[0],
        loc[5..].iter().copied().fold(0.0, f64::max),
        late(loc),
        late(odo)
    );
    assert!(loc[5..].iter().all(|&x| x < 0.1), "{loc:?}");
    // No drift: the last quarter's mean error is no larger than the second quarter's (+1 cm).
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let q = frames / 4;
    assert!(mean(&loc[3 * q..]) < mean(&loc[q..2 * q]) + 0.01, "{loc:?}");
    assert!(
        late(loc) < late(odo),
        "localisation {} vs odometry {}",
        late(loc),
        late(odo)
    );
}

/// A localiser started far from the truth says it is lost (it does not report a made-up pose
/// as tracked) and, given a new pose (`set_pose`) 0.3 m and 5° off the truth, tracks again:
/// the correction of the given pose's error is not taken for motion.
#[test]
fn a_lost_localiser_says_so_and_recovers_from_a_new_pose() {
    use keylo::map::localise::Localiser;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};
    let sim = Simulator::new(&SimConfig {
        scene: SceneKind::Lab,
        frames: 20,
        ..SimConfig::default()
    })
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let map = mapped(&sim, MapConfig::default(), &dir.path().join("map"), true);
    let points = map.points().unwrap();
    let truth = |k: usize| sim.relative_pose_at(sim.gt_stamp(k));
    let far = keylo::Pose::from_parts(
        Translation3::new(3.0, -2.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 2.0),
    );
    let settings = LocaliseConfig {
        voxel_size: 0.3,
        ..LocaliseConfig::default()
    };
    let mut localiser = Localiser::new(&points, truth(0) * far, settings).unwrap();
    let lost: Vec<bool> = (0..5)
        .map(|k| !localiser.localise(&sim.frame(k)).tracking)
        .collect();
    assert!(
        lost.iter().all(|&l| l),
        "tracking from 3.6 m and 115° off: {lost:?}"
    );
    let off = keylo::Pose::from_parts(
        Translation3::new(0.3, 0.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 5f64.to_radians()),
    );
    localiser.set_pose(truth(4) * off);
    for k in 5..20 {
        let l = localiser.localise(&sim.frame(k));
        let e = (l.pose.translation.vector - truth(k).translation.vector).norm();
        assert!(
            l.tracking && e < 0.1,
            "frame {k} after set_pose: fitness {}, error {e}",
            l.fitness
        );
    }
}

/// `[registrar] kind = "localise"` puts localisation into any front end: an `Odometry` built
/// from a config localises a second lab run (another seed: the furniture and path drawn anew)
/// in the first run's map, with ICP and with NDT, each frame carrying its fit; `reset` goes
/// back to the initial pose as a new localiser, and `set_pose` relocalises a lost one. A
/// missing map, an empty `map` key and an initial pose outside the map are errors naming them.
#[test]
fn the_localise_registrar_localises_from_a_config() {
    let sim = |seed| {
        Simulator::new(&SimConfig {
            scene: SceneKind::Lab,
            frames: 30,
            seed,
            ..SimConfig::default()
        })
        .unwrap()
    };
    let (a, b) = (sim(0), sim(3));
    let dir = tempfile::tempdir().unwrap();
    let map_dir = dir.path().join("map");
    mapped(&a, MapConfig::default(), &map_dir, true);
    let map_from_scene = a.pose_at(a.gt_stamp(0)).inverse();
    let truth = |k: usize| map_from_scene * b.pose_at(b.gt_stamp(k));
    let start = truth(0) * keylo::Pose::translation(0.2, -0.1, 0.0);
    let (t, q) = (start.translation.vector, start.rotation.quaternion());
    let config_text = |method: &str, extra: &str| {
        format!(
            "[registrar]\nkind = \"localise\"\nmap = \"{}\"\nmethod = \"{method}\"\nvoxel_size = \
             0.3\ninitial_pose = [{}, {}, {}, {}, {}, {}, {}]\n{extra}",
            map_dir.display(),
            t.x,
            t.y,
            t.z,
            q.i,
            q.j,
            q.k,
            q.w
        )
    };
    for (method, extra) in [("icp", ""), ("ndt", "ndt.resolution = 1.0\n")] {
        let (registry, config) = common::resolve(&config_text(method, extra));
        let mut odometry = keylo::Odometry::build(&config, &registry).unwrap();
        let mut errors = Vec::new();
        for k in 0..b.len() {
            let r = odometry.process(&b.frame(k)).unwrap();
            let fit = r.fit.expect("a localise frame carries its fit");
            assert!(fit.tracking, "{method} frame {k}: fitness {}", fit.fitness);
            errors.push((r.pose.translation.vector - truth(k).translation.vector).norm());
        }
        println!("{method}: position errors {errors:.3?}");
        assert!(errors[3..].iter().all(|&e| e < 0.1), "{method}: {errors:?}");
        // reset: back to the initial pose, as a new localiser.
        odometry.reset().unwrap();
        let r = odometry.process(&b.frame(0)).unwrap();
        let e = (r.pose.translation.vector - truth(0).translation.vector).norm();
        assert!(e < 0.1, "{method}: after reset, frame 0 off by {e} m");
        // Lost from a pose 3.6 m and 115° off, then found again from a given pose.
        let far = keylo::Pose::from_parts(
            nalgebra::Translation3::new(3.0, -2.0, 0.0),
            nalgebra::UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), 2.0),
        );
        odometry.set_pose(&(truth(0) * far)).unwrap();
        let r = odometry.process(&b.frame(1)).unwrap();
        let e = (r.pose.translation.vector - truth(1).translation.vector).norm();
        assert!(
            !r.fit.unwrap().tracking,
            "{method}: tracking from far off: fitness {}, error {e} m",
            r.fit.unwrap().fitness
        );
        odometry.set_pose(&truth(1)).unwrap();
        for k in 2..6 {
            let r = odometry.process(&b.frame(k)).unwrap();
            let e = (r.pose.translation.vector - truth(k).translation.vector).norm();
            assert!(
                r.fit.unwrap().tracking && e < 0.1,
                "{method} frame {k}: {e} m"
            );
        }
    }

    let registry = keylo::registry();
    let fails = |text: &str, needle: &str| {
        let raw = keylo::config::RawConfig::parse("t.toml", text).unwrap();
        let e = match registry.resolve(&raw) {
            Ok(config) => match keylo::Odometry::build(&config, &registry) {
                Ok(_) => panic!("built from {text}"),
                Err(e) => e.to_string(),
            },
            Err(e) => e.to_string(),
        };
        assert!(e.contains(needle), "{text}: {e}");
    };
    fails("[registrar]\nkind = \"localise\"\n", "`map` is empty");
    fails(
        "[registrar]\nkind = \"localise\"\nmap = \"/no/such/map\"\n",
        "/no/such/map",
    );
    fails(
        &config_text("icp", "").replace(&format!("[{}", t.x), "[500"),
        "lies outside the map",
    );
    fails(
        &format!(
            "[registrar]\nkind = \"localise\"\nmap = \"{}\"\ninitial_pose = [1, 2, 3]\n",
            map_dir.display()
        ),
        "3 numbers; expected seven",
    );
    fails(
        &format!(
            "[registrar]\nkind = \"localise\"\nmap = \"{}\"\nmethod = \"gicp\"\n",
            map_dir.display()
        ),
        "gicp",
    );
}
