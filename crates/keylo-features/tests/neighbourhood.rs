//! The keypoint-neighbourhood downsampler: index mapping against a float reference, borders,
//! azimuth wrap, resize factors, times, too-few-points handling, and real Ouster frames.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use keylo_core::{
    BeamGeometry, Channel, ChannelFeatures, Downsampler, FrameFeatures, Image, Keypoint, LidarFrame,
};
use keylo_features::neighbourhood::{
    select_pixels, window, KeypointNeighbourhood, Mapping, NeighbourhoodConfig, TooFew, Windows,
};
use nalgebra::Point3;
use proptest::prelude::*;

fn frame(rows: usize, cols: usize) -> LidarFrame {
    let beams = Arc::new(BeamGeometry {
        model: "test".into(),
        altitude_deg: vec![0.0; rows],
        azimuth_deg: vec![0.0; rows],
        origin_to_beam_mm: 0.0,
        columns_per_frame: cols,
        frame_rate_hz: 10.0,
        column_lag_by_row: Vec::new(),
    });
    let mut f = LidarFrame::empty(3, 100.0, rows, cols, beams);
    f.column_times = (0..cols).map(|c| 100.0 + c as f64 * 1e-4).collect();
    for i in 0..rows * cols {
        f.valid[i] = true;
        f.range[i] = 5.0;
        f.points[i] = Point3::new(i as f32, 1.0, 2.0);
    }
    f
}

fn features(image_w: usize, image_h: usize, channel: Channel, kps: &[(f32, f32)]) -> FrameFeatures {
    let image = Image::new_gray(image_w, image_h, channel);
    FrameFeatures {
        per_image: vec![ChannelFeatures {
            image,
            keypoints: kps
                .iter()
                .map(|&(x, y)| Keypoint {
                    x,
                    y,
                    ..Keypoint::default()
                })
                .collect(),
            descriptors: None,
        }],
    }
}

fn sizes(sig: usize, rng: usize) -> BTreeMap<String, usize> {
    Windows::Preset(format!("{sig}_{rng}")).sizes().unwrap()
}

