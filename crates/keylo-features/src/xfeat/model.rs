//! The XFeat ONNX session: the built-in model (or a file), run on one image.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use ort::session::Session;
use ort::value::Tensor;

use super::params::{Precision, XFeatParams};
use crate::{onnx_session, FeaturesError};

/// The shipped XFeat model: the authors' export of their weights (Apache-2.0), made
/// size-agnostic by `models/xfeat/make_xfeat_onnx.py`; `models/xfeat/PROVENANCE.md`.
pub static BUILTIN_MODEL: &[u8] = include_bytes!("../../models/xfeat/xfeat.onnx");

/// The same model quantized to INT8 by `models/xfeat/quantize_xfeat.py` (`precision = "int8"`).
pub static BUILTIN_MODEL_INT8: &[u8] = include_bytes!("../../models/xfeat/xfeat_int8.onnx");

/// Dense outputs at H/8 × W/8.
pub struct RawOutput {
    /// Descriptors, `64 × hc × wc`.
    pub descriptors: Vec<f32>,
    /// Keypoint logits, `65 × hc × wc`.
    pub logits: Vec<f32>,
    /// Reliability, `hc × wc`.
    pub reliability: Vec<f32>,
    pub hc: usize,
    pub wc: usize,
}

/// A loaded model.
#[derive(Clone)]
pub struct Model {
    pub name: String,
    session: Arc<Mutex<Session>>,
}

impl Model {
    /// The model of `params` (`model_path`: `params.model` resolved against the config dir).
    pub fn load(
        params: &XFeatParams,
        model_path: Option<&std::path::Path>,
    ) -> Result<Self, FeaturesError> {
        let builtin = match params.precision {
            Precision::Fp32 => ("built-in", BUILTIN_MODEL),
            Precision::Int8 => ("built-in int8", BUILTIN_MODEL_INT8),
        };
        let name = model_path.map_or_else(|| builtin.0.to_string(), |p| p.display().to_string());
        let key = format!("xfeat {name} threads {}", params.threads);
        let session = onnx_session::shared(key, || {
            let bytes = match model_path {
                Some(p) => std::fs::read(p).map_err(|e| FeaturesError::BadParameter {
                    field: "model".into(),
                    value: format!("\"{}\"", p.display()),
                    expected: format!("a readable XFeat ONNX file ({e})"),
                })?,
                None => builtin.1.to_vec(),
            };
            let what = format!("XFeat model `{name}`");
            onnx_session::builder(&params.onnxruntime, params.threads, false, &what)?
                .commit_from_memory(&bytes)
                .map_err(|e| {
                    FeaturesError::Unavailable(format!("{what}: cannot load the ONNX model: {e}"))
                })
        })?;
        Ok(Self { name, session })
    }

    /// Runs the network on a grey image (`h × w` values in [0, 1], given as three equal
    /// channels, as XFeat takes colour and averages it).
    pub fn run(&self, grey: &[f32], h: usize, w: usize) -> Result<RawOutput, FeaturesError> {
        let fail = |what: &str, e: String| {
            FeaturesError::Unavailable(format!("XFeat model `{}`: {what}: {e}", self.name))
        };
        let mut input = Vec::with_capacity(3 * h * w);
        for _ in 0..3 {
            input.extend_from_slice(grey);
        }
        let tensor = Tensor::from_array(([1usize, 3, h, w], input))
            .map_err(|e| fail("input tensor", e.to_string()))?;
        let mut session = self.session.lock().unwrap_or_else(|p| p.into_inner());
        let outputs = session
            .run(ort::inputs![tensor])
            .map_err(|e| fail("inference", e.to_string()))?;
        let (hc, wc) = (h / 8, w / 8);
        let mut by_channels = BTreeMap::new();
        for (_, value) in outputs.iter() {
            let (shape, data) = value
                .try_extract_tensor::<f32>()
                .map_err(|e| fail("output", e.to_string()))?;
            let dims: Vec<i64> = shape.iter().copied().collect();
            if dims.len() != 4 || dims[0] != 1 || dims[2] as usize != hc || dims[3] as usize != wc {
                return Err(fail(
                    "output",
                    format!("shape {dims:?}, expected [1, C, {hc}, {wc}]"),
                ));
            }
            by_channels.insert(dims[1], data.to_vec());
        }
        match (
            by_channels.remove(&64),
            by_channels.remove(&65),
            by_channels.remove(&1),
        ) {
            (Some(descriptors), Some(logits), Some(reliability)) => Ok(RawOutput {
                descriptors,
                logits,
                reliability,
                hc,
                wc,
            }),
            _ => Err(fail(
                "outputs",
                "expected descriptors [1, 64, H/8, W/8], keypoint logits [1, 65, H/8, W/8] and \
                 reliability [1, 1, H/8, W/8] (XFeat's backbone without post-processing)"
                    .into(),
            )),
        }
    }
}
