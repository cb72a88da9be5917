//! Known-answer checks of the metrics on synthetic images: identical consecutive images match
//! completely, identity transforms repeat every keypoint, the authors' scaling homography
//! loses what the corrected one keeps, and a shifted image is explained by one homography.

use keylo_core::{BuildContext, Registry};
use keylo_kpeval::sweep::{run_sweep, SweepGrid, SweepOptions};
use keylo_kpeval::{evaluate, parse_combos, ComboSet, EvalOptions, EvalSpec, Plane, Row};

fn registry() -> Registry {
    let mut r = Registry::default();
    keylo_features::register(&mut r);
    r
}

/// A 512×64 textured image: bright and dark rectangles on a mid-grey ground, shifted by `dx`.
fn textured(dx: usize) -> Plane {
    let (cols, rows) = (512usize, 64usize);
    let mut data = vec![110u8; cols * rows];
    let mut seed = 12345u64;
    let mut next = |n: u64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) % n
    };
    for _ in 0..60 {
        let (x, y) = (
            next(cols as u64 - 20) as usize,
            next(rows as u64 - 12) as usize,
        );
        let (w, h) = (4 + next(14) as usize, 3 + next(8) as usize);
        let v = if next(2) == 0 { 230 } else { 20 };
        for yy in y..y + h {
            for xx in x..x + w {
                let sx = xx + dx;
                if sx < cols {
                    data[yy * cols + sx] = v;
                }
            }
        }
    }
    Plane {
        rows,
        cols,
        data,
        label: format!("shift {dx}"),
    }
}

fn spec_at_own_size() -> EvalSpec {
    let mut spec = EvalSpec::default();
    spec.image.width = 0;
    spec.image.height = 0;
    spec
}

fn run(planes: &[Plane], combos: &str, spec: &EvalSpec) -> Vec<Row> {
    let r = registry();
    let combos = parse_combos(&ComboSet::parse(combos), &r).unwrap();
    let opts = EvalOptions {
        jobs: 1,
        skip_unavailable: false,
        progress: None,
    };
    let res = evaluate(planes, &combos, spec, &r, &BuildContext::default(), &opts).unwrap();
    assert!(res.failed.is_empty(), "{:?}", res.failed);
    res.rows
}

#[test]
fn identical_images_match_completely_and_identity_transforms_repeat_everything() {
    let planes = vec![textured(0), textured(0)];
    let mut spec = spec_at_own_size();
    spec.metrics.rotation_deg = 0.0;
    spec.metrics.scale = 1.0;
    spec.metrics.blur_kernel = 1;
    let rows = run(&planes, "SIFT_SIFT,SHITOMASI_BRIEF,AKAZE_AKAZE", &spec);
    assert_eq!(rows.len(), 6);
    for r in &rows {
        assert!(r.keypoints >= 5, "{r:?}");
        assert_eq!(r.robustness_rotation, Some(1.0), "{r:?}");
        assert_eq!(r.robustness_scaling_corrected, Some(1.0), "{r:?}");
        assert_eq!(r.robustness_blur, Some(1.0), "{r:?}");
    }
    for r in rows.iter().filter(|r| r.index == 1) {
        assert_eq!(r.matches, Some(r.described), "{r:?}");
        assert_eq!(r.match_ratio, Some(1.0), "{r:?}");
        assert_eq!(r.match_score, Some(1.0), "{r:?}");
        assert!(r.time_ms.unwrap() >= r.detect_ms, "{r:?}");
    }
    // The first image has no pair: no match figures, no time.
    for r in rows.iter().filter(|r| r.index == 0) {
        assert_eq!((r.matches, r.time_ms, r.match_ratio), (None, None, None));
    }
}

#[test]
fn a_shifted_image_is_explained_by_one_homography_and_the_papers_scaling_h_loses_keypoints() {
    let planes = vec![textured(0), textured(6)];
    let rows = run(&planes, "SHITOMASI_BRIEF", &spec_at_own_size());
    let pair = &rows[1];
    // Most matches are the true ones: a 6 px translation, one homography.
    assert!(pair.match_ratio.unwrap() > 0.6, "{pair:?}");
    assert!(pair.match_score.unwrap() > 0.9, "{pair:?}");
    assert!(pair.distinctiveness.unwrap() > 0.5, "{pair:?}");
    // Scaling ×2: the corrected homography finds most corners again, the authors' (shifted by
    // half the image) almost none.
    let (paper, corrected) = (
        pair.robustness_scaling.unwrap(),
        pair.robustness_scaling_corrected.unwrap(),
    );
    assert!(corrected > 0.6, "{pair:?}");
    assert!(paper < 0.3 && paper < corrected, "{pair:?}");
    // Shi-Tomasi corners survive a 45° rotation on the enlarged canvas.
    assert!(pair.robustness_rotation.unwrap() > 0.5, "{pair:?}");
}

