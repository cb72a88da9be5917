//! A global map saved from a simulated run lies on the scene's true surfaces: every map
//! point, taken to the scene's frame with the ground-truth pose of the first frame, is
//! measured against the scene's geometry (not against keylo's own output). Built from the
//! true poses the map is as exact as the sensor; built without deskewing it lies farther
//! off, which shows the check can fail.

mod common;

use common::mapped;

use keylo::map::{Bounds, Map, MapConfig};
use keylo::sim::{SceneKind, SimConfig, Simulator};

/// Distances of the map's points to the scene's surfaces: (median, 95th percentile), m.
fn surface_errors(sim: &Simulator, map: &Map) -> (f64, f64) {
    let to_scene = sim.pose_at(sim.gt_stamp(0));
    let world = &sim.scene().world;
    let mut d: Vec<f64> = (map.cloud().unwrap().iter())
        .step_by(7)
        .map(|r| {
            let p =
                to_scene * nalgebra::Point3::new(f64::from(r[0]), f64::from(r[1]), f64::from(r[2]));
            f64::from(world.surface_distance([p.x as f32, p.y as f32, p.z as f32].into()))
        })
        .collect();
    d.sort_by(f64::total_cmp);
    (d[d.len() / 2], d[d.len() * 95 / 100])
}

#[test]
fn a_saved_map_lies_on_the_scenes_surfaces() {
    let sim = Simulator::new(&SimConfig {
        scene: SceneKind::Road,
        frames: 40,
        ..SimConfig::default()
    })
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let map = mapped(&sim, MapConfig::default(), &dir.path().join("map"), false);
    let (median, p95) = surface_errors(&sim, &map);
    let truth = mapped(&sim, MapConfig::default(), &dir.path().join("truth"), true);
    let (truth_median, truth_p95) = surface_errors(&sim, &truth);
    let raw = MapConfig {
        deskew: false,
        ..MapConfig::default()
    };
    let skewed = mapped(&sim, raw, &dir.path().join("skewed"), true);
    let (skewed_median, skewed_p95) = surface_errors(&sim, &skewed);
    println!(
        "map points to the scene's surfaces: median {median:.4} m, p95 {p95:.4} m; \
         from true poses {truth_median:.4} / {truth_p95:.4} m; \
         from true poses without deskew {skewed_median:.4} / {skewed_p95:.4} m"
    );
    // From true poses the map is as exact as the sensor (1 cm range noise) and the voxel
    // centroids allow; from the odometry's it carries the odometry's drift as well.
    assert!(
        truth_median < 0.005 && truth_p95 < 0.02,
        "true poses: {truth_median}, {truth_p95}"
    );
    assert!(
        median < 0.05 && p95 < 0.25,
        "odometry: median {median}, p95 {p95}"
    );
    assert!(
        skewed_p95 > 3.0 * truth_p95,
        "without deskew: p95 {skewed_p95} vs {truth_p95}"
    );

    // Keyframes every metre of the path (or 10°), their clouds beside them.
    let m = map.manifest();
    let path: f64 = (1..sim.len())
        .map(|k| {
            let (a, b) = (
                sim.pose_at(sim.gt_stamp(k - 1)),
                sim.pose_at(sim.gt_stamp(k)),
            );
            (b.translation.vector - a.translation.vector).norm()
        })
        .sum();
    assert!(
        m.keyframes >= 2 && (m.keyframes as f64) <= path + 2.0,
        "{} keyframes over {path:.1} m",
        m.keyframes
    );
    for row in map.keyframes() {
        assert!(map.keyframe_file(row.keyframe, "ply").is_file());
    }

    // A crop keeps what lies in its box, and is itself a map.
    let b = m.bounds.unwrap();
    let half = Bounds {
        min: b.min,
        max: [(b.min[0] + b.max[0]) / 2.0, b.max[1], b.max[2]],
    };
    let cropped = map.crop(&half, &dir.path().join("crop")).unwrap();
    let reopened = Map::open(&dir.path().join("crop")).unwrap();
    assert!(cropped.points > 0 && cropped.points < m.points);
    assert!(reopened
        .cloud()
        .unwrap()
        .iter()
        .all(|r| f64::from(r[0]) <= half.max[0]));
    assert!(reopened
        .keyframes()
        .iter()
        .all(|k| k.pose.translation.x <= half.max[0]));
    // The PCD export holds the same points as the PLY.
    let pcd = dir.path().join("all.pcd");
    assert_eq!(map.export(&pcd, None).unwrap(), m.points);
    let options = keylo::io::folder::fields::FieldOptions::default();
    let read = keylo::io::pcd::read_pcd(&pcd, 0.0, &options).unwrap();
    assert_eq!(read.points.len(), m.points);
}

/// Mean NEES of the pose graph's keyframe edges against the ground truth, for raw KISS-ICP
/// on `frames` frames of `scene` (seed `seed`), with covariances from `noise`.
fn edge_nees(
    scene: SceneKind,
    seed: u64,
    frames: usize,
    noise: keylo::map::covariance::NoiseModel,
) -> Vec<f64> {
    let sim = Simulator::new(&SimConfig {
        scene,
        frames,
        seed,
        ..SimConfig::default()
    })
    .unwrap();
    let (registry, config) = common::resolve("[registrar]\nkind = \"kiss-icp\"\n");
    let mut odometry = keylo::Odometry::build(&config, &registry).unwrap();
    let mut graph = keylo::map::PoseGraph::new(1.0, 10.0, noise);
    let mut truth = Vec::new();
    for k in 0..sim.len() {
        let r = odometry.process(&sim.frame(k)).unwrap();
        if graph.add(&r) {
            truth.push(sim.relative_pose_at(sim.gt_stamp(k)));
        }
    }
    graph
        .edges()
        .map(|(a, b, measured, cov)| {
            let e = keylo::registration::se3::log(
                &(measured.inverse() * (truth[a].inverse() * truth[b])),
            );
            (e.transpose() * cov.try_inverse().unwrap() * e)[(0, 0)]
        })
        .collect()
}

/// The pose graph's edge covariances against ground truth on seeds the noise model was not
/// fitted on (seeds 0–4): a calibrated covariance gives a mean NEES of 6. keylo's plain
/// `σ² H⁻¹` is far too confident.
#[test]
fn the_pose_graph_covariance_is_calibrated_on_seeds_it_was_not_fitted_on() {
    use keylo::map::covariance::NoiseModel;
    let fitted = NoiseModel::fitted("kiss-icp").unwrap();
    for scene in [SceneKind::Lab, SceneKind::Road] {
        let fit: Vec<f64> = (5..7)
            .flat_map(|seed| edge_nees(scene, seed, 50, fitted))
            .collect();
        let plain: Vec<f64> = edge_nees(scene, 5, 50, NoiseModel::plain(0.03));
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        println!(
            "{scene:?}: {} edges, mean NEES {:.2} (σ²H⁻¹ alone: {:.0})",
            fit.len(),
            mean(&fit),
            mean(&plain)
        );
        assert!(fit.len() >= 8, "{scene:?}: {} edges", fit.len());
        // Summing the frames' covariances along an edge treats their errors as independent;
        // odometry's consecutive errors partly cancel, so edges come out conservative.
        assert!(
            (1.5..18.0).contains(&mean(&fit)),
            "{scene:?}: mean NEES {}",
            mean(&fit)
        );
        assert!(
            mean(&plain) > 18.0,
            "{scene:?}: σ²H⁻¹ alone gives {}",
            mean(&plain)
        );
    }
}
