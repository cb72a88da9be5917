//! `reference.tum` in a run folder: the reference trajectory moved into the estimate's frame
//! (associated by time and aligned without scale, as the accuracy figures are), so that
//! pictures of the run (`keylo report`) show both in one frame with the local map.

use std::path::Path;

use anyhow::{Context, Result};
use keylo::eval::align::align_trajectory;
use keylo::eval::associate::{associate, AssociateOptions};
use keylo::Trajectory;

/// The file's name in a run folder.
pub const FILE: &str = "reference.tum";

/// Writes `reference` aligned onto `estimate` to `out/reference.tum`.
pub fn write(out: &Path, estimate: &Trajectory, reference: &Trajectory) -> Result<()> {
    let pairs = associate(reference, estimate, &AssociateOptions::default())?;
    let alignment = align_trajectory(&pairs.reference, &pairs.estimate, false)?;
    let path = out.join(FILE);
    keylo::io::trajectory::write_tum(&path, &alignment.apply_trajectory(reference))
        .with_context(|| format!("writing {}", path.display()))
}
