//! The facade's frame-by-frame API (issue 21): a [`keylo::Frontend`] built from TOML and from
//! typed configs runs the same, per-frame output carries keypoints with descriptors and 3-D
//! points, a user-defined registrar plugs in, and bad point arrays are errors naming them.

mod common;

use keylo::config::RawConfig;
use keylo::registration::downsample::PassthroughConfig;
use keylo::registration::KissIcpConfig;
use keylo::{Frontend, LidarFrame, PointCloud, Pose, Registrar, Registration};

/// `n` frames of the simulated lab (OS1-64, 512 columns) and their ground truth.
fn lab(n: usize) -> (Vec<LidarFrame>, Vec<Pose>) {
    simulate(&format!(
        "scene = 'lab'\nsensor = 'os1-64'\ncolumns = 512\nframes = {n}\n"
    ))
}

/// The frames of a simulator `[source]` (its keys) and their ground truth.
fn simulate(keys: &str) -> (Vec<LidarFrame>, Vec<Pose>) {
    let (registry, config) = common::resolve(&format!("[source]\nkind = 'sim'\n{keys}"));
    let mut source = keylo::build_source(&config, &registry).unwrap();
    let frames: Vec<LidarFrame> = std::iter::from_fn(|| source.next_frame())
        .map(|f| f.unwrap())
        .collect();
    (frames, source.ground_truth().unwrap().poses)
}

fn poses(frontend: &mut Frontend, frames: &[LidarFrame]) -> Vec<Pose> {
    frames
        .iter()
        .map(|f| *frontend.push_frame(f).unwrap().pose())
        .collect()
}

#[test]
fn toml_and_typed_configs_build_the_same_pipeline() {
    let (frames, truth) = lab(6);
    let toml = "[downsampler]\nkind = 'passthrough'\n\n[registrar]\nkind = 'kiss-icp'\n\
                max_range = 30.0\nvoxel_size = 0.25\n";
    let mut from_toml = Frontend::from_toml(toml, ".").unwrap();
    let mut typed = Frontend::builder()
        .downsampler(&PassthroughConfig::default())
        .registrar(&KissIcpConfig {
            max_range: 30.0,
            voxel_size: 0.25,
            ..Default::default()
        })
        .build()
        .unwrap();
    let a = poses(&mut from_toml, &frames);
    let b = poses(&mut typed, &frames);
    assert_eq!(a, b, "bit-identical poses");
    // And they follow the simulator (relative to the first frame).
    let truth_last = truth[0].inverse() * truth[5];
    let err = (a[5].translation.vector - truth_last.translation.vector).norm();
    assert!(err < 0.05, "{err} m off the ground truth");
    assert_eq!(typed.frames(), 6);
    let out = typed.last().unwrap();
    assert_eq!(out.result.index, frames[5].index);
    // Per-frame covariance from the degeneracy analysis: finite, positive diagonal.
    let cov = out
        .covariance(0.02)
        .expect("the lab constrains every direction");
    assert!((0..6).all(|i| cov[i][i] > 0.0 && cov[i][i].is_finite()));
    // The local map is the registrar's, in the world frame.
    assert_eq!(typed.local_map().len(), out.result.map_points);
    // Reset: frame count, output and map forgotten; the next frame is the identity.
    typed.reset().unwrap();
    assert!(typed.last().is_none() && typed.frames() == 0);
    let first = *typed.push_frame(&frames[3]).unwrap().pose();
    assert_eq!(first, Pose::identity());
}

/// A registrar of the test's own: the pose is the frame count along x.
struct Counter(f64);

impl Registrar for Counter {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, keylo::CoreError> {
        self.0 += 1.0;
        Ok(Registration {
            stamp: cloud.timestamp,
            pose: Pose::translation(self.0, 0.0, 0.0),
            source_points: cloud.len(),
            iterations: 1,
            converged: true,
            degeneracy: None,
            fit: None,
        })
    }

    fn map_size(&self) -> usize {
        0
    }
}

#[test]
fn a_registrar_of_your_own_plugs_in() {
    let mut frontend = Frontend::builder()
        .registrar_instance(Box::new(Counter(0.0)))
        .build()
        .unwrap();
    let points = [[1.0, 2.0, 0.5], [3.0, -1.0, 0.2], [-2.0, 0.5, 1.0]];
    for k in 0..3 {
        frontend.push_points(k as f64 * 0.1, &points, None).unwrap();
    }
    let out = frontend.last().unwrap();
    assert_eq!(out.pose().translation.x, 3.0);
    assert_eq!(out.result.cloud_points, 3);
    assert!(out.degeneracy().is_none() && out.covariance(0.02).is_none());
    // Hooks the registrar does not offer are errors naming them.
    let err = frontend.set_motion_prior(&Pose::identity()).unwrap_err();
    assert!(err.to_string().contains("set_motion_prior"), "{err}");
}

