//! `keylo_pipeline_stats` says when a frame is degenerate: too few registered points (one
//! point here), with the registrar's minimum.

mod common;

use std::ffi::c_char;

use common::{error, push};
use keylo_capi::ffi::*;

fn stats(p: *mut KeyloPipeline) -> KeyloFrameStats {
    // SAFETY: all-zero is a valid KeyloFrameStats (plain numbers and bools).
    let mut s: KeyloFrameStats = unsafe { std::mem::zeroed() };
    s.size = std::mem::size_of::<KeyloFrameStats>() as u32;
    // SAFETY: `s` is a KeyloFrameStats of the size given.
    assert_eq!(
        unsafe { keylo_pipeline_stats(p, &mut s) },
        KEYLO_CAPI_OK,
        "{}",
        error(p)
    );
    s
}

#[test]
fn a_one_point_scan_is_reported_degenerate_and_a_room_is_not() {
    let toml = c"[registrar]\nkind = \"kiss-icp\"\nmax_range = 30.0\n";
    let mut err = [0 as c_char; 256];
    // SAFETY: valid strings and buffer.
    let p = unsafe { keylo_pipeline_new(toml.as_ptr(), std::ptr::null(), err.as_mut_ptr(), 256) };
    assert!(!p.is_null());
    let one = [5.0f32, 1.0, 0.5];
    // SAFETY: three floats, no times or intensities.
    let r = unsafe {
        keylo_pipeline_push_points(p, 0.0, one.as_ptr(), std::ptr::null(), std::ptr::null(), 1)
    };
    assert_eq!(r, KEYLO_CAPI_OK, "{}", error(p));
    let s = stats(p);
    assert_eq!(s.degenerate, KEYLO_DEGENERATE_TOO_FEW_POINTS);
    assert_eq!(s.degenerate_minimum, 3);
    assert_eq!(s.registered_points, 1);
    // SAFETY: a handle keylo made.
    unsafe { keylo_pipeline_free(p) };

    // SAFETY: as above.
    let p = unsafe { keylo_pipeline_new(toml.as_ptr(), std::ptr::null(), err.as_mut_ptr(), 256) };
    for k in 0..6 {
        assert_eq!(push(p, k), KEYLO_CAPI_OK, "{}", error(p));
        let s = stats(p);
        // Frame 1 is matched against the first frame alone, whose floor rows lie 0.4 m apart:
        // no floor point has planar neighbours within a voxel edge, so the analysis sees no
        // information along z (degeneracy.csv shows the same from `keylo run`); from frame 2
        // on the map is dense enough.
        if k == 1 {
            assert_eq!(s.degenerate, KEYLO_DEGENERATE_NO_INFORMATION);
            assert_eq!(s.degenerate_directions, 1);
        } else {
            assert_eq!(s.degenerate, KEYLO_DEGENERATE_NONE, "frame {k}");
        }
    }
    // SAFETY: a handle keylo made.
    unsafe { keylo_pipeline_free(p) };
}
