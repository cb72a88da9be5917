//! Trajectories for evaluation (`keylo_io::trajectory::Labelled`), with the CLI's messages.

use std::path::Path;

use anyhow::Result;
pub use keylo::io::trajectory::Labelled;
use keylo::Trajectory;

/// Reads a TUM or KITTI file.
pub fn read(path: &Path) -> Result<Labelled> {
    Ok(Labelled::read(path)?)
}

/// A trajectory known to be time-stamped (e.g. keylo's own estimate).
pub fn stamped(trajectory: Trajectory, label: &str) -> Labelled {
    Labelled::stamped(trajectory, label)
}

/// Makes the stamps of `a` and `b` comparable (a KITTI file takes the other's stamps).
pub fn reconcile(a: &mut Labelled, b: &mut Labelled) -> Result<()> {
    use keylo::io::trajectory::Format;
    let kitti = match (a.format, b.format) {
        (Format::Kitti, Format::Tum) => Some(a.label.clone()),
        (Format::Tum, Format::Kitti) => Some(b.label.clone()),
        _ => None,
    };
    keylo::io::trajectory::reconcile(a, b)?;
    if let Some(k) = kitti {
        tracing::info!("{k} has no time stamps: paired one for one with the other trajectory");
    }
    Ok(())
}
