//! The C API's contract on bad input: NULL, freed, twice-freed and made-up handles; structs
//! whose `size` is too small or from an older header; NaN points and point arrays of the
//! wrong shape. And the local map and covariance outputs.

mod common;

use common::{error, pipeline, push, room, stats_out};
use keylo_capi::ffi::*;

const KISS: &std::ffi::CStr = c"[registrar]\nkind = \"kiss-icp\"\nmax_range = 30.0\n";

fn pose_out() -> KeyloPose {
    KeyloPose {
        size: std::mem::size_of::<KeyloPose>() as u32,
        ..KeyloPose::default()
    }
}

#[test]
fn freed_and_made_up_handles_are_refused_not_dereferenced() {
    let p = pipeline(KISS);
    assert_eq!(push(p, 0), KEYLO_CAPI_OK, "{}", error(p));
    // SAFETY: every handle value is accepted by the contract.
    unsafe { keylo_pipeline_free(p) };
    let mut pose = pose_out();
    // SAFETY: as above; `pose` is writable.
    unsafe {
        assert_eq!(push(p, 1), KEYLO_CAPI_ERROR);
        assert_eq!(keylo_pipeline_pose(p, &mut pose), KEYLO_CAPI_ERROR);
        assert_eq!(keylo_pipeline_reset(p), KEYLO_CAPI_ERROR);
    }
    assert!(error(p).contains("already freed"), "{}", error(p));
    // Freeing twice is harmless; so is freeing NULL or a made-up handle.
    let made_up = std::ptr::without_provenance_mut::<KeyloPipeline>(0xdead_bee0);
    // SAFETY: every handle value is accepted by the contract.
    unsafe {
        keylo_pipeline_free(p);
        keylo_pipeline_free(std::ptr::null_mut());
        keylo_pipeline_free(made_up);
        assert_eq!(keylo_pipeline_reset(made_up), KEYLO_CAPI_ERROR);
    }
    assert!(error(made_up).contains("not from keylo_pipeline_new"));
    assert_eq!(error(std::ptr::null()), "pipeline is NULL");
    // A new pipeline never gets the freed handle back.
    let q = pipeline(KISS);
    assert_ne!(p, q);
    assert_eq!(push(p, 0), KEYLO_CAPI_ERROR);
    assert_eq!(push(q, 0), KEYLO_CAPI_OK, "{}", error(q));
    // SAFETY: a live handle.
    unsafe { keylo_pipeline_free(q) };
}

#[test]
fn sized_structs_take_what_the_caller_knows() {
    let p = pipeline(KISS);
    let mut pose = pose_out();
    // Before any frame: an error, not a pose.
    // SAFETY: `pose` is writable and sized.
    assert_eq!(
        unsafe { keylo_pipeline_pose(p, &mut pose) },
        KEYLO_CAPI_ERROR
    );
    assert_eq!(push(p, 0), KEYLO_CAPI_OK, "{}", error(p));
    assert_eq!(push(p, 1), KEYLO_CAPI_OK, "{}", error(p));
    // SAFETY: as above.
    assert_eq!(unsafe { keylo_pipeline_pose(p, &mut pose) }, KEYLO_CAPI_OK);
    assert_eq!(pose.size as usize, std::mem::size_of::<KeyloPose>());
    assert_eq!(pose.frames, 2);
    assert!((pose.matrix[3] - pose.translation[0]).abs() < 1e-12);
    // A size of 0 (the caller forgot it) is refused with a message naming the struct.
    let mut unset = KeyloPose::default();
    // SAFETY: writable.
    assert_eq!(
        unsafe { keylo_pipeline_pose(p, &mut unset) },
        KEYLO_CAPI_ERROR
    );
    assert!(error(p).contains("sizeof(KeyloPose)"), "{}", error(p));
    let mut d = std::mem::MaybeUninit::<KeyloDegeneracy>::zeroed();
    // SAFETY: zeroed: size 0, refused before anything is written.
    assert_eq!(
        unsafe { keylo_pipeline_degeneracy(p, d.as_mut_ptr()) },
        KEYLO_CAPI_ERROR
    );
    assert!(error(p).contains("sizeof(KeyloDegeneracy)"), "{}", error(p));
    // An input frame whose size is too small, or NULL, is refused.
    let xyz = [1.0f32, 2.0, 3.0];
    let mut frame = KeyloFrameIn {
        size: 8,
        rows: 1,
        cols: 1,
        timestamp: 5.0,
        column_times: std::ptr::null(),
        xyz: xyz.as_ptr(),
        range: std::ptr::null(),
        signal: std::ptr::null(),
        reflectivity: std::ptr::null(),
        near_ir: std::ptr::null(),
        valid: std::ptr::null(),
    };
    // SAFETY: `frame` readable; NULL checked.
    unsafe {
        assert_eq!(keylo_pipeline_push_frame(p, &frame), KEYLO_CAPI_ERROR);
        assert!(error(p).contains("sizeof(KeyloFrameIn)"), "{}", error(p));
        assert_eq!(
            keylo_pipeline_push_frame(p, std::ptr::null()),
            KEYLO_CAPI_ERROR
        );
        assert!(error(p).contains("frame is NULL"), "{}", error(p));
        frame.size = std::mem::size_of::<KeyloFrameIn>() as u32;
        // A 1x1 frame is read (and fails on its own terms, not on its layout).
        let rc = keylo_pipeline_push_frame(p, &frame);
        assert!(
            rc == KEYLO_CAPI_OK || error(p).contains("frame"),
            "{}",
            error(p)
        );
        keylo_pipeline_free(p);
    }
}

