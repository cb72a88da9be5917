//! TUM RGB-D trajectory format: `t tx ty tz qx qy qz qw` per line.

use std::path::Path;

use keylo_core::{Pose, Trajectory};
use nalgebra::{Translation3, UnitQuaternion};

use super::file::{label, read_text, write_text};
use super::lines::{first_line, numbers, raw_lines};
use super::rotation::quaternion_xyzw;
use super::TrajectoryError;

/// Numbers per TUM line.
pub const TUM_COLUMNS: usize = 8;

/// Parses TUM text; `file` labels error messages.
///
/// `#` comment lines and blank lines are skipped; quaternions are normalised.
///
/// ```
/// let traj = keylo_io::trajectory::parse_tum("# t x y z qx qy qz qw\n0.5 1 2 3 0 0 0 1\n", "gt.tum")?;
/// assert_eq!(traj.stamps, vec![0.5]);
/// assert_eq!(traj.poses[0].translation.vector.z, 3.0);
/// let err = keylo_io::trajectory::parse_tum("0.5 1 2 3 0 0", "gt.tum").unwrap_err();
/// assert_eq!(err.to_string(), "gt.tum line 1: expected 8 numbers, found 6");
/// # Ok::<(), keylo_io::trajectory::TrajectoryError>(())
/// ```
pub fn parse_tum(text: &str, file: &str) -> Result<Trajectory, TrajectoryError> {
    first_line(text, file)?;
    let mut traj = Trajectory::default();
    for line in raw_lines(text) {
        let v = numbers(&line, TUM_COLUMNS, file)?;
        let rotation = tum_rotation(&v, file, line.number)?;
        let pose = Pose::from_parts(Translation3::new(v[1], v[2], v[3]), rotation);
        traj.push(v[0], pose);
    }
    Ok(traj)
}

fn tum_rotation(
    v: &[f64],
    file: &str,
    line: usize,
) -> Result<UnitQuaternion<f64>, TrajectoryError> {
    quaternion_xyzw([v[4], v[5], v[6], v[7]]).map_err(|norm| TrajectoryError::BadQuaternion {
        file: file.to_string(),
        line,
        norm,
    })
}

/// Reads a TUM file.
pub fn read_tum(path: impl AsRef<Path>) -> Result<Trajectory, TrajectoryError> {
    let path = path.as_ref();
    parse_tum(&read_text(path)?, &label(path))
}

/// Formats a trajectory as TUM text (9 decimals everywhere, quaternion with `qw >= 0`).
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// let mut traj = Trajectory::default();
/// traj.push(1.0, Pose::translation(1.0, 2.0, 3.0));
/// let text = keylo_io::trajectory::format_tum(&traj);
/// assert_eq!(text, "1.000000000 1.000000000 2.000000000 3.000000000 0.000000000 0.000000000 0.000000000 1.000000000\n");
/// ```
pub fn format_tum(traj: &Trajectory) -> String {
    traj.iter()
        .map(|(stamp, pose)| format_tum_line(stamp, pose))
        .collect()
}

/// One TUM line (with its newline), as [`format_tum`] writes it: for appending pose by pose.
pub fn format_tum_line(stamp: f64, pose: &Pose) -> String {
    tum_line(stamp, pose, |v| format!("{v:.9}"))
}

/// [`format_tum_line`] with every number in its shortest exact form (`{:e}`)
/// (`[output] exact = true`).
pub fn format_tum_line_exact(stamp: f64, pose: &Pose) -> String {
    tum_line(stamp, pose, |v| format!("{v:e}"))
}

fn tum_line(stamp: f64, pose: &Pose, number: impl Fn(f64) -> String) -> String {
    let t = pose.translation.vector;
    let q = canonical(pose.rotation);
    let values = [stamp, t.x, t.y, t.z, q.i, q.j, q.k, q.w];
    let fields: Vec<String> = values.iter().map(|&v| number(v)).collect();
    let mut line = fields.join(" ");
    line.push('\n');
    line
}

/// The same rotation with a non-negative real part.
fn canonical(q: UnitQuaternion<f64>) -> nalgebra::Quaternion<f64> {
    if q.w < 0.0 {
        -q.into_inner()
    } else {
        q.into_inner()
    }
}

/// Writes a trajectory as a TUM file.
pub fn write_tum(path: impl AsRef<Path>, traj: &Trajectory) -> Result<(), TrajectoryError> {
    write_text(path.as_ref(), &format_tum(traj))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_quaternion_names_line() {
        let err = parse_tum("# c\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 0\n", "est.tum").unwrap_err();
        assert!(
            err.to_string().starts_with("est.tum line 3: quaternion"),
            "{err}"
        );
    }

    #[test]
    fn empty_and_comment_only_are_errors() {
        for text in ["", "\n\n", "# only a comment\n"] {
            let err = parse_tum(text, "e.tum").unwrap_err();
            assert!(matches!(err, TrajectoryError::Empty { .. }), "{err}");
        }
    }

    #[test]
    fn round_trip_keeps_nanometres() {
        let mut traj = Trajectory::default();
        let rotation = UnitQuaternion::from_euler_angles(0.1, -2.0, 3.0);
        traj.push(
            1.6e9 + 0.123,
            Pose::from_parts(Translation3::new(1.0, -2.0, 3.5), rotation),
        );
        let back = parse_tum(&format_tum(&traj), "x").unwrap();
        assert!((back.stamps[0] - traj.stamps[0]).abs() < 1e-6);
        assert!(back.poses[0].rotation.angle_to(&rotation) < 1e-8);
    }
}
