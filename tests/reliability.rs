//! Rows of the bad-input catalogue in docs/reliability.md that concern a sequence's content
//! (time, motion, units, scale) rather than a file's bytes. Frames come from the simulator
//! (OS1-64, 512 columns: small and fast) and are edited before the pipeline sees them.

mod common;

use keylo::{CoreError, FrameResult, LidarFrame, Odometry};

const SOURCE: &str = "[source]\nkind = 'sim'\nscene = 'lab'\nsensor = 'os1-64'\ncolumns = 512\n";

fn resolve(extra: &str) -> (keylo::Registry, keylo::config::PipelineConfig) {
    common::resolve(&format!("{SOURCE}{extra}"))
}

/// `n` simulated frames of the lab.
fn frames(n: usize) -> Vec<LidarFrame> {
    let (registry, config) = resolve(&format!("frames = {n}\n"));
    let mut source = keylo::build_source(&config, &registry).unwrap();
    std::iter::from_fn(|| source.next_frame())
        .map(|f| f.unwrap())
        .collect()
}

/// The per-frame stages of a config (its `[source]` is not used).
fn odometry(extra: &str) -> Odometry {
    let (registry, config) = resolve(extra);
    Odometry::build(&config, &registry).unwrap()
}

fn run(odo: &mut Odometry, frames: &[LidarFrame]) -> Vec<Result<FrameResult, CoreError>> {
    frames.iter().map(|f| odo.process(f)).collect()
}

fn bad_frame_message(r: &Result<FrameResult, CoreError>) -> String {
    match r {
        Err(e @ CoreError::BadFrame { .. }) => e.to_string(),
        other => panic!("expected a bad frame, got {other:?}"),
    }
}

fn stage_message(r: &Result<FrameResult, CoreError>) -> String {
    match r {
        Err(e) => e.to_string(),
        Ok(r) => panic!("expected an error, got frame {}", r.index),
    }
}

#[test]
fn time_going_backwards_is_a_bad_frame_and_the_run_goes_on_after_it() {
    let mut f = frames(6);
    f[3].timestamp = f[1].timestamp;
    let results = run(&mut odometry(""), &f);
    let msg = bad_frame_message(&results[3]);
    assert!(
        msg.contains("frame 3") && msg.contains("not after"),
        "{msg}"
    );
    // The bad frame changed nothing: the frames after it register as if it were absent.
    assert!(results.iter().enumerate().all(|(i, r)| i == 3 || r.is_ok()));
    let mut without: Vec<_> = f.clone();
    without.remove(3);
    let clean = run(&mut odometry(""), &without);
    let pose = |r: &Result<FrameResult, CoreError>| r.as_ref().unwrap().pose;
    assert_eq!(pose(&results[5]), pose(&clean[4]));
}

#[test]
fn a_duplicated_frame_and_a_non_finite_timestamp_are_bad_frames() {
    let mut f = frames(4);
    f[2] = f[1].clone();
    f[2].index = 2;
    f[3].timestamp = f64::NAN;
    let results = run(&mut odometry(""), &f);
    assert!(bad_frame_message(&results[2]).contains("the same frame twice"));
    assert!(bad_frame_message(&results[3]).contains("not finite"));
}

#[test]
fn a_cloud_in_millimetres_is_refused_with_a_question_about_units() {
    let mut f = frames(2);
    for p in f.iter_mut().flat_map(|fr| fr.points.iter_mut()) {
        *p = (p.coords * 1000.0).into();
    }
    // KISS-ICP's default (`empty_frame = "predict"`, upstream's behaviour) predicts such a
    // frame and warns with the same question; `error`, and NDT, refuse it.
    let predicted = run(&mut odometry(""), &f);
    assert_eq!(
        predicted[1].as_ref().map(|r| r.registered_points).ok(),
        Some(0)
    );
    for extra in [
        "[registrar]\nempty_frame = 'error'\n",
        "[registrar]\nkind = 'ndt'\n",
    ] {
        let msg = stage_message(&run(&mut odometry(extra), &f)[0]);
        assert!(
            msg.contains("frame 0") && msg.contains("are the coordinates in metres?"),
            "{msg}"
        );
    }
}

