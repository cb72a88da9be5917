//! Classic detectors and descriptors through OpenCV: `shi-tomasi`, `harris`, `fast`,
//! `brisk`, `sift`, `akaze`, `kaze`, `orb`, and `surf` (an explanatory error here).

mod akaze;
mod akaze_levels;
mod akaze_sized;
mod brisk;
mod fast;
mod feature;
mod gftt;
mod orb;
mod sift;
pub(crate) mod surf;

pub use akaze::{AkazeDescriptor, AkazeParams, Diffusivity, KazeParams};
pub use akaze_sized::AkazeFeature;
pub use brisk::BriskParams;
pub use fast::{FastParams, FastType};
pub use feature::{CvFeature, CvParams};
pub use gftt::{GfttParams, HarrisParams, ShiTomasiParams};
pub use orb::{OrbParams, OrbScore};
pub use sift::SiftParams;
pub use surf::SurfParams;

use keylo_core::Registry;
use serde::de::DeserializeOwned;
use serde::Serialize;

trait Params:
    CvParams + DeserializeOwned + Serialize + schemars::JsonSchema + Default + 'static
{
}
impl<P> Params for P where
    P: CvParams + DeserializeOwned + Serialize + schemars::JsonSchema + Default + 'static
{
}

/// `StageParams` of OpenCV parameter structs: their kind is [`CvParams::KIND`].
macro_rules! cv_stage_params {
    ($($ty:ty => $($stage:ident),+;)+) => {$(
        impl keylo_core::config::StageParams for $ty {
            const KIND: &'static str = <$ty as CvParams>::KIND;
        }
        $(impl keylo_core::config::$stage for $ty {})+
    )+};
}

cv_stage_params! {
    ShiTomasiParams => DetectorParams;
    HarrisParams => DetectorParams;
    FastParams => DetectorParams;
    BriskParams => DetectorParams, DescriptorParams;
    SiftParams => DetectorParams, DescriptorParams;
    AkazeParams => DetectorParams, DescriptorParams;
    KazeParams => DetectorParams, DescriptorParams;
    OrbParams => DetectorParams, DescriptorParams;
}

keylo_core::stage_params!(SurfParams => "surf" as DetectorParams, DescriptorParams);

fn add_detector<P: Params>(registry: &mut Registry, summary: &'static str) {
    registry.detectors.add::<P>(P::KIND, summary, |p, _| {
        Ok(Box::new(
            CvFeature::new(&p).map_err(|e| e.in_stage("detector"))?,
        ))
    });
}

fn add_descriptor<P: Params>(registry: &mut Registry, summary: &'static str) {
    registry.descriptors.add::<P>(P::KIND, summary, |p, _| {
        Ok(Box::new(
            CvFeature::new(&p).map_err(|e| e.in_stage("descriptor"))?,
        ))
    });
}

/// Registers the OpenCV detectors and descriptors.
pub fn register(registry: &mut Registry) {
    add_detector::<ShiTomasiParams>(registry, "Shi-Tomasi corners (OpenCV GFTTDetector)");
    add_detector::<HarrisParams>(
        registry,
        "Harris corners (OpenCV GFTTDetector, Harris score)",
    );
    add_detector::<FastParams>(registry, "FAST corners (OpenCV FastFeatureDetector)");
    add_detector::<BriskParams>(registry, "BRISK keypoints (OpenCV)");
    add_detector::<SiftParams>(registry, "SIFT keypoints (OpenCV)");
    registry.detectors.add::<AkazeParams>(
        <AkazeParams as CvParams>::KIND,
        "AKAZE keypoints (OpenCV; only the scale levels the image size can use)",
        |p, _| {
            Ok(Box::new(
                AkazeFeature::new(&p).map_err(|e| e.in_stage("detector"))?,
            ))
        },
    );
    add_detector::<KazeParams>(registry, "KAZE keypoints (OpenCV)");
    add_detector::<OrbParams>(registry, "ORB keypoints (OpenCV)");
    add_descriptor::<BriskParams>(registry, "BRISK binary descriptor (OpenCV)");
    add_descriptor::<SiftParams>(registry, "SIFT 128-d float descriptor (OpenCV)");
    registry.descriptors.add::<AkazeParams>(
        <AkazeParams as CvParams>::KIND,
        "AKAZE descriptor (OpenCV; needs AKAZE keypoints)",
        |p, _| {
            Ok(Box::new(
                AkazeFeature::new(&p).map_err(|e| e.in_stage("descriptor"))?,
            ))
        },
    );
    add_descriptor::<KazeParams>(
        registry,
        "KAZE float descriptor (OpenCV; needs KAZE keypoints)",
    );
    add_descriptor::<OrbParams>(registry, "ORB (oriented BRIEF) binary descriptor (OpenCV)");
    register_surf(registry);
}

#[cfg(feature = "nonfree")]
fn register_surf(registry: &mut Registry) {
    use crate::native::surf::Surf;
    let kind = <SurfParams as keylo_core::config::StageParams>::KIND;
    registry.detectors.add::<SurfParams>(
        kind,
        "SURF keypoints (native, OpenCV's layout; cargo feature `nonfree`)",
        |p, _| Ok(Box::new(Surf::new(&p).map_err(|e| e.in_stage("detector"))?)),
    );
    registry.descriptors.add::<SurfParams>(
        kind,
        "SURF 64-d float descriptor (native; cargo feature `nonfree`)",
        |p, _| {
            Ok(Box::new(
                Surf::new(&p).map_err(|e| e.in_stage("descriptor"))?,
            ))
        },
    );
}

#[cfg(not(feature = "nonfree"))]
fn register_surf(registry: &mut Registry) {
    let kind = <SurfParams as keylo_core::config::StageParams>::KIND;
    registry.detectors.add::<SurfParams>(
        kind,
        "SURF (needs the cargo feature `nonfree`)",
        |_, _| Err(surf::unavailable().in_stage("detector")),
    );
    registry.descriptors.add::<SurfParams>(
        kind,
        "SURF descriptor (needs the cargo feature `nonfree`)",
        |_, _| Err(surf::unavailable().in_stage("descriptor")),
    );
}
