//! `[detector]`/`[descriptor] kind = "xfeat"`: settings, with XFeat's own defaults
//! (`detectAndCompute(top_k = 4096, detection_threshold = 0.05)`, 5×5 suppression).

use serde::{Deserialize, Serialize};

pub use crate::superpoint::Precision;
use crate::{check, FeaturesError};

/// `[detector]`/`[descriptor] kind = "xfeat"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct XFeatParams {
    /// XFeat ONNX model (input `[1, 3, H, W]` in [0, 1]; outputs the 64-d dense descriptors,
    /// the 65-channel keypoint logits and the reliability map, all at H/8 × W/8). Empty: the
    /// shipped model (the authors' weights, Apache-2.0), built into keylo.
    pub model: String,
    /// `fp32` or `int8`: which shipped model runs (`model` empty). The INT8 one: activations
    /// uint8, weights int8 per channel, the keypoint head FP32, calibrated on 100 real OS0-128
    /// signal images; 97.7 % of the FP32 keypoints within 1 px
    /// (`models/xfeat/quantize_xfeat.py` makes it).
    pub precision: Precision,
    /// Smallest keypoint heatmap value kept (XFeat's `detection_threshold`).
    pub detection_threshold: f32,
    /// Side of the square max-pool suppression window, pixels (odd; 1 turns it off).
    pub nms_kernel: usize,
    /// Most keypoints kept, best score first (XFeat's `top_k`; 0: no cap).
    pub top_k: usize,
    /// As a detector: also return the 64-d descriptors of the same pass.
    pub describe: bool,
    /// ONNX Runtime intra-op threads (0: ONNX Runtime's choice, one per core).
    pub threads: usize,
    /// The ONNX Runtime shared library; empty: found as for `superpoint`.
    pub onnxruntime: String,
}

impl Default for XFeatParams {
    fn default() -> Self {
        Self {
            model: String::new(),
            precision: Precision::Fp32,
            detection_threshold: 0.05,
            nms_kernel: 5,
            top_k: 4096,
            describe: true,
            threads: 2,
            onnxruntime: String::new(),
        }
    }
}

impl XFeatParams {
    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), FeaturesError> {
        check(
            self.detection_threshold.is_finite() && (0.0..1.0).contains(&self.detection_threshold),
            "detection_threshold",
            self.detection_threshold,
            "expected a value in [0, 1)",
        )?;
        check(
            self.nms_kernel % 2 == 1 && self.nms_kernel <= 31,
            "nms_kernel",
            self.nms_kernel,
            "expected an odd size from 1 to 31",
        )?;
        check(
            self.precision == Precision::Fp32 || self.model.is_empty(),
            "precision",
            "int8",
            "\"fp32\" with a model of your own (int8 picks the shipped INT8 model)",
        )?;
        check(
            self.threads <= 256,
            "threads",
            self.threads,
            "expected 0 to 256",
        )
    }
}