#[test]
fn nan_points_are_dropped_and_bad_arrays_refused() {
    let p = pipeline(KISS);
    let mut xyz = room(0.0);
    let n = xyz.len() / 3;
    // Every tenth point NaN or infinite: dropped, as every keylo reader drops them.
    for (i, point) in xyz.chunks_exact_mut(3).enumerate() {
        if i % 10 == 0 {
            point[i % 3] = if i % 20 == 0 { f32::NAN } else { f32::INFINITY };
        }
    }
    // SAFETY: `xyz` holds 3 * n floats.
    let rc = unsafe {
        keylo_pipeline_push_points(p, 0.0, xyz.as_ptr(), std::ptr::null(), std::ptr::null(), n)
    };
    assert_eq!(rc, KEYLO_CAPI_OK, "{}", error(p));
    let mut stats = stats_out();
    // SAFETY: writable and sized.
    assert_eq!(
        unsafe { keylo_pipeline_stats(p, &mut stats) },
        KEYLO_CAPI_OK
    );
    assert_eq!(stats.cloud_points as usize, n - n.div_ceil(10));
    // NULL points, zero points: errors naming the argument.
    // SAFETY: NULL and 0 are checked first.
    unsafe {
        let (null, no_times) = (std::ptr::null(), std::ptr::null());
        assert_eq!(
            keylo_pipeline_push_points(p, 0.1, null, no_times, null, 5),
            KEYLO_CAPI_ERROR
        );
        assert!(error(p).contains("xyz is NULL"), "{}", error(p));
        assert_eq!(
            keylo_pipeline_push_points(p, 0.1, xyz.as_ptr(), no_times, null, 0),
            KEYLO_CAPI_ERROR
        );
        assert_eq!(
            keylo_pipeline_push_points(p, 0.1, xyz.as_ptr(), no_times, null, usize::MAX),
            KEYLO_CAPI_ERROR
        );
        assert!(error(p).contains("overflows"), "{}", error(p));
        keylo_pipeline_free(p);
    }
}

#[test]
fn local_map_and_covariance_come_out() {
    let p = pipeline(KISS);
    for k in 0..4 {
        assert_eq!(push(p, k), KEYLO_CAPI_OK, "{}", error(p));
    }
    let (mut xyz, mut n) = (std::ptr::null(), 0usize);
    // SAFETY: writable out-parameters.
    assert_eq!(
        unsafe { keylo_pipeline_local_map(p, &mut xyz, &mut n) },
        KEYLO_CAPI_OK
    );
    let mut stats = stats_out();
    // SAFETY: writable and sized.
    assert_eq!(
        unsafe { keylo_pipeline_stats(p, &mut stats) },
        KEYLO_CAPI_OK
    );
    assert_eq!(n as u64, stats.map_points);
    // SAFETY: `3 * n` doubles, valid until the next call.
    let map = unsafe { std::slice::from_raw_parts(xyz, 3 * n) };
    assert!(map.iter().all(|v| v.is_finite()));
    // The room's walls are at y = ±4 (world frame = first sensor frame).
    assert!(map.chunks_exact(3).any(|q| (q[1] - 4.0).abs() < 0.01));
    let mut cov = [0.0f64; 36];
    // SAFETY: 36 writable doubles.
    let rc = unsafe { keylo_pipeline_covariance(p, 0.02, cov.as_mut_ptr()) };
    assert_eq!(rc, KEYLO_CAPI_OK, "{}", error(p));
    for i in 0..6 {
        assert!(cov[7 * i] > 0.0, "diagonal {i}: {cov:?}");
        for j in 0..6 {
            let (a, b) = (cov[6 * i + j], cov[6 * j + i]);
            assert!(
                (a - b).abs() <= 1e-9 * a.abs().max(b.abs()),
                "not symmetric"
            );
        }
    }
    // Translation standard deviations of a few millimetres at most for 2 cm noise.
    assert!(cov[0].sqrt() < 0.005 && cov[14].sqrt() < 0.005, "{cov:?}");
    // SAFETY: NULL is checked; a bad sigma is refused.
    unsafe {
        assert_eq!(
            keylo_pipeline_covariance(p, 0.02, std::ptr::null_mut()),
            KEYLO_CAPI_ERROR
        );
        assert_eq!(
            keylo_pipeline_covariance(p, -1.0, cov.as_mut_ptr()),
            KEYLO_CAPI_ERROR
        );
        assert!(error(p).contains("sigma"), "{}", error(p));
        assert_eq!(
            keylo_pipeline_local_map(p, std::ptr::null_mut(), &mut n),
            KEYLO_CAPI_ERROR
        );
        keylo_pipeline_free(p);
    }
}
