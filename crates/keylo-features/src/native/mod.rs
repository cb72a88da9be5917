//! Native descriptors, for what Debian's OpenCV lacks (no `xfeatures2d`): `brief` (BRIEF,
//! Calonder et al. 2010) and `freak` (FREAK, Alahi et al. 2012), written from the papers.
//!
//! - [`integral`]: integral image, box sums and area-weighted means.
//! - [`brief`]: BRIEF; OpenCV contrib's test pattern ([`brief_opencv`]) or keylo's own
//!   fixed-seed Gaussian draw ([`brief::test_pairs`]).
//! - [`freak_pattern`]: the 43-field retina pattern and its pair tables.
//! - [`freak`]: FREAK: OpenCV contrib's (`freak_cv`, tables in [`freak_opencv`]) or keylo's
//!   own, whose 512 pairs ([`freak_pairs`]) [`pairs_training`] selected.
//!
//! Sampling patterns, seeds and the training command: `docs/keypoints.md`, "Native BRIEF and
//! FREAK".

pub mod brief;
pub mod brief_opencv;
pub mod freak;
mod freak_cv;
pub mod freak_opencv;
pub mod freak_pairs;
pub mod freak_pattern;
mod input;
pub mod integral;
pub mod pairs_training;
#[cfg(feature = "nonfree")]
pub mod surf;
#[cfg(test)]
mod test_images;

pub use brief::{Brief, BriefParams, BriefPattern};
pub use freak::{Freak, FreakParams, FreakPattern};
pub use integral::Integral;

use keylo_core::config::StageParams;
use keylo_core::Registry;

keylo_core::stage_params!(BriefParams => "brief" as DescriptorParams);
keylo_core::stage_params!(FreakParams => "freak" as DescriptorParams);

/// Registers `brief` and `freak` as descriptors.
pub fn register(registry: &mut Registry) {
    registry.descriptors.add::<BriefParams>(
        BriefParams::KIND,
        "BRIEF binary descriptor (native; OpenCV contrib's test pattern by default)",
        |p, _| {
            Ok(Box::new(
                Brief::new(&p).map_err(|e| e.in_stage("descriptor"))?,
            ))
        },
    );
    registry.descriptors.add::<FreakParams>(
        FreakParams::KIND,
        "FREAK binary descriptor (native; OpenCV contrib's by default)",
        |p, _| {
            Ok(Box::new(
                Freak::new(&p).map_err(|e| e.in_stage("descriptor"))?,
            ))
        },
    );
}
