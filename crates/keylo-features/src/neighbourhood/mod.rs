//! The paper's downsampler: the frame points under K×K windows around keypoints.

mod config;
mod matched;
mod select;

pub use config::{KeypointUse, Mapping, NeighbourhoodConfig, TooFew, Windows};
/// The index math moved to core (the pipeline maps keypoints to points with it too).
pub use keylo_core::pixel_math::{clip_rows, cover, stride_pixel, window, wrap_col};
pub use matched::MatchedFilter;
pub use select::select_pixels;

use std::collections::BTreeMap;

use keylo_core::config::StageParams;
use keylo_core::{CoreError, Downsampler, FrameFeatures, LidarFrame, PointCloud};

use crate::check;

/// `keypoint-neighbourhood`: the points of every keypoint's window, with their times.
pub struct KeypointNeighbourhood {
    config: NeighbourhoodConfig,
    sizes: BTreeMap<String, usize>,
    matched: Option<MatchedFilter>,
    /// The pixels the last frame's windows selected (all valid pixels after an
    /// `on_too_few = "all-points"` fallback).
    selected: Vec<usize>,
}

impl KeypointNeighbourhood {
    /// Checks the config.
    pub fn new(config: NeighbourhoodConfig) -> Result<Self, CoreError> {
        let sizes = config
            .windows
            .sizes()
            .map_err(|e| e.in_stage("downsampler"))?;
        check(
            config.min_points >= 1,
            "min_points",
            config.min_points,
            "expected >= 1",
        )
        .map_err(|e| e.in_stage("downsampler"))?;
        check(
            config.matched_fraction > 0.0 && config.matched_fraction <= 1.0,
            "matched_fraction",
            config.matched_fraction,
            "expected a fraction in (0, 1]",
        )
        .map_err(|e| e.in_stage("downsampler"))?;
        let matched = (config.keypoints == KeypointUse::Matched)
            .then(|| MatchedFilter::new(config.matched_fraction));
        Ok(Self {
            config,
            sizes,
            matched,
            selected: Vec::new(),
        })
    }
}

impl Downsampler for KeypointNeighbourhood {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        let filtered;
        let features = match self.matched.as_mut() {
            Some(m) => {
                filtered = m.filter(features).map_err(|e| e.in_stage("downsampler"))?;
                &filtered
            }
            None => features,
        };
        let pixels = select_pixels(frame, features, &self.sizes, self.config.mapping)
            .map_err(|e| e.in_stage("downsampler"))?;
        let mode = self.config.pixel_points;
        let selected = frame.cloud_of_selected(&pixels, mode);
        self.selected = pixels;
        if selected.len() >= self.config.min_points {
            return Ok(selected);
        }
        match self.config.on_too_few {
            TooFew::AllPoints => {
                // The pixels `LidarFrame::cloud` takes: every valid one.
                self.selected = (0..frame.rows * frame.cols)
                    .filter(|&i| frame.valid[i])
                    .collect();
                Ok(frame.cloud(mode))
            }
            TooFew::Error => Err(CoreError::BadFrame {
                frame: frame.index,
                message: format!(
                    "too few points: the keypoint windows selected {} valid points from {} \
                     keypoints, fewer than downsampler.min_points = {} (set \
                     downsampler.on_too_few = \"all-points\" to register the whole frame instead)",
                    selected.len(),
                    features.keypoint_count(),
                    self.config.min_points
                ),
            }),
        }
    }

    fn selected_pixels(&self) -> Option<&[usize]> {
        Some(&self.selected)
    }
}

keylo_core::stage_params!(NeighbourhoodConfig => "keypoint-neighbourhood" as DownsamplerParams);

/// Registers downsampler `keypoint-neighbourhood`.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.downsamplers.add::<NeighbourhoodConfig>(
        NeighbourhoodConfig::KIND,
        "the frame points under K×K windows around every keypoint (the paper's method)",
        |config, _ctx| Ok(Box::new(KeypointNeighbourhood::new(config)?)),
    );
}
