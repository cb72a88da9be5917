//! `xfeat`: XFeat (Potje, Cadar, Araujo, Martins, Nascimento, "XFeat: Accelerated Features
//! for Lightweight Image Matching", CVPR 2024) through ONNX Runtime: the authors' released
//! weights (Apache-2.0), built into keylo ([`model::BUILTIN_MODEL`]); detector and 64-d
//! descriptor, post-processed as the authors' `detectAndCompute` ([`decode`]).

pub mod decode;
mod model;
mod params;

pub use model::{BUILTIN_MODEL, BUILTIN_MODEL_INT8};
pub use params::{Precision, XFeatParams};

use keylo_core::config::StageParams;
use keylo_core::{
    BuildContext, CoreError, Descriptor, DescriptorData, Descriptors, Detector, Image, Keypoint,
    Registry,
};

use decode::Map;
use model::{Model, RawOutput};

/// Descriptor length.
const DIM: usize = 64;

keylo_core::stage_params!(XFeatParams => "xfeat" as DetectorParams, DescriptorParams);

/// XFeat as a keylo [`Detector`] and [`Descriptor`].
pub struct XFeat {
    params: XFeatParams,
    model: Model,
}

impl XFeat {
    /// Loads the model of `params` (a relative `model` path from the config's folder).
    pub fn new(params: XFeatParams, ctx: &BuildContext) -> Result<Self, crate::FeaturesError> {
        ctx.check_library("onnxruntime", &params.onnxruntime)
            .map_err(|e| crate::FeaturesError::Unavailable(e.to_string()))?;
        params.validate()?;
        let path = (!params.model.is_empty()).then(|| ctx.base_dir.join(&params.model));
        let model = Model::load(&params, path.as_deref())?;
        Ok(Self { params, model })
    }

    /// The network's dense outputs for `image` (one plane), its descriptors already
    /// unit-normalised per cell. As XFeat's `preprocess_tensor`, an image whose sides are not
    /// multiples of 32 is resized (bilinear) down to the nearest ones; the returned [`Frame`]
    /// says by how much.
    fn dense(&self, image: &Image) -> Result<(RawOutput, Frame), crate::FeaturesError> {
        if image.channels != 1 {
            return Err(crate::FeaturesError::BadInput(format!(
                "`xfeat` needs a one-plane image; image `{}` has {} planes",
                image.name(),
                image.channels
            )));
        }
        let (w, h) = (image.width, image.height);
        if image.stride < w || image.data.len() < image.stride * h {
            return Err(crate::FeaturesError::BadInput(format!(
                "image `{}`: {} bytes for {w}×{h} pixels with stride {}",
                image.name(),
                image.data.len(),
                image.stride
            )));
        }
        let (w32, h32) = (w / 32 * 32, h / 32 * 32);
        if w32 == 0 || h32 == 0 {
            return Err(crate::FeaturesError::BadInput(format!(
                "`xfeat` needs images of at least 32×32 pixels (XFeat's backbone); image `{}` \
                 is {w}×{h}",
                image.name()
            )));
        }
        let grey: Vec<f32> = (0..h)
            .flat_map(|y| image.data[y * image.stride..y * image.stride + w].iter())
            .map(|&v| f32::from(v) / 255.0)
            .collect();
        let grey = if (w32, h32) == (w, h) {
            grey
        } else {
            resize_bilinear(&grey, (w, h), (w32, h32))?
        };
        let mut out = self.model.run(&grey, h32, w32)?;
        decode::normalise_channels(&mut out.descriptors, DIM);
        let frame = Frame {
            w: w32,
            h: h32,
            sx: w as f32 / w32 as f32,
            sy: h as f32 / h32 as f32,
        };
        Ok((out, frame))
    }

