//! `superpoint`: the learned SuperPoint detector and descriptor through ONNX Runtime (`ort`).
//!
//! By default the shipped two-channel model runs (built into keylo, nothing downloaded); any
//! SuperPoint ONNX with one or two input channels loads from `model = "path.onnx"`. The
//! network's dense outputs become keypoints and 256-d unit descriptors in
//! [`decode`]; the ONNX Runtime library is found and loaded by [`runtime`].

pub mod decode;
mod input;
mod model;
mod params;
pub mod runtime;

pub use model::BUILTIN_MODEL;
pub use params::{ExecutionProvider, Nms, Precision, SuperPointParams};

use keylo_core::config::StageParams;
use keylo_core::{
    BuildContext, CoreError, Descriptor, DescriptorData, Descriptors, Detector, Image, Keypoint,
    Registry,
};

use decode::Selection;
use model::Model;

/// SuperPoint as a keylo [`Detector`] and [`Descriptor`].
pub struct SuperPoint {
    params: SuperPointParams,
    model: Model,
}

impl SuperPoint {
    /// Loads the model of `params` (a relative `model` path is resolved against the config
    /// directory of `ctx`).
    pub fn new(params: SuperPointParams, ctx: &BuildContext) -> Result<Self, crate::FeaturesError> {
        ctx.check_library("onnxruntime", &params.onnxruntime)
            .map_err(|e| crate::FeaturesError::Unavailable(e.to_string()))?;
        params.validate()?;
        let path = (!params.model.is_empty()).then(|| ctx.resolve_path(&params.model));
        let model = Model::load(&params, path.as_deref())?;
        Ok(Self { params, model })
    }

    /// Input channels of the loaded network (`None`: the model leaves it open).
    pub fn model_channels(&self) -> Option<usize> {
        self.model.channels
    }

    fn infer(
        &self,
        image: &Image,
    ) -> Result<(model::RawOutput, Vec<f32>, usize, usize), crate::FeaturesError> {
        let input = input::prepare(image, self.model.channels, &self.model.name)?;
        let (w, h) = (input.w, input.h);
        let raw = self.model.run(input.data, input.channels, h, w)?;
        let heat = decode::heatmap(&raw.scores, raw.hc, raw.wc);
        Ok((raw, heat, w, h))
    }

    fn selection(&self) -> Selection {
        Selection {
            threshold: self.params.confidence,
            nms: self.params.nms,
            nms_radius: self.params.nms_radius,
            border: self.params.border,
            max_keypoints: self.params.max_keypoints,
        }
    }

    /// Keypoints and (always) their descriptors from one pass of the network.
    pub fn run(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Descriptors), crate::FeaturesError> {
        let (raw, heat, w, h) = self.infer(image)?;
        let keypoints = decode::select(&heat, w, h, (image.width, image.height), &self.selection());
        let descriptors = describe_at(&raw, &keypoints);
        Ok((keypoints, descriptors))
    }
}

fn describe_at(raw: &model::RawOutput, keypoints: &[Keypoint]) -> Descriptors {
    let data = decode::sample_descriptors(&raw.descriptors, raw.dim, raw.hc, raw.wc, keypoints);
    Descriptors {
        rows: keypoints.len(),
        dim: raw.dim,
        data: DescriptorData::Float(data),
    }
}

impl Detector for SuperPoint {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        Ok(self.run(image).map_err(|e| e.in_stage("detector"))?.0)
    }

    fn detect_and_describe(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), CoreError> {
        let (k, d) = self.run(image).map_err(|e| e.in_stage("detector"))?;
        Ok((k, self.params.describe.then_some(d)))
    }
}

impl Descriptor for SuperPoint {
    /// SuperPoint descriptors of any keypoints (e.g. another detector's); keypoints outside
    /// the image are dropped.
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        let (raw, _, _, _) = self.infer(image).map_err(|e| e.in_stage("descriptor"))?;
        let (w, h) = (image.width as f32, image.height as f32);
        keypoints.retain(|k| {
            k.x.is_finite() && k.y.is_finite() && k.x >= 0.0 && k.y >= 0.0 && k.x < w && k.y < h
        });
        Ok(describe_at(&raw, keypoints))
    }
}

keylo_core::stage_params!(SuperPointParams => "superpoint" as DetectorParams, DescriptorParams);

/// Registers `superpoint` as a detector and a descriptor.
pub fn register(registry: &mut Registry) {
    registry.detectors.add::<SuperPointParams>(
        SuperPointParams::KIND,
        "SuperPoint keypoints + 256-d descriptors (ONNX Runtime; the shipped two-channel model by default)",
        |p, ctx| Ok(Box::new(SuperPoint::new(p, ctx).map_err(|e| e.in_stage("detector"))?)),
    );
    registry.descriptors.add::<SuperPointParams>(
        SuperPointParams::KIND,
        "SuperPoint 256-d float descriptors at any keypoints (ONNX Runtime)",
        |p, ctx| {
            Ok(Box::new(
                SuperPoint::new(p, ctx).map_err(|e| e.in_stage("descriptor"))?,
            ))
        },
    );
}
