//! `reference.tum` in a run folder: the reference trajectory moved into the estimate's frame
//! (associated by time and aligned without scale, as the accuracy figures are), so that
//! pictures of the run (`keylo report`) show both in one frame with the local map.

use std::path::Path;

use anyhow::{Context, Result};
use keylo::eval::align_roll::align_trajectory;
use keylo::eval::associate::{associate, AssociateOptions};
use keylo::Trajectory;

/// The file's name in a run folder.
pub const FILE: &str = "reference.tum";

/// Writes `reference` aligned onto `estimate` to `out/reference.tum`.
pub fn write(out: &Path, estimate: &Trajectory, reference: &Trajectory) -> Result<()> {
    let pairs = associate(reference, estimate, &AssociateOptions::default())?;
    // The accuracy figures align the estimate onto the reference (T · estimate); the
    // reference in the estimate's frame is T⁻¹ · reference.
    let alignment = align_trajectory(&pairs.estimate, &pairs.reference, false)?;
    let inverse = alignment.isometry().inverse();
    let moved = Trajectory {
        stamps: reference.stamps.clone(),
        poses: reference.poses.iter().map(|p| inverse * p).collect(),
    };
    let path = out.join(FILE);
    keylo::io::trajectory::write_tum(&path, &moved)
        .with_context(|| format!("writing {}", path.display()))
}