    /// Keypoints (best score first) and, when `describe`, their descriptors.
    fn run(
        &self,
        image: &Image,
        describe: bool,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), crate::FeaturesError> {
        let (out, frame) = self.dense(image)?;
        let (w, h) = (frame.w, frame.h);
        let heat = decode::heatmap(&out.logits, out.hc, out.wc);
        let heat = Map {
            data: &heat,
            rows: h,
            cols: w,
        };
        let reliability = Map {
            data: &out.reliability,
            rows: out.hc,
            cols: out.wc,
        };
        let p = &self.params;
        let mut scored: Vec<(f32, usize, usize)> =
            decode::suppress(&heat, p.nms_kernel, p.detection_threshold)
                .into_iter()
                .map(|(x, y)| {
                    let at = (x as f32, y as f32);
                    let s =
                        decode::nearest(&heat, at, w, h) * decode::bilinear(&reliability, at, w, h);
                    (s, x, y)
                })
                // As `detectAndCompute`: a keypoint at (0, 0) is its padding, scored −1.
                .filter(|&(s, x, y)| s > 0.0 && (x, y) != (0, 0))
                .collect();
        // Best first; ties in image order (the sort is stable).
        scored.sort_by(|a, b| b.0.total_cmp(&a.0));
        if p.top_k > 0 {
            scored.truncate(p.top_k);
        }
        let at_network: Vec<(f32, f32)> = scored
            .iter()
            .map(|&(_, x, y)| (x as f32, y as f32))
            .collect();
        let descriptors = describe.then(|| self.sample(&out, &at_network, w, h));
        let keypoints: Vec<Keypoint> = scored
            .iter()
            .map(|&(s, x, y)| Keypoint {
                x: x as f32 * frame.sx,
                y: y as f32 * frame.sy,
                size: 8.0,
                angle: -1.0,
                response: s,
                octave: 0,
                class_id: -1,
            })
            .collect();
        Ok((keypoints, descriptors))
    }

    /// The unit descriptors at `points` (in the network's `w × h` input).
    fn sample(&self, out: &RawOutput, points: &[(f32, f32)], w: usize, h: usize) -> Descriptors {
        let mut data = Vec::with_capacity(points.len() * DIM);
        for &p in points {
            let start = data.len();
            decode::bicubic(
                &out.descriptors,
                DIM,
                (out.hc, out.wc),
                p,
                (w, h),
                &mut data,
            );
            decode::normalise(&mut data[start..]);
        }
        Descriptors {
            rows: points.len(),
            dim: DIM,
            data: DescriptorData::Float(data),
        }
    }
}

/// The network's input size and the scale back to the image's pixels.
struct Frame {
    w: usize,
    h: usize,
    sx: f32,
    sy: f32,
}

/// `grey` (`from` = width, height) resized bilinearly to `to` (pixel centres aligned, as
/// PyTorch's `interpolate(..., align_corners=False)` and OpenCV's `INTER_LINEAR`).
fn resize_bilinear(
    grey: &[f32],
    from: (usize, usize),
    to: (usize, usize),
) -> Result<Vec<f32>, crate::FeaturesError> {
    use opencv::core::{Mat, Size};
    use opencv::prelude::*;
    let cv = |e: opencv::Error| crate::FeaturesError::opencv("xfeat resize", e);
    let src = Mat::from_slice(grey)
        .and_then(|m| m.reshape(1, from.1 as i32).and_then(|m| m.try_clone()))
        .map_err(cv)?;
    let mut dst = Mat::default();
    let size = Size::new(to.0 as i32, to.1 as i32);
    opencv::imgproc::resize(
        &src,
        &mut dst,
        size,
        0.0,
        0.0,
        opencv::imgproc::INTER_LINEAR,
    )
    .map_err(cv)?;
    Ok(dst.data_typed::<f32>().map_err(cv)?.to_vec())
}

impl Detector for XFeat {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        let (k, _) = self.run(image, false).map_err(|e| e.in_stage("detector"))?;
        Ok(k)
    }

    fn detect_and_describe(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), CoreError> {
        self.run(image, self.params.describe)
            .map_err(|e| e.in_stage("detector"))
    }
}

impl Descriptor for XFeat {
    /// Descriptors of any keypoints (inside the image), sampled from XFeat's dense map.
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        let (out, frame) = self.dense(image).map_err(|e| e.in_stage("descriptor"))?;
        let (w, h) = (image.width as f32, image.height as f32);
        keypoints.retain(|k| k.x >= 0.0 && k.y >= 0.0 && k.x < w && k.y < h);
        let points: Vec<(f32, f32)> = keypoints
            .iter()
            .map(|k| (k.x / frame.sx, k.y / frame.sy))
            .collect();
        Ok(self.sample(&out, &points, frame.w, frame.h))
    }
}

/// Registers `xfeat` as a detector and a descriptor.
pub fn register(registry: &mut Registry) {
    registry.detectors.add::<XFeatParams>(
        XFeatParams::KIND,
        "XFeat keypoints (ONNX Runtime; the authors' weights, Apache-2.0, built in)",
        |p, ctx| {
            Ok(Box::new(
                XFeat::new(p, ctx).map_err(|e| e.in_stage("detector"))?,
            ))
        },
    );
    registry.descriptors.add::<XFeatParams>(
        XFeatParams::KIND,
        "XFeat 64-d float descriptor (ONNX Runtime; built-in model)",
        |p, ctx| {
            Ok(Box::new(
                XFeat::new(p, ctx).map_err(|e| e.in_stage("descriptor"))?,
            ))
        },
    );
}
