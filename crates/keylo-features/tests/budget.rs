//! The same-budget baselines `random` and `voxel-budget` on real Ouster frames.

mod common;

use keylo_core::{ChannelFeatures, Detector, Downsampler, FrameFeatures, LidarFrame, Registry};
use keylo_features::budget::{
    RandomConfig, RandomDownsampler, VoxelBudgetConfig, VoxelBudgetDownsampler,
};
use keylo_features::image::LidarImageConfig;
use keylo_features::neighbourhood::{KeypointNeighbourhood, NeighbourhoodConfig};

fn fast_features(frame: &LidarFrame) -> FrameFeatures {
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let f = registry.detectors.get("fast").unwrap();
    let mut det: Box<dyn Detector> = f
        .build(
            &f.resolve(&"threshold = 30".parse().unwrap()).unwrap(),
            &Default::default(),
        )
        .unwrap();
    let config = LidarImageConfig {
        images: vec!["signal".into(), "range".into()],
        ..LidarImageConfig::default()
    };
    let per_image = common::images(frame, config)
        .into_iter()
        .map(|image| ChannelFeatures {
            keypoints: det.detect(&image).unwrap(),
            image,
            descriptors: None,
        })
        .collect();
    FrameFeatures { per_image }
}

#[test]
fn random_keeps_the_budget_in_scan_order_and_repeats() {
    let frames = common::os0_frames();
    let f = &frames[1];
    let mut d = RandomDownsampler::new(RandomConfig {
        points: 3000,
        ..RandomConfig::default()
    })
    .unwrap();
    let none = FrameFeatures::default();
    let a = d.downsample(f, &none).unwrap();
    assert_eq!(a.len(), 3000);
    assert_eq!(d.downsample(f, &none).unwrap(), a);
    let times = a.times.as_ref().unwrap();
    assert!(times.iter().all(|t| t.is_finite()));
}

#[test]
fn zero_points_matches_the_keypoint_windows() {
    let frames = common::os0_frames();
    let f = &frames[1];
    let feats = fast_features(f);
    let target = KeypointNeighbourhood::new(NeighbourhoodConfig::default())
        .unwrap()
        .downsample(f, &feats)
        .unwrap()
        .len();
    assert!(target > 500, "{target}");
    let random = RandomDownsampler::new(RandomConfig::default())
        .unwrap()
        .downsample(f, &feats)
        .unwrap();
    assert_eq!(random.len(), target);
    let voxel = VoxelBudgetDownsampler::new(VoxelBudgetConfig::default())
        .unwrap()
        .downsample(f, &feats)
        .unwrap();
    assert!(
        voxel.len() <= target && voxel.len() * 10 >= target * 9,
        "voxel-budget kept {} for a budget of {target}",
        voxel.len()
    );
}

#[test]
fn matching_budget_without_keypoints_is_a_clear_error() {
    let frames = common::os0_frames();
    let e = RandomDownsampler::new(RandomConfig::default())
        .unwrap()
        .downsample(&frames[1], &FrameFeatures::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("points = 0") && e.contains("[detector]"), "{e}");
}
