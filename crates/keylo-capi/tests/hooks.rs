//! The SLAM hooks of the C API: motion prior, set_pose and reset, and their bad input (a
//! matrix that is not rigid, NULL arguments).

mod common;

use std::ffi::c_char;

use common::{error, push};
use keylo_capi::ffi::*;

const IDENTITY: [f64; 16] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

#[test]
fn hooks_work_and_refuse_what_is_not_rigid() {
    let toml = c"[registrar]\nkind = \"kiss-icp\"\nmax_range = 30.0\n";
    let mut err = [0 as c_char; 256];
    // SAFETY: valid strings and buffer.
    let p = unsafe { keylo_pipeline_new(toml.as_ptr(), std::ptr::null(), err.as_mut_ptr(), 256) };
    assert!(!p.is_null());
    for k in 0..3 {
        assert_eq!(push(p, k), KEYLO_CAPI_OK, "{}", error(p));
    }
    // A prior of 0.1 m along x, as the room moves by.
    let mut step = IDENTITY;
    step[3] = 0.1;
    // SAFETY: 16 doubles.
    assert_eq!(
        unsafe { keylo_pipeline_set_motion_prior(p, step.as_ptr()) },
        KEYLO_CAPI_OK
    );
    assert_eq!(push(p, 3), KEYLO_CAPI_OK, "{}", error(p));
    // Not rigid: scaled, a bad last row, NaN, NULL.
    let mut scaled = IDENTITY;
    scaled[0] = 2.0;
    let mut last_row = IDENTITY;
    last_row[12] = 1.0;
    let mut nan = IDENTITY;
    nan[3] = f64::NAN;
    for m in [scaled, last_row, nan] {
        // SAFETY: 16 doubles.
        let r = unsafe { keylo_pipeline_set_motion_prior(p, m.as_ptr()) };
        assert_eq!(r, KEYLO_CAPI_ERROR);
        assert!(error(p).contains("not a rigid transform"), "{}", error(p));
    }
    // SAFETY: NULL is refused, not read.
    assert_eq!(
        unsafe { keylo_pipeline_set_pose(p, std::ptr::null()) },
        KEYLO_CAPI_ERROR
    );
    assert!(error(p).contains("NULL"), "{}", error(p));
    // set_pose, then the pose of the next frame continues from it.
    let mut moved = IDENTITY;
    moved[3] = 100.0;
    // SAFETY: 16 doubles.
    assert_eq!(
        unsafe { keylo_pipeline_set_pose(p, moved.as_ptr()) },
        KEYLO_CAPI_OK
    );
    assert_eq!(push(p, 4), KEYLO_CAPI_OK, "{}", error(p));
    let mut pose = KeyloPose {
        size: std::mem::size_of::<KeyloPose>() as u32,
        ..KeyloPose::default()
    };
    // SAFETY: `pose` is writable and its size is set.
    assert_eq!(unsafe { keylo_pipeline_pose(p, &mut pose) }, KEYLO_CAPI_OK);
    assert!(pose.translation[0] > 99.0, "{:?}", pose.translation);
    // Per-frame statistics, in a struct that starts with its size.
    let mut stats = common::stats_out();
    // SAFETY: `stats` is writable and its size is set.
    assert_eq!(
        unsafe { keylo_pipeline_stats(p, &mut stats) },
        KEYLO_CAPI_OK,
        "{}",
        error(p)
    );
    assert_eq!(stats.frame, 4);
    assert!(
        stats.cloud_points > 1000 && stats.registered_points > 0,
        "{stats:?}"
    );
    assert!(stats.register_ms > 0.0 && stats.map_points > 0, "{stats:?}");
    // An older, shorter struct gets only its fields; a size too small is refused.
    let mut old = KeyloFrameStats {
        size: 16,
        ..KeyloFrameStats::default()
    };
    // SAFETY: 16 writable bytes at least.
    assert_eq!(unsafe { keylo_pipeline_stats(p, &mut old) }, KEYLO_CAPI_OK);
    assert_eq!((old.size, old.frame, old.cloud_points), (16, 4, 0));
    old.size = 4;
    // SAFETY: as above.
    assert_eq!(
        unsafe { keylo_pipeline_stats(p, &mut old) },
        KEYLO_CAPI_ERROR
    );
    assert!(error(p).contains("out->size"), "{}", error(p));
    // Reset: no pose until the next frame, which starts at the identity.
    // SAFETY: a live pipeline.
    assert_eq!(unsafe { keylo_pipeline_reset(p) }, KEYLO_CAPI_OK);
    let mut none = KeyloPose {
        size: std::mem::size_of::<KeyloPose>() as u32,
        ..KeyloPose::default()
    };
    // SAFETY: `none` is writable and its size is set.
    assert_eq!(
        unsafe { keylo_pipeline_pose(p, &mut none) },
        KEYLO_CAPI_ERROR
    );
    assert_eq!(push(p, 0), KEYLO_CAPI_OK, "{}", error(p));
    // A NULL pipeline is an error for every hook.
    // SAFETY: NULL is checked first.
    unsafe {
        assert_eq!(keylo_pipeline_reset(std::ptr::null_mut()), KEYLO_CAPI_ERROR);
        assert_eq!(
            keylo_pipeline_set_motion_prior(std::ptr::null_mut(), IDENTITY.as_ptr()),
            KEYLO_CAPI_ERROR
        );
        keylo_pipeline_free(p);
    }
}

