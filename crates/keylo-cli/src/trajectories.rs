//! Trajectories for evaluation (`keylo_io::trajectory::Labelled`), with the CLI's messages.

use anyhow::Result;
pub use keylo::io::trajectory::Labelled;

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
