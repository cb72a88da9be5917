//! Localisation through the C API: a map saved with `keylo_pipeline_save_map`, then a
//! pipeline whose config names `[registrar] kind = "localise"`; `keylo_pipeline_stats` gives
//! each frame's fit, and a pose set far off is reported as not tracking.

mod common;

use std::ffi::CString;

use common::{error, pipeline, push, stats_out};
use keylo_capi::ffi::*;

const FRAMES: usize = 6;

fn stats(p: *mut KeyloPipeline) -> KeyloFrameStats {
    let mut s = stats_out();
    // SAFETY: a pipeline and a stats struct with its size set.
    assert_eq!(unsafe { keylo_pipeline_stats(p, &mut s) }, KEYLO_CAPI_OK);
    s
}

fn pose_x(p: *mut KeyloPipeline) -> f64 {
    let mut pose = KeyloPose {
        size: std::mem::size_of::<KeyloPose>() as u32,
        ..KeyloPose::default()
    };
    // SAFETY: a pipeline and a pose struct with its size set.
    assert_eq!(unsafe { keylo_pipeline_pose(p, &mut pose) }, KEYLO_CAPI_OK);
    pose.translation[0]
}

#[test]
fn a_localise_pipeline_reports_each_frames_fit() {
    let dir = tempfile::tempdir().unwrap();
    let map_dir = dir.path().join("map");
    let odometry = pipeline(c"[registrar]\nkind = \"kiss-icp\"\nmax_range = 30.0\n");
    let path = CString::new(map_dir.to_str().unwrap()).unwrap();
    // SAFETY: NUL-terminated strings.
    let rc =
        unsafe { keylo_pipeline_save_map(odometry, path.as_ptr(), c"voxel_size = 0.1".as_ptr()) };
    assert_eq!(rc, KEYLO_CAPI_OK, "{}", error(odometry));
    let mut mapped = Vec::new();
    for k in 0..FRAMES {
        assert_eq!(push(odometry, k), KEYLO_CAPI_OK, "{}", error(odometry));
        let s = stats(odometry);
        assert!(
            !s.localised && s.fitness == 0.0 && !s.tracking,
            "odometry has no fit"
        );
        mapped.push(pose_x(odometry));
    }
    // SAFETY: a pipeline.
    assert_eq!(
        unsafe { keylo_pipeline_finish_map(odometry) },
        KEYLO_CAPI_OK
    );
    // SAFETY: a pipeline, freed once.
    unsafe { keylo_pipeline_free(odometry) };

    let toml = CString::new(format!(
        "[registrar]\nkind = \"localise\"\nmap = \"{}\"\nvoxel_size = 0.3\n",
        map_dir.display()
    ))
    .unwrap();
    let localiser = pipeline(&toml);
    for (k, x) in mapped.iter().enumerate().take(FRAMES - 1) {
        assert_eq!(push(localiser, k), KEYLO_CAPI_OK, "{}", error(localiser));
        let s = stats(localiser);
        assert!(
            s.localised && s.tracking && s.fitness > 0.9,
            "frame {k}: {s:?}"
        );
        assert!((pose_x(localiser) - x).abs() < 0.02, "frame {k}");
    }
    // A pose 3.6 m off and turned 90°: not tracking, and said so.
    let mut far = [0.0; 16];
    far[1] = -1.0; // x' = -y
    far[4] = 1.0; // y' = x
    far[10] = 1.0;
    far[15] = 1.0;
    far[3] = 3.0;
    far[7] = -2.0;
    // SAFETY: 16 doubles.
    assert_eq!(
        unsafe { keylo_pipeline_set_pose(localiser, far.as_ptr()) },
        KEYLO_CAPI_OK
    );
    assert_eq!(
        push(localiser, FRAMES - 1),
        KEYLO_CAPI_OK,
        "{}",
        error(localiser)
    );
    let s = stats(localiser);
    assert!(s.localised && !s.tracking && s.fitness < 0.5, "{s:?}");
    // SAFETY: a pipeline, freed once.
    unsafe { keylo_pipeline_free(localiser) };
}
