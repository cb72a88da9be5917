//! KITTI odometry pose format: 12 numbers per line, the row-major 3x4 matrix `[R|t]`.

use std::path::Path;

use keylo_core::{Pose, Trajectory};
use nalgebra::{Matrix3, Translation3};

use super::file::{label, read_text, write_text};
use super::lines::{first_line, numbers, raw_lines};
use super::rotation::nearest_rotation;
use super::TrajectoryError;

/// Numbers per KITTI line.
pub const KITTI_COLUMNS: usize = 12;

/// Parses KITTI text; stamps are the pose indices `0, 1, 2, …`.
///
/// Each rotation block is re-orthonormalised (nearest rotation); blocks that are far from
/// a rotation or have a non-positive determinant are rejected with the line number.
///
/// ```
/// let text = "1 0 0 5  0 1 0 6  0 0 1 7\n1 0 0 8  0 1 0 9  0 0 1 10\n";
/// let traj = keylo_io::trajectory::parse_kitti(text, "poses.txt")?;
/// assert_eq!(traj.stamps, vec![0.0, 1.0]);
/// assert_eq!(traj.poses[1].translation.vector.x, 8.0);
/// # Ok::<(), keylo_io::trajectory::TrajectoryError>(())
/// ```
pub fn parse_kitti(text: &str, file: &str) -> Result<Trajectory, TrajectoryError> {
    first_line(text, file)?;
    let mut traj = Trajectory::default();
    for (index, line) in raw_lines(text).enumerate() {
        let v = numbers(&line, KITTI_COLUMNS, file)?;
        traj.push(index as f64, kitti_pose(&v, file, line.number)?);
    }
    Ok(traj)
}

/// Parses KITTI text and takes the stamps from `times` (one per pose).
pub fn parse_kitti_with_times(
    text: &str,
    file: &str,
    times: &[f64],
) -> Result<Trajectory, TrajectoryError> {
    let mut traj = parse_kitti(text, file)?;
    if times.len() != traj.len() {
        return Err(TrajectoryError::TimesMismatch {
            file: file.to_string(),
            poses: traj.len(),
            times: times.len(),
        });
    }
    traj.stamps = times.to_vec();
    Ok(traj)
}

fn kitti_pose(v: &[f64], file: &str, line: usize) -> Result<Pose, TrajectoryError> {
    let m = Matrix3::new(v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10]);
    let rotation = nearest_rotation(&m).map_err(|reason| TrajectoryError::BadRotation {
        file: file.to_string(),
        line,
        reason,
    })?;
    Ok(Pose::from_parts(
        Translation3::new(v[3], v[7], v[11]),
        rotation,
    ))
}

/// Reads a KITTI pose file; stamps are the pose indices.
pub fn read_kitti(path: impl AsRef<Path>) -> Result<Trajectory, TrajectoryError> {
    let path = path.as_ref();
    parse_kitti(&read_text(path)?, &label(path))
}

/// Reads a KITTI pose file with stamps from `times` (e.g. a KITTI `times.txt`).
pub fn read_kitti_with_times(
    path: impl AsRef<Path>,
    times: &[f64],
) -> Result<Trajectory, TrajectoryError> {
    let path = path.as_ref();
    parse_kitti_with_times(&read_text(path)?, &label(path), times)
}

/// Formats a trajectory as KITTI text (12 significant digits; stamps are dropped).
pub fn format_kitti(traj: &Trajectory) -> String {
    traj.poses.iter().map(format_kitti_line).collect()
}

/// One KITTI line (with its newline), as [`format_kitti`] writes it.
pub fn format_kitti_line(pose: &Pose) -> String {
    kitti_line(pose, |v| format!("{v:.12e}"))
}

/// [`format_kitti_line`] with every number in its shortest exact form (`{:e}`): read back,
/// the matrix is bit for bit the pose's (`[output] exact = true`).
pub fn format_kitti_line_exact(pose: &Pose) -> String {
    kitti_line(pose, |v| format!("{v:e}"))
}

fn kitti_line(pose: &Pose, number: impl Fn(f64) -> String) -> String {
    let r = pose.rotation.to_rotation_matrix().into_inner();
    let t = pose.translation.vector;
    let mut fields = Vec::with_capacity(KITTI_COLUMNS);
    for row in 0..3 {
        fields.extend((0..3).map(|col| number(r[(row, col)])));
        fields.push(number(t[row]));
    }
    let mut line = fields.join(" ");
    line.push('\n');
    line
}

/// Writes a trajectory as a KITTI pose file (stamps are dropped).
pub fn write_kitti(path: impl AsRef<Path>, traj: &Trajectory) -> Result<(), TrajectoryError> {
    write_text(path.as_ref(), &format_kitti(traj))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shuffled_matrix_is_rejected_with_line() {
        let text = "1 0 0 0 0 1 0 0 0 0 1 0\n0 0 1 0 1 0 0 0 0 0 1 0\n";
        let err = parse_kitti(text, "est.txt").unwrap_err().to_string();
        assert!(
            err.starts_with("est.txt line 2: the 3x3 block is not a rotation"),
            "{err}"
        );
    }

    #[test]
    fn times_must_match() {
        let text = "1 0 0 0 0 1 0 0 0 0 1 0\n";
        let err = parse_kitti_with_times(text, "p.txt", &[0.0, 0.1]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "p.txt: 1 poses but 2 timestamps were given"
        );
        let ok = parse_kitti_with_times(text, "p.txt", &[0.25]).unwrap();
        assert_eq!(ok.stamps, vec![0.25]);
    }

    #[test]
    fn infinite_value_is_rejected() {
        let err = parse_kitti("1 0 0 inf 0 1 0 0 0 0 1 0\n", "p.txt").unwrap_err();
        assert_eq!(
            err.to_string(),
            "p.txt line 1, column 4: value 'inf' is not finite"
        );
    }
}
