//! `plugin:loam-edges`: LOAM-style edge keypoints on the range image.
//!
//! Along each image row, the curvature of pixel `i` is LOAM's smoothness
//! `c = |Σ_{0<|j|≤k} (r_{i+j} − r_i)| / (2k · r_i)`: large at depth discontinuities, corners and
//! thin structures (poles, door frames), small on planes. Windows touching an invalid pixel
//! (0) are skipped. The image is cut into `cell_width × cell_height` buckets and each keeps its
//! `per_cell` highest-curvature pixels above `threshold`, so keypoints spread over the scan
//! instead of piling up on one wall edge. keylo's built-in detectors (ORB, FAST, AKAZE,
//! SuperPoint) look for intensity texture; this one looks for geometry.
//!
//! Build with `cargo build -p loam-edges --release`; use with
//! `[detector] kind = "plugin:loam-edges"` on `[image] images = ["range"]`.

use keylo_core::{CoreError, Detector, Image, Keypoint};
use serde::Deserialize;

/// Parameters (`[detector]` keys).
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Params {
    /// Pixels on each side of the curvature window (LOAM: 5).
    pub half_window: usize,
    /// Bucket width, pixels.
    pub cell_width: usize,
    /// Bucket height, pixels.
    pub cell_height: usize,
    /// Keypoints kept per bucket, best first.
    pub per_cell: usize,
    /// Smallest curvature kept (LOAM's edge threshold: 0.1 on metric range).
    pub threshold: f32,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            half_window: 5,
            cell_width: 32,
            cell_height: 4,
            per_cell: 2,
            threshold: 0.1,
        }
    }
}

/// The detector.
pub struct LoamEdges {
    params: Params,
    /// Reused per-bucket candidate list.
    candidates: Vec<(f32, usize, usize)>,
}

impl keylo_plugin::FromConfig for LoamEdges {
    type Params = Params;
    fn from_params(params: Params) -> Result<Self, String> {
        if params.half_window == 0 || params.half_window > 32 {
            return Err(format!(
                "half_window = {}: expected 1..=32",
                params.half_window
            ));
        }
        if params.cell_width == 0 || params.cell_height == 0 || params.per_cell == 0 {
            return Err("cell_width, cell_height and per_cell must be at least 1".into());
        }
        if params.threshold.is_nan() || params.threshold < 0.0 {
            return Err(format!("threshold = {}: expected >= 0", params.threshold));
        }
        Ok(Self {
            params,
            candidates: Vec::new(),
        })
    }
}

impl LoamEdges {
    /// LOAM curvature at `(x, y)`, `None` where the window leaves the row or holds no return.
    fn curvature(&self, image: &Image, x: usize, y: usize) -> Option<f32> {
        let k = self.params.half_window;
        if x < k || x + k >= image.width {
            return None;
        }
        let row = &image.data[y * image.stride..];
        let at = |i: usize| row.get(i * image.channels).copied().map(f32::from);
        let r = at(x).filter(|&v| v > 0.0)?;
        let mut sum = 0.0;
        for i in x - k..=x + k {
            let v = at(i).filter(|&v| v > 0.0)?;
            sum += v - r;
        }
        Some(sum.abs() / (2.0 * k as f32 * r))
    }
}

impl Detector for LoamEdges {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        let p = self.params.clone();
        if image.data.len() < image.height * image.stride {
            return Err(CoreError::stage(
                "detector",
                "loam-edges: image buffer too small",
            ));
        }
        let mut out = Vec::new();
        for cy in (0..image.height).step_by(p.cell_height) {
            for cx in (0..image.width).step_by(p.cell_width) {
                let mut cands = std::mem::take(&mut self.candidates);
                cands.clear();
                for y in cy..(cy + p.cell_height).min(image.height) {
                    for x in cx..(cx + p.cell_width).min(image.width) {
                        if let Some(c) = self.curvature(image, x, y).filter(|&c| c >= p.threshold) {
                            cands.push((c, x, y));
                        }
                    }
                }
                cands.sort_by(|a, b| b.0.total_cmp(&a.0));
                out.extend(cands.iter().take(p.per_cell).map(|&(c, x, y)| Keypoint {
                    x: x as f32,
                    y: y as f32,
                    size: (2 * p.half_window + 1) as f32,
                    angle: -1.0,
                    response: c,
                    octave: 0,
                    class_id: 0,
                }));
                self.candidates = cands;
            }
        }
        Ok(out)
    }
}

keylo_plugin::export_plugin! {
    name: "loam-edges",
    version: env!("CARGO_PKG_VERSION"),
    detector: LoamEdges => "LOAM-style edge keypoints: range-image curvature, bucketed",
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_plugin::FromConfig;

    #[test]
    fn a_step_in_range_is_an_edge_and_a_plane_is_not() {
        let mut img = Image::new_gray(64, 4, keylo_core::Channel::Range);
        for y in 0..4 {
            for x in 0..64 {
                img.data[y * 64 + x] = if x < 40 { 50 } else { 200 };
            }
        }
        let mut d = LoamEdges::from_params(Params::default()).unwrap();
        let kps = d.detect(&img).unwrap();
        assert!(!kps.is_empty());
        assert!(kps.iter().all(|k| (34.0..46.0).contains(&k.x)), "{kps:?}");
        // Two buckets across, one down, two keypoints each.
        assert!(kps.len() <= 4, "{}", kps.len());
    }

    #[test]
    fn bad_parameters_are_refused() {
        let p = Params {
            half_window: 0,
            ..Params::default()
        };
        assert!(LoamEdges::from_params(p).is_err());
    }
}