/// A call made while another thread is inside a call on the same pipeline gets
/// `KEYLO_CAPI_BUSY` and does nothing: never a race. A caller that retries gets through.
#[test]
fn two_threads_on_one_pipeline_get_busy_not_a_race() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let toml = c"[registrar]\nkind = \"kiss-icp\"\nmax_range = 30.0\n";
    // SAFETY: valid strings; no error buffer.
    let p = unsafe { keylo_pipeline_new(toml.as_ptr(), std::ptr::null(), std::ptr::null_mut(), 0) };
    assert!(!p.is_null());
    let handle = p as usize;
    let done = std::sync::Arc::new(AtomicBool::new(false));
    let flag = std::sync::Arc::clone(&done);
    let worker = std::thread::spawn(move || {
        let p = handle as *mut KeyloPipeline;
        let (mut codes, mut refused) = (Vec::new(), 0);
        for k in 0..20 {
            loop {
                match push(p, k) {
                    KEYLO_CAPI_BUSY => refused += 1,
                    code => {
                        codes.push(code);
                        break;
                    }
                }
                std::thread::yield_now();
            }
        }
        flag.store(true, Ordering::SeqCst);
        (codes, refused)
    });
    let (mut busy, mut other) = (0, Vec::new());
    while !done.load(Ordering::SeqCst) {
        let mut stats = common::stats_out();
        // SAFETY: a live pipeline; `stats` writable.
        match unsafe { keylo_pipeline_stats(p, &mut stats) } {
            KEYLO_CAPI_BUSY => busy += 1,
            code => other.push(code),
        }
        std::thread::yield_now();
    }
    let (codes, refused) = worker.join().unwrap();
    assert!(codes.iter().all(|&c| c == KEYLO_CAPI_OK), "{codes:?}");
    // Between the worker's calls the pipeline is free: OK, or ERROR before its first frame.
    let expected = |c: &i32| *c == KEYLO_CAPI_OK || *c == KEYLO_CAPI_ERROR;
    assert!(other.iter().all(expected), "{other:?}");
    let total = busy + refused;
    assert!(
        total > 0,
        "neither thread found it busy ({} other calls)",
        other.len()
    );
    // SAFETY: no call is running any more.
    unsafe { keylo_pipeline_free(p) };
}

