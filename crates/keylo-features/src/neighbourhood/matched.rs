//! `keypoints = "matched"`: keep only the keypoints that match the previous frame's, as the
//! paper's published AKAZE path does (brute force, sorted by distance, best fraction kept).

use std::collections::BTreeMap;

use keylo_core::{ChannelFeatures, Descriptors, FrameFeatures, Keypoint};

use crate::matching::cross_checked;
use crate::FeaturesError;

/// The previous frame's descriptors per image name, and the matching rule.
pub struct MatchedFilter {
    fraction: f64,
    previous: BTreeMap<String, Descriptors>,
}

impl MatchedFilter {
    /// Keeps the best `fraction` (0–1] of the matches.
    pub fn new(fraction: f64) -> Self {
        Self {
            fraction,
            previous: BTreeMap::new(),
        }
    }

    /// `features` with every image's keypoints reduced to those matching the previous
    /// frame's descriptors of the same image (all keypoints on an image's first frame); the
    /// current descriptors become the previous ones.
    pub fn filter(&mut self, features: &FrameFeatures) -> Result<FrameFeatures, FeaturesError> {
        let mut out = FrameFeatures::default();
        for image in &features.per_image {
            let name = image.image.name();
            let Some(current) = image.descriptors.as_ref() else {
                return Err(FeaturesError::BadInput(format!(
                    "downsampler.keypoints = \"matched\" needs descriptors, and image `{name}` \
                     has none: set `describe = true` on the detector or configure [descriptor]"
                )));
            };
            let keypoints = match self.previous.get(&name) {
                Some(prev) => self.matched(&image.keypoints, current, prev)?,
                None => image.keypoints.clone(),
            };
            self.previous.insert(name, current.clone());
            out.per_image.push(ChannelFeatures {
                image: image.image.clone(),
                keypoints,
                descriptors: None,
            });
        }
        Ok(out)
    }

    fn matched(
        &self,
        keypoints: &[Keypoint],
        current: &Descriptors,
        previous: &Descriptors,
    ) -> Result<Vec<Keypoint>, FeaturesError> {
        let list = cross_checked(current, previous, false)?;
        let keep = ((list.len() as f64) * self.fraction).round() as usize;
        Ok(list
            .iter()
            .take(keep)
            .filter_map(|m| keypoints.get(m.query).copied())
            .collect())
    }
}
