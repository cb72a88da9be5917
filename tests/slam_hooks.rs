//! The SLAM hooks of `Odometry` (issue 21): an external motion prior that rescues a frame the
//! constant-velocity model loses, `reset`, `set_pose`, the local map, and bad priors.

mod common;

use keylo::{LidarFrame, Odometry, Pose};
use nalgebra::{Translation3, UnitQuaternion};

/// Moving frames of the simulated corridor at a brisk 0.96 m per frame with a 20 m range, where
/// the walls constrain motion along the corridor only weakly (no motion distortion, full
/// speed from the start; the `ideal` appearance the test was set up on).
const SOURCE: &str = "[source]\nkind = 'sim'\nscene = 'corridor'\nsensor = 'os1-64'\n\
                      columns = 512\nmotion_distortion = false\nstart_ramp_s = 0\n\
                      speed_scale = 8\nmax_range_m = 20\nappearance = 'ideal'\n";

fn resolve(extra: &str) -> (keylo::Registry, keylo::config::PipelineConfig) {
    common::resolve(&format!("{SOURCE}{extra}"))
}

/// `moving` frames of the corridor, then the sensor stops dead: `stopped` more frames seeing
/// exactly what the last moving frame saw (time goes on).
fn sudden_stop(moving: usize, stopped: usize) -> (Vec<LidarFrame>, Vec<Pose>) {
    let (registry, config) = resolve(&format!("frames = {moving}\n"));
    let mut source = keylo::build_source(&config, &registry).unwrap();
    let mut frames: Vec<LidarFrame> = std::iter::from_fn(|| source.next_frame())
        .map(|f| f.unwrap())
        .collect();
    let truth = source.ground_truth().unwrap();
    let mut poses: Vec<Pose> = truth.poses.clone();
    let (last, last_pose) = (frames[moving - 1].clone(), poses[moving - 1]);
    for k in 1..=stopped {
        let mut f = last.clone();
        let dt = 0.1 * k as f64;
        f.index += k as u64;
        f.timestamp += dt;
        f.column_times.iter_mut().for_each(|t| *t += dt);
        if let Some(times) = f.pixel_times.as_mut() {
            times.iter_mut().for_each(|t| *t += dt);
        }
        frames.push(f);
        poses.push(last_pose);
    }
    (frames, poses)
}

fn odometry() -> Odometry {
    let (registry, config) = resolve("");
    Odometry::build(&config, &registry).unwrap()
}

/// Runs the frames; from frame `prior_from` on, each gets the true motion as its prior.
/// Returns the estimated poses relative to the first, and how many frames failed.
fn run(frames: &[LidarFrame], truth: &[Pose], prior_from: Option<usize>) -> (Vec<Pose>, usize) {
    let mut odo = odometry();
    let (mut poses, mut failed) = (Vec::new(), 0);
    for (i, f) in frames.iter().enumerate() {
        if prior_from.is_some_and(|from| i >= from) {
            let delta = truth[i - 1].inverse() * truth[i];
            odo.set_motion_prior(&delta).unwrap();
        }
        match odo.process(f) {
            Ok(r) => poses.push(r.pose),
            Err(_) => failed += 1,
        }
    }
    (poses, failed)
}

/// How far the estimate moved after frame `from` (the truth stands still there).
fn drift_after(est: &[Pose], from: usize) -> f64 {
    (est[from].inverse() * est[est.len() - 1])
        .translation
        .vector
        .norm()
}

#[test]
fn an_imu_like_prior_rescues_a_sudden_stop() {
    let (frames, truth) = sudden_stop(15, 8);
    let (cv, cv_failed) = run(&frames, &truth, None);
    let (imu, imu_failed) = run(&frames, &truth, Some(15));
    assert_eq!(imu_failed, 0);
    assert_eq!(imu.len(), frames.len());
    let step = (truth[13].inverse() * truth[14]).translation.vector.norm();
    let cv_error = if cv.len() == frames.len() {
        drift_after(&cv, 14)
    } else {
        f64::INFINITY
    };
    let imu_error = drift_after(&imu, 14);
    println!(
        "speed {step:.2} m/frame, then a dead stop; movement estimated after the stop: \
         constant velocity {cv_error:.3} m ({cv_failed} failed frames), with the prior \
         {imu_error:.4} m"
    );
    // Measured: constant velocity 0.359 m, with the prior 0.0084 m.
    assert!(imu_error < 0.05, "{imu_error}");
    assert!(
        cv_failed > 0 || (cv_error > 0.2 && cv_error > 10.0 * imu_error),
        "constant velocity should lose the stop: {cv_error} m, {cv_failed} failed"
    );
}

#[test]
fn reset_set_pose_and_the_local_map() {
    let (frames, _) = sudden_stop(4, 0);
    let mut odo = odometry();
    assert!(odo.local_map().is_empty());
    for f in &frames[..3] {
        odo.process(f).unwrap();
    }
    assert!(!odo.local_map().is_empty());
    // A correction from a back end: the next pose continues from it.
    let shift = Pose::from_parts(
        Translation3::new(10.0, 0.0, 0.0),
        UnitQuaternion::identity(),
    );
    odo.set_pose(&shift).unwrap();
    let after = odo.process(&frames[3]).unwrap().pose;
    assert!(after.translation.x > 5.0, "{after}");
    // Reset: a new start, and any time stamp is accepted again (here: an earlier frame).
    odo.reset().unwrap();
    assert!(odo.local_map().is_empty());
    let first = odo.process(&frames[0]).unwrap();
    assert_eq!(first.pose, Pose::identity());
}

#[test]
fn bad_priors_are_errors_and_ndt_offers_the_hooks_too() {
    let mut odo = odometry();
    let mut bad = Pose::identity();
    bad.translation.x = f64::NAN;
    let e = odo.set_motion_prior(&bad).unwrap_err().to_string();
    assert!(e.contains("not a rigid transform"), "{e}");
    let mut skewed = Pose::identity();
    skewed.rotation = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(2.0, 0.0, 0.0, 0.0));
    assert!(odo.set_motion_prior(&skewed).is_err());
    let far = Pose::from_parts(
        Translation3::new(50.0, 0.0, 0.0),
        UnitQuaternion::identity(),
    );
    let e = odo.set_motion_prior(&far).unwrap_err().to_string();
    assert!(e.contains("max_motion_per_frame"), "{e}");
    // NDT offers the hooks as well, with the same checks.
    let (frames, _) = sudden_stop(3, 0);
    let (registry, config) = resolve("[registrar]\nkind = 'ndt'\n");
    let mut ndt = Odometry::build(&config, &registry).unwrap();
    assert!(ndt.set_motion_prior(&far).is_err());
    for f in &frames {
        ndt.set_motion_prior(&Pose::identity()).unwrap();
        ndt.process(f).unwrap();
    }
    assert!(!ndt.local_map().is_empty());
    ndt.reset().unwrap();
    assert!(ndt.local_map().is_empty());
    assert_eq!(ndt.process(&frames[0]).unwrap().pose, Pose::identity());
}