/// Reference, in floats: grid pixel (r, c) is selected when its footprint, mapped into image
/// coordinates, overlaps the footprint of the keypoint's window (columns modulo the width).
fn reference(
    rows: usize,
    cols: usize,
    w: usize,
    h: usize,
    k: usize,
    x: f32,
    y: f32,
) -> BTreeSet<usize> {
    let (x0, x1) = window(x, k);
    let (y0, y1) = window(y, k);
    // Window footprint in image edge coordinates.
    let (wx0, wx1) = (x0 as f64, (x1 + 1) as f64);
    let (wy0, wy1) = (y0 as f64, (y1 + 1) as f64);
    let (sx, sy) = (w as f64 / cols as f64, h as f64 / rows as f64);
    let overlaps = |a0: f64, a1: f64, b0: f64, b1: f64| a0 < b1 - 1e-9 && b0 < a1 - 1e-9;
    let mut out = BTreeSet::new();
    for r in 0..rows {
        let (py0, py1) = (r as f64 * sy, (r + 1) as f64 * sy);
        if !overlaps(py0, py1, wy0, wy1) {
            continue;
        }
        for c in 0..cols {
            let (px0, px1) = (c as f64 * sx, (c + 1) as f64 * sx);
            let wraps = [-(w as f64), 0.0, w as f64];
            if wraps.iter().any(|o| overlaps(px0 + o, px1 + o, wx0, wx1)) {
                out.insert(r * cols + c);
            }
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    /// Exact mapping equals the float reference for any keypoint (borders and the azimuth
    /// seam included), any window size and any resize factor.
    #[test]
    fn exact_mapping_matches_reference(
        rows in 8usize..80, cols in 16usize..300,
        w in 8usize..300, h in 4usize..80,
        k in 1usize..9, fx in 0.0f32..1.0, fy in 0.0f32..1.0,
    ) {
        let (x, y) = (fx * (w as f32 - 1.0), fy * (h as f32 - 1.0));
        let f = frame(rows, cols);
        let feats = features(w, h, Channel::Signal, &[(x, y)]);
        let got: BTreeSet<usize> = select_pixels(&f, &feats, &sizes(k, 1), Mapping::Exact)
            .unwrap()
            .into_iter()
            .collect();
        prop_assert_eq!(got, reference(rows, cols, w, h, k, x, y));
    }
}

#[test]
fn halved_image_window_selects_2k_by_2k_points() {
    let f = frame(128, 2048);
    let feats = features(1024, 64, Channel::Signal, &[(500.0, 30.0)]);
    let exact = select_pixels(&f, &feats, &sizes(5, 5), Mapping::Exact).unwrap();
    assert_eq!(exact.len(), 100);
    // Window 498..=502 x 28..=32 → columns 996..=1005, rows 56..=65.
    assert_eq!(exact.first(), Some(&(56 * 2048 + 996)));
    assert_eq!(exact.last(), Some(&(65 * 2048 + 1005)));
    let stride = select_pixels(&f, &feats, &sizes(5, 5), Mapping::UpstreamStride).unwrap();
    assert_eq!(stride.len(), 25);
    assert!(stride.contains(&(56 * 2048 + 996)));
    assert!(!stride.contains(&(57 * 2048 + 997)));
}

#[test]
fn windows_wrap_in_azimuth_and_clip_at_the_top() {
    let f = frame(64, 1024);
    let feats = features(1024, 64, Channel::Signal, &[(0.2, 0.0)]);
    let px = select_pixels(&f, &feats, &sizes(5, 5), Mapping::Exact).unwrap();
    let cols: BTreeSet<usize> = px.iter().map(|i| i % 1024).collect();
    let rows: BTreeSet<usize> = px.iter().map(|i| i / 1024).collect();
    assert_eq!(cols, BTreeSet::from([1022, 1023, 0, 1, 2]));
    assert_eq!(rows, BTreeSet::from([0, 1, 2]));
}

#[test]
fn overlapping_windows_are_deduplicated_and_invalid_points_dropped() {
    let mut f = frame(64, 1024);
    let feats = features(1024, 64, Channel::Range, &[(100.0, 10.0), (101.0, 10.0)]);
    let px = select_pixels(&f, &feats, &sizes(3, 5), Mapping::Exact).unwrap();
    assert_eq!(
        px.len(),
        6 * 5,
        "range window 5, two keypoints one column apart"
    );
    f.valid[10 * 1024 + 100] = false;
    f.range[10 * 1024 + 101] = 0.0;
    let px = select_pixels(&f, &feats, &sizes(3, 5), Mapping::Exact).unwrap();
    assert_eq!(px.len(), 28);
}

#[test]
fn downsampled_cloud_keeps_point_times() {
    let f = frame(64, 1024);
    let feats = features(1024, 64, Channel::Signal, &[(700.0, 20.0)]);
    let mut d = KeypointNeighbourhood::new(NeighbourhoodConfig {
        windows: Windows::Preset("5_5".into()),
        min_points: 1,
        ..NeighbourhoodConfig::default()
    })
    .unwrap();
    let cloud = d.downsample(&f, &feats).unwrap();
    assert_eq!(cloud.len(), 25);
    let times = cloud.times.as_ref().unwrap();
    for (p, t) in cloud.points.iter().zip(times) {
        let i = p.x as usize;
        assert!((t - (f.column_times[i % 1024] - f.timestamp)).abs() < 1e-12);
    }
}

#[test]
fn too_few_points_is_an_error_or_falls_back() {
    let f = frame(64, 1024);
    let none = features(1024, 64, Channel::Signal, &[]);
    let mut strict = KeypointNeighbourhood::new(NeighbourhoodConfig::default()).unwrap();
    let e = strict.downsample(&f, &none).unwrap_err().to_string();
    assert!(
        e.contains("too few points") && e.contains("min_points"),
        "{e}"
    );
    let mut lenient = KeypointNeighbourhood::new(NeighbourhoodConfig {
        on_too_few: TooFew::AllPoints,
        ..NeighbourhoodConfig::default()
    })
    .unwrap();
    assert_eq!(lenient.downsample(&f, &none).unwrap().len(), 64 * 1024);
}

#[test]
fn missing_window_and_bad_keypoints_are_clear_errors() {
    let f = frame(64, 1024);
    let feats = features(1024, 64, Channel::NearIr, &[(5.0, 5.0)]);
    let e = select_pixels(&f, &feats, &sizes(4, 7), Mapping::Exact)
        .unwrap_err()
        .to_string();
    assert!(e.contains("near-ir") && e.contains("windows"), "{e}");
    let feats = features(1024, 64, Channel::Signal, &[(f32::NAN, 5.0)]);
    let e = select_pixels(&f, &feats, &sizes(4, 7), Mapping::Exact)
        .unwrap_err()
        .to_string();
    assert!(e.contains("outside image"), "{e}");
}

#[test]
fn real_frames_shrink_and_stay_deterministic() {
    use keylo_core::{ImageBuilder, Registry};
    use keylo_features::image::{LidarImageBuilder, LidarImageConfig};
    let frames = common::os0_frames();
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let factory = registry.detectors.get("akaze").unwrap();
    let params = factory.resolve(&toml::Table::new()).unwrap();
    let mut akaze = factory.build(&params, &Default::default()).unwrap();
    let mut builder = LidarImageBuilder::new(LidarImageConfig {
        images: vec!["signal".into(), "range".into()],
        ..LidarImageConfig::default()
    })
    .unwrap();
    let mut down = KeypointNeighbourhood::new(NeighbourhoodConfig::default()).unwrap();
    for f in &frames {
        let mut feats = FrameFeatures::default();
        for image in builder.build(f).unwrap() {
            let keypoints = akaze.detect(&image).unwrap();
            feats.per_image.push(ChannelFeatures {
                image,
                keypoints,
                descriptors: None,
            });
        }
        let cloud = down.downsample(f, &feats).unwrap();
        let again = down.downsample(f, &feats).unwrap();
        assert_eq!(cloud, again);
        let valid = f.valid_count();
        assert!(
            cloud.len() * 5 < valid && cloud.len() > 100,
            "frame {}: {} of {valid} points",
            f.index,
            cloud.len()
        );
    }
}

#[test]
fn matched_mode_keeps_keypoints_matching_the_previous_frame() {
    use keylo_core::{ImageBuilder, Registry};
    use keylo_features::image::{LidarImageBuilder, LidarImageConfig};
    use keylo_features::neighbourhood::KeypointUse;
    let frames = common::os0_frames();
    assert!(frames.len() >= 2);
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let factory = registry.detectors.get("akaze").unwrap();
    let params = factory
        .resolve(&"describe = true".parse().unwrap())
        .unwrap();
    let mut akaze = factory.build(&params, &Default::default()).unwrap();
    let mut builder = LidarImageBuilder::new(LidarImageConfig::default()).unwrap();
    let config = NeighbourhoodConfig {
        windows: Windows::Preset("1_1".into()),
        keypoints: KeypointUse::Matched,
        min_points: 1,
        ..NeighbourhoodConfig::default()
    };
    let mut matched = KeypointNeighbourhood::new(config.clone()).unwrap();
    let mut all = KeypointNeighbourhood::new(NeighbourhoodConfig {
        keypoints: KeypointUse::All,
        ..config
    })
    .unwrap();
    let mut counts = Vec::new();
    for f in &frames[..2] {
        let image = builder.build(f).unwrap().remove(0);
        let (keypoints, descriptors) = akaze.detect_and_describe(&image).unwrap();
        let feats = FrameFeatures {
            per_image: vec![ChannelFeatures {
                image,
                keypoints,
                descriptors,
            }],
        };
        counts.push((
            matched.downsample(f, &feats).unwrap().len(),
            all.downsample(f, &feats).unwrap().len(),
        ));
    }
    // First frame: nothing to match against, every keypoint counts.
    assert_eq!(counts[0].0, counts[0].1);
    // Second: only the best 90 % of the matches.
    assert!(counts[1].0 < counts[1].1 && counts[1].0 > 0, "{counts:?}");

    let bare = features(1024, 64, Channel::Signal, &[(5.0, 5.0)]);
    let e = KeypointNeighbourhood::new(NeighbourhoodConfig {
        keypoints: KeypointUse::Matched,
        ..NeighbourhoodConfig::default()
    })
    .unwrap()
    .downsample(&frames[0], &bare)
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("needs descriptors") && e.contains("describe = true"),
        "{e}"
    );
}