#[test]
fn bad_point_arrays_are_errors_naming_them() {
    let mut frontend = Frontend::builder().build().unwrap();
    let points = [[1.0, 2.0, 0.5], [3.0, -1.0, 0.2]];
    let err = frontend
        .push_points(0.0, &points, Some(&[0.0]))
        .unwrap_err();
    let text = err.to_string();
    assert!(text.contains("`times` has 1 values for 2 points"), "{text}");
    assert!(matches!(
        err,
        keylo::Error::TimesLength {
            times: 1,
            points: 2,
            ..
        }
    ));
    // NaN points are dropped; a scan of nothing but NaN has no point to register: KISS-ICP
    // predicts (upstream's behaviour), reporting 0 registered points.
    let nan = [[f64::NAN, 0.0, 0.0], [0.0, f64::INFINITY, 1.0]];
    let out = frontend.push_points(0.0, &nan, None).unwrap();
    assert_eq!(
        (out.result.cloud_points, out.result.registered_points),
        (0, 0)
    );
    // Time must go forward.
    let err = frontend.push_points(0.0, &points, None).unwrap_err();
    assert!(
        err.to_string().contains("not after the previous frame"),
        "{err}"
    );
    // A bad `[source.projection]` names the table.
    let err = Frontend::from_toml("[source.projection]\nrows = 'many'\n", ".")
        .err()
        .unwrap();
    assert!(err.to_string().contains("source.projection.rows"), "{err}");
    // A value the projection cannot take is a typed error naming the key.
    let err = Frontend::from_toml("[source.projection]\nrows = 0\n", ".")
        .err()
        .unwrap();
    assert!(matches!(err, keylo::Error::Projection(_)), "{err}");
    assert!(err.to_string().contains("projection.rows = 0"), "{err}");
    // A ring beyond the grid's rows: the frame and the ring are named.
    let mut rings =
        Frontend::from_toml("[source.projection]\nrows = 4\nrow_from = 'ring'\n", ".").unwrap();
    let cloud = keylo::io::cloud::RawCloud {
        timestamp: 0.0,
        points: vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        ring: Some(vec![0, 9]),
        ..Default::default()
    };
    let err = rings.push_cloud(&cloud).err().unwrap();
    assert!(
        matches!(
            err,
            keylo::Error::Points {
                frame: 0,
                source: keylo::io::cloud::CloudError::RingOutOfRange { ring: 9, rows: 4 }
            }
        ),
        "{err}"
    );
    // So does a bad key of a stage, with its path.
    let raw = RawConfig::parse("t", "[registrar]\nkind = 'kiss-icp'\nmax_rnage = 3\n").unwrap();
    let err = Frontend::from_raw(raw, keylo::registry()).err().unwrap();
    assert!(err.to_string().contains("max_rnage"), "{err}");
}

/// Keypoints, descriptors and their 3-D points come out with every frame.
#[cfg(feature = "opencv")]
#[test]
fn keypoints_come_out_with_descriptors_and_points() {
    use keylo::features::classic::OrbParams;
    use keylo::features::image::LidarImageConfig;
    use keylo::features::neighbourhood::NeighbourhoodConfig;

    let (frames, _) = simulate("scene = 'road'\nframes = 2\n");
    let mut frontend = Frontend::builder()
        .image(&LidarImageConfig {
            images: vec!["signal".into(), "range".into()],
            ..Default::default()
        })
        .detector(&OrbParams::default())
        .descriptor(&OrbParams::default())
        .downsampler(&NeighbourhoodConfig::default())
        .registrar(&KissIcpConfig {
            max_range: 30.0,
            ..Default::default()
        })
        .build()
        .unwrap();
    frontend.push_frame(&frames[0]).unwrap();
    let out = frontend.push_frame(&frames[1]).unwrap();
    assert_eq!(out.features.per_image.len(), 2);
    let keypoints: Vec<_> = out.keypoints().collect();
    assert_eq!(keypoints.len(), out.result.keypoints);
    assert!(keypoints.len() > 30, "{} keypoints", keypoints.len());
    let with_point = keypoints.iter().filter(|k| k.point.is_some()).count();
    // Keypoints over the sky (no return) have no point; most are over something.
    assert!(
        with_point * 2 > keypoints.len(),
        "{with_point} of {}",
        keypoints.len()
    );
    let frame = &frames[1];
    // The same points the hybrid registrar's keypoint matching uses.
    let described = keylo::FrameKeypoints::from_features(frame, &out.features);
    assert_eq!(described.len(), with_point);
    for k in &keypoints {
        // ORB: binary descriptors, one row per keypoint.
        let dim = k.image.descriptors.as_ref().map(|d| d.dim);
        match k.descriptor() {
            Some(keylo::DescriptorRow::Binary(row)) => assert_eq!(Some(row.len()), dim),
            other => panic!("{other:?}"),
        }
        // The point is one of the frame's (or between four of them): within the sensor's range
        // and near the range of the pixel under the keypoint.
        let Some(p) = k.point else { continue };
        let (col, row) = (
            (f64::from(k.keypoint.x) * frame.cols as f64 / k.image.image.width as f64) as usize,
            (f64::from(k.keypoint.y) * frame.rows as f64 / k.image.image.height as f64) as usize,
        );
        let range = p.coords.norm();
        assert!(range.is_finite() && range > 0.1 && range < 100.0, "{p}");
        let pixel = row.min(frame.rows - 1) * frame.cols + col.min(frame.cols - 1);
        if frame.valid[pixel] {
            let near = (range - f64::from(frame.range[pixel])).abs();
            assert!(near < 0.5 * range, "{near} m from the pixel's range");
        }
    }
}