#[test]
fn huge_coordinates_are_cropped_or_refused_never_a_panic() {
    let mut all = frames(3);
    for p in all[1].points.iter_mut() {
        p.x = 1e30;
    }
    all[2]
        .points
        .iter_mut()
        .step_by(7)
        .for_each(|p| p.x = f32::MAX);
    let results = run(&mut odometry("[registrar]\nempty_frame = 'error'\n"), &all);
    assert!(results[0].is_ok());
    assert!(stage_message(&results[1]).contains("no point within"));
    // By default the frame with nothing in range is predicted (upstream's behaviour).
    let predicted = run(&mut odometry(""), &all);
    assert_eq!(
        predicted[1].as_ref().map(|r| r.registered_points).ok(),
        Some(0)
    );
    // Some points out at f32::MAX: they are cropped, the rest registers.
    assert!(results[2].is_ok(), "{:?}", results[2].as_ref().err());
}

#[test]
fn a_single_frame_gives_a_one_pose_trajectory_and_eval_says_why_it_cannot_align() {
    let f = frames(1);
    let r = run(&mut odometry(""), &f);
    let pose = r[0].as_ref().unwrap().pose;
    assert_eq!(pose, keylo::Pose::identity());
    let mut est = keylo::Trajectory::default();
    est.push(r[0].as_ref().unwrap().stamp, pose);
    let err = keylo::eval::evaluate(&est, &est, &Default::default()).unwrap_err();
    assert!(
        err.to_string().contains("at least 3 point pairs, got 1"),
        "{err}"
    );
}

#[test]
fn a_sensor_at_rest_for_1000_frames_stays_within_a_centimetre_and_its_map_levels_off() {
    let first = frames(1).remove(0);
    let mut odo = odometry("");
    let mut map = Vec::new();
    let mut worst = 0.0f64;
    let mut drift = Vec::new();
    for i in 0..1000u64 {
        let mut f = first.clone();
        let dt = 0.1 * i as f64;
        f.index = i;
        f.timestamp += dt;
        f.column_times.iter_mut().for_each(|t| *t += dt);
        if let Some(times) = &mut f.pixel_times {
            times.iter_mut().for_each(|t| *t += dt);
        }
        let r = odo.process(&f).unwrap();
        worst = worst.max(r.pose.translation.vector.norm());
        drift.push(r.pose.translation.vector.norm());
        map.push(r.map_points);
    }
    // Measured: 2.4 mm after the first frame (the 1.5×-voxel source against the map stops
    // within KISS-ICP's convergence criterion), at most 4.6 mm, no trend; the map grows by
    // 1.4 % from frame 100 to 999 as the jitter puts points in neighbouring voxels.
    assert!(worst < 0.01, "drifted {worst} m at rest");
    let late = drift[500..].iter().sum::<f64>() / 500.0;
    assert!(late < 0.003, "mean drift over the last 500 frames {late} m");
    assert!(
        map[999] as f64 <= 1.05 * map[100] as f64,
        "map {:?}",
        [map[100], map[999]]
    );
}

#[test]
fn a_10_m_teleport_is_not_detected_by_kiss_icp_and_the_run_goes_on() {
    // Known limitation (docs/reliability.md): like upstream KISS-ICP, nothing flags a jump
    // the adaptive threshold cannot follow; the pose is wrong from there on.
    let mut f = frames(6);
    for p in f[3..].iter_mut().flat_map(|fr| fr.points.iter_mut()) {
        p.x -= 10.0;
    }
    let results = run(&mut odometry(""), &f);
    assert!(results.iter().all(|r| r.is_ok()));
    let x = |i: usize| results[i].as_ref().unwrap().pose.translation.vector.x;
    let jump = x(3) - x(2);
    assert!(jump.abs() < 5.0, "followed the teleport: {jump} m");
}