/// GICP comes from the registry like every registrar: both modes register, follow
/// `set_pose` (frame to frame: the previous scan moves with the pose; local map: the map
/// stays, so a pose far from it gets an error until it is set back) and `reset`, and a bad
/// parameter is refused with its key in the message.
#[test]
fn gicp_is_taken_like_any_registrar() {
    for toml in [
        c"[registrar]\nkind = \"gicp\"\nvoxel_size = 0.3\nmax_range = 30.0\n",
        c"[registrar]\nkind = \"gicp\"\nvoxel_size = 0.3\nmode = \"frame-to-frame\"\n",
    ] {
        let mut err = [0 as c_char; 256];
        // SAFETY: valid strings and buffer.
        let p =
            unsafe { keylo_pipeline_new(toml.as_ptr(), std::ptr::null(), err.as_mut_ptr(), 256) };
        assert!(!p.is_null());
        for k in 0..3 {
            assert_eq!(push(p, k), KEYLO_CAPI_OK, "{}", error(p));
        }
        let mut pose = KeyloPose {
            size: std::mem::size_of::<KeyloPose>() as u32,
            ..KeyloPose::default()
        };
        // SAFETY: `pose` is writable and its size is set.
        assert_eq!(unsafe { keylo_pipeline_pose(p, &mut pose) }, KEYLO_CAPI_OK);
        // The sensor moves 0.1 m a frame along x: at 0.2 m by frame 2.
        assert!(
            (pose.translation[0] - 0.2).abs() < 0.01,
            "{:?}",
            pose.translation
        );
        // set_pose moves the odometry, not its map: 100 m away no map point is near, so
        // the frame is an error naming that (KISS-ICP would predict), and the state is kept.
        let mut moved = IDENTITY;
        moved[3] = 100.0;
        // SAFETY: 16 doubles; a live pipeline.
        unsafe {
            assert_eq!(keylo_pipeline_set_pose(p, moved.as_ptr()), KEYLO_CAPI_OK);
        }
        let code = push(p, 3);
        let frame_to_frame = toml.to_string_lossy().contains("frame-to-frame");
        if frame_to_frame {
            assert_eq!(code, KEYLO_CAPI_OK, "{}", error(p));
            // SAFETY: as above.
            assert_eq!(unsafe { keylo_pipeline_pose(p, &mut pose) }, KEYLO_CAPI_OK);
            assert!(pose.translation[0] > 99.0, "{:?}", pose.translation);
        } else {
            assert_eq!(code, KEYLO_CAPI_ERROR);
            assert!(error(p).contains("too few to register"), "{}", error(p));
            let mut back = IDENTITY;
            back[3] = 0.2;
            // SAFETY: as above.
            unsafe {
                assert_eq!(keylo_pipeline_set_pose(p, back.as_ptr()), KEYLO_CAPI_OK);
            }
            assert_eq!(push(p, 3), KEYLO_CAPI_OK, "{}", error(p));
            // SAFETY: as above.
            assert_eq!(unsafe { keylo_pipeline_pose(p, &mut pose) }, KEYLO_CAPI_OK);
            assert!(
                (pose.translation[0] - 0.3).abs() < 0.01,
                "{:?}",
                pose.translation
            );
        }
        // SAFETY: a live pipeline.
        assert_eq!(unsafe { keylo_pipeline_reset(p) }, KEYLO_CAPI_OK);
        assert_eq!(push(p, 0), KEYLO_CAPI_OK, "{}", error(p));
        // SAFETY: no call is running.
        unsafe { keylo_pipeline_free(p) };
    }
    let bad = c"[registrar]\nkind = \"gicp\"\nk_correspondences = 1\n";
    let mut err = [0 as c_char; 256];
    // SAFETY: valid strings and buffer.
    let p = unsafe { keylo_pipeline_new(bad.as_ptr(), std::ptr::null(), err.as_mut_ptr(), 256) };
    assert!(p.is_null());
    // SAFETY: the buffer is NUL-terminated by keylo_pipeline_new.
    let text = unsafe { std::ffi::CStr::from_ptr(err.as_ptr()) }.to_string_lossy();
    assert!(text.contains("k_correspondences"), "{text}");
}
