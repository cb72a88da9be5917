//! Trajectories for evaluation: read with their format and a label, and a KITTI file (no time
//! stamps: its stamps are the line numbers) paired with a time-stamped TUM trajectory.

use std::path::Path;

use keylo_core::Trajectory;

use super::{detect_format, file, parse_kitti, parse_tum, Format, TrajectoryError};

/// A trajectory with the format it was read in and a label for messages.
#[derive(Debug, Clone)]
pub struct Labelled {
    pub trajectory: Trajectory,
    pub format: Format,
    pub label: String,
}

impl Labelled {
    /// Reads a TUM or KITTI file.
    pub fn read(path: &Path) -> Result<Self, TrajectoryError> {
        let label = path.display().to_string();
        let text = file::read_text(path)?;
        let format = detect_format(&text, &label)?;
        let trajectory = match format {
            Format::Tum => parse_tum(&text, &label)?,
            Format::Kitti => parse_kitti(&text, &label)?,
        };
        Ok(Self {
            trajectory,
            format,
            label,
        })
    }

    /// A trajectory known to be time-stamped (e.g. keylo's own estimate).
    pub fn stamped(trajectory: Trajectory, label: &str) -> Self {
        Self {
            trajectory,
            format: Format::Tum,
            label: label.into(),
        }
    }
}

/// Makes the stamps of `a` and `b` comparable. When exactly one is a KITTI file, its poses are
/// given the other's stamps, one for one, which requires equal lengths.
pub fn reconcile(a: &mut Labelled, b: &mut Labelled) -> Result<(), TrajectoryError> {
    let (kitti, other) = match (a.format, b.format) {
        (Format::Kitti, Format::Tum) => (a, b),
        (Format::Tum, Format::Kitti) => (b, a),
        _ => return Ok(()),
    };
    let (n, m) = (kitti.trajectory.len(), other.trajectory.len());
    if n != m {
        return Err(TrajectoryError::Unpairable {
            kitti: kitti.label.clone(),
            kitti_poses: n,
            other: other.label.clone(),
            other_poses: m,
        });
    }
    kitti.trajectory.stamps.clone_from(&other.trajectory.stamps);
    kitti.format = Format::Tum;
    Ok(())
}
