//! Frame pixels selected by keypoint windows.

use std::collections::BTreeMap;

use keylo_core::{ChannelFeatures, FrameFeatures, LidarFrame};

use super::Mapping;
use crate::FeaturesError;
use keylo_core::pixel_math::{clip_rows, cover, stride_pixel, window, wrap_col};

/// Row-major indices (ascending, deduplicated) of the valid, positive-range frame pixels
/// that the keypoint windows of every image select.
pub fn select_pixels(
    frame: &LidarFrame,
    features: &FrameFeatures,
    sizes: &BTreeMap<String, usize>,
    mapping: Mapping,
) -> Result<Vec<usize>, FeaturesError> {
    let mut mask = vec![false; frame.rows * frame.cols];
    for image in &features.per_image {
        if image.keypoints.is_empty() {
            continue;
        }
        let name = image.image.name();
        let k = *sizes.get(&name).ok_or_else(|| {
            FeaturesError::BadInput(format!(
                "downsampler.windows has no window size for image `{name}` (it has: {}); \
                 add it, e.g. windows = {{ {name:?} = 5 }}",
                sizes.keys().cloned().collect::<Vec<_>>().join(", ")
            ))
        })?;
        mark_windows(frame, image, k, mapping, &mut mask)?;
    }
    Ok(mask
        .iter()
        .enumerate()
        .filter(|(i, m)| **m && frame.valid[*i] && frame.range[*i] > 0.0)
        .map(|(i, _)| i)
        .collect())
}

fn mark_windows(
    frame: &LidarFrame,
    features: &ChannelFeatures,
    k: usize,
    mapping: Mapping,
    mask: &mut [bool],
) -> Result<(), FeaturesError> {
    let image = &features.image;
    let (w, h) = (image.width, image.height);
    let (rows, cols) = (frame.rows, frame.cols);
    for kp in &features.keypoints {
        let inside = kp.x.is_finite()
            && kp.y.is_finite()
            && kp.x > -1.0
            && kp.y > -1.0
            && kp.x < w as f32
            && kp.y < h as f32;
        if !inside {
            return Err(FeaturesError::BadInput(format!(
                "keypoint ({}, {}) lies outside image `{}` of {w}x{h} pixels",
                kp.x,
                kp.y,
                image.name()
            )));
        }
        let (x0, x1) = window(kp.x, k);
        let (y0, y1) = window(kp.y, k);
        match mapping {
            Mapping::Exact => {
                let (c0, c1) = cover(x0, x1, cols, w);
                let (r0, r1) = cover(y0, y1, rows, h);
                let Some((r0, r1)) = clip_rows(r0, r1, rows) else {
                    continue;
                };
                for r in r0..=r1 {
                    for c in c0..=c1 {
                        mask[r * cols + wrap_col(c, cols)] = true;
                    }
                }
            }
            Mapping::UpstreamStride => {
                for y in y0..=y1 {
                    let r = stride_pixel(y, rows, h);
                    if r < 0 || r >= rows as i64 {
                        continue;
                    }
                    for x in x0..=x1 {
                        let c = wrap_col(stride_pixel(x, cols, w), cols);
                        mask[r as usize * cols + c] = true;
                    }
                }
            }
        }
    }
    Ok(())
}
