//! Keypoints to draw (`keylo keypoints eval --images N`): what each detector of an
//! evaluation finds on every N-th image, as the evaluation sees that image (resized).

use keylo_core::{BuildContext, Image, Keypoint, Registry};

use crate::runner::output_size;
use crate::stages::build_groups;
use crate::{Combo, EvalSpec, KpEvalError, Plane};

/// One detector's keypoints on one image.
pub struct Pictured {
    /// The paper's name of the detector.
    pub detector: String,
    /// Index of the image among the evaluated ones.
    pub index: usize,
    /// The image's label (frame index or file name).
    pub label: String,
    pub image: Image,
    pub keypoints: Vec<Keypoint>,
}

/// Every detector of `combos` (each once) on images 0, `every`, 2 × `every`, … of
/// `planes`. Detectors that cannot be built are left out when `skip_unavailable`.
pub fn detect_for_pictures(
    planes: &[Plane],
    combos: &[Combo],
    spec: &EvalSpec,
    registry: &Registry,
    ctx: &BuildContext,
    every: usize,
    skip_unavailable: bool,
) -> Result<Vec<Pictured>, KpEvalError> {
    let (width, height) = output_size(planes, spec);
    let (mut groups, _) = build_groups(
        combos,
        spec,
        registry,
        ctx,
        (width, height),
        skip_unavailable,
    )?;
    let channel = spec.image.channel()?;
    let mut out = Vec::new();
    for (index, plane) in planes.iter().enumerate().step_by(every.max(1)) {
        let image = plane.image(width, height, spec.image.interpolation, channel)?;
        for g in &mut groups {
            let keypoints = g
                .detector
                .detect(&image)
                .map_err(|e| KpEvalError::stage(&g.detector_name, "detector", e))?;
            out.push(Pictured {
                detector: g.detector_name.clone(),
                index,
                label: plane.label.clone(),
                image: image.clone(),
                keypoints,
            });
        }
    }
    Ok(out)
}