#[test]
fn detector_figures_are_shared_by_its_combinations_and_jobs_do_not_change_results() {
    let planes = vec![textured(0), textured(3), textured(7)];
    let spec = spec_at_own_size();
    let rows = run(&planes, "FAST_BRIEF,FAST_SIFT", &spec);
    for i in 0..3 {
        let a: Vec<&Row> = rows.iter().filter(|r| r.index == i).collect();
        assert_eq!(a.len(), 2);
        assert_eq!(a[0].keypoints, a[1].keypoints);
        assert_eq!(a[0].robustness_rotation, a[1].robustness_rotation);
    }
    let r = registry();
    let combos = parse_combos(&ComboSet::parse("FAST_BRIEF,ORB_ORB"), &r).unwrap();
    let go = |jobs| {
        let opts = EvalOptions {
            jobs,
            skip_unavailable: false,
            progress: None,
        };
        let res = evaluate(&planes, &combos, &spec, &r, &BuildContext::default(), &opts).unwrap();
        let mut v: Vec<_> = res
            .rows
            .iter()
            .map(|r| (r.combo.clone(), r.index, r.keypoints, r.matches, r.inliers))
            .collect();
        v.sort();
        v
    };
    assert_eq!(go(1), go(2));
}

#[test]
fn too_few_images_and_an_unbuildable_named_combination_are_errors() {
    let r = registry();
    let combos = parse_combos(&ComboSet::parse("SURF_SURF"), &r).unwrap();
    let opts = EvalOptions {
        jobs: 1,
        skip_unavailable: false,
        progress: None,
    };
    let spec = spec_at_own_size();
    let e = evaluate(
        &[textured(0)],
        &combos,
        &spec,
        &r,
        &BuildContext::default(),
        &opts,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("at least 2"), "{e}");
    let planes = [textured(0), textured(1)];
    let e = evaluate(&planes, &combos, &spec, &r, &BuildContext::default(), &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("SURF_SURF") && e.contains("nonfree"), "{e}");
}

#[test]
fn a_sweep_resumes_from_its_csv_and_gives_the_same_results() {
    let dir = tempfile::tempdir().unwrap();
    let planes = vec![textured(0), textured(4)];
    let r = registry();
    let combos = parse_combos(&ComboSet::parse("SIFT_SIFT,SHITOMASI_BRIEF"), &r).unwrap();
    let grid = SweepGrid {
        interpolations: vec![
            keylo_features::image::Interpolation::Linear,
            keylo_features::image::Interpolation::Nearest,
        ],
        widths: vec![256, 512],
        heights: vec![64],
    };
    let opts = SweepOptions {
        jobs: 2,
        skip_unavailable: false,
        store: dir.path().join("sweep.csv"),
        progress: None,
        only: None,
        timed: None,
    };
    let spec = EvalSpec::default();
    let sweep = || {
        run_sweep(
            &planes,
            &combos,
            &spec,
            &grid,
            &r,
            &BuildContext::default(),
            &opts,
        )
    };
    let go = || sweep().unwrap();
    let first = go();
    assert!(first.failed.is_empty(), "{:?}", first.failed);
    assert_eq!(first.results.len(), 4 * 2);
    assert_eq!((first.tasks_run, first.tasks_resumed), (8, 0));
    assert!(
        first
            .results
            .iter()
            .all(|c| c.mean("keypoints").is_some_and(|k| k > 0.0)),
        "{:?}",
        first.results
    );
    let again = go();
    assert_eq!((again.tasks_run, again.tasks_resumed), (0, 8));
    let key = |v: &[keylo_kpeval::sweep::CellResult]| {
        v.iter()
            .map(|c| {
                (
                    c.interpolation.clone(),
                    c.width,
                    c.combo.clone(),
                    c.mean("keypoints"),
                    c.mean("match_ratio").map(|x| (x * 1e9).round()),
                )
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(key(&first.results), key(&again.results));
    // A CSV of something else is refused, not mixed with.
    std::fs::write(&opts.store, "a,b,c\n1,2,3\n").unwrap();
    let e = sweep().unwrap_err().to_string();
    assert!(e.contains("sweep.csv") && e.contains("header"), "{e}");
}

#[test]
fn the_shipped_example_config_is_the_default() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/keypoints/paper-eval.toml"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let spec = EvalSpec::from_toml(&text, path).unwrap();
    assert_eq!(spec, EvalSpec::default());
}
