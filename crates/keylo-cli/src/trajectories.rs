//! Reading trajectories for evaluation, and pairing a KITTI file (no time stamps: its stamps
//! are the line numbers) with a time-stamped TUM trajectory.

use std::path::Path;

use anyhow::{bail, Context, Result};
use keylo::io::trajectory::{detect_format, parse_kitti, parse_tum, Format};
use keylo::Trajectory;

/// A trajectory with the format it was read in and a label for messages.
pub struct Labelled {
    pub trajectory: Trajectory,
    pub format: Format,
    pub label: String,
}

/// Reads a TUM or KITTI file.
pub fn read(path: &Path) -> Result<Labelled> {
    let label = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {label}"))?;
    let format = detect_format(&text, &label)?;
    let trajectory = match format {
        Format::Tum => parse_tum(&text, &label)?,
        Format::Kitti => parse_kitti(&text, &label)?,
    };
    Ok(Labelled {
        trajectory,
        format,
        label,
    })
}

/// A trajectory known to be time-stamped (e.g. keylo's own estimate).
pub fn stamped(trajectory: Trajectory, label: &str) -> Labelled {
    Labelled {
        trajectory,
        format: Format::Tum,
        label: label.into(),
    }
}

/// Makes the stamps of `a` and `b` comparable. When exactly one is a KITTI file, its poses are
/// given the other's stamps, one for one, which requires equal lengths.
pub fn reconcile(a: &mut Labelled, b: &mut Labelled) -> Result<()> {
    let (kitti, other) = match (a.format, b.format) {
        (Format::Kitti, Format::Tum) => (a, b),
        (Format::Tum, Format::Kitti) => (b, a),
        _ => return Ok(()),
    };
    let (n, m) = (kitti.trajectory.len(), other.trajectory.len());
    if n != m {
        bail!(
            "{} is a KITTI file (no time stamps) and {} has {m} time-stamped poses, not {n}: \
             poses can only be paired one for one; give both as TUM or both as KITTI",
            kitti.label,
            other.label
        );
    }
    tracing::info!(
        "{} has no time stamps: pairing its poses one for one with {}",
        kitti.label,
        other.label
    );
    kitti.trajectory.stamps.clone_from(&other.trajectory.stamps);
    kitti.format = Format::Tum;
    Ok(())
}
