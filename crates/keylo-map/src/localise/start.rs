//! Where localisation starts: an initial pose from seven numbers, checked to be a rotation
//! and to lie in the map.

use keylo_core::Pose;
use nalgebra::{Quaternion, Translation3, UnitQuaternion};

use crate::{Map, MapError};

/// How far outside the map's box (x, y, z) an initial position may lie, m.
pub const OUTSIDE_MARGIN_M: f64 = 5.0;

/// `[x, y, z, qx, qy, qz, qw]` as a pose; the message says what is wrong (count, a value
/// that is not finite, a quaternion that is not unit).
pub fn pose_of_values(v: &[f64]) -> Result<Pose, String> {
    let [x, y, z, qx, qy, qz, qw] = v[..] else {
        return Err(format!(
            "{} numbers; expected seven (x y z qx qy qz qw)",
            v.len()
        ));
    };
    if v.iter().any(|c| !c.is_finite()) {
        return Err("not every number is finite".into());
    }
    let q = Quaternion::new(qw, qx, qy, qz);
    if (q.norm() - 1.0).abs() > 1e-3 {
        return Err(format!(
            "the quaternion's norm is {}; expected 1 (a rotation)",
            q.norm()
        ));
    }
    Ok(Pose::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_quaternion(q),
    ))
}

/// "x y z qx qy qz qw" (spaces or commas) as a pose; the message quotes the text.
pub fn pose_of_text(text: &str) -> Result<Pose, String> {
    let v: Vec<f64> = text
        .split([' ', ','])
        .filter(|s| !s.is_empty())
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| format!("\"{text}\": expected seven numbers x y z qx qy qz qw"))?;
    pose_of_values(&v).map_err(|e| format!("\"{text}\": {e}"))
}

/// The pose localisation starts from: `given`, else the map's first keyframe; an error when
/// neither exists or the pose lies more than [`OUTSIDE_MARGIN_M`] outside the map's box (a
/// pose in another frame, or meant for another map).
pub fn initial_pose(map: &Map, given: Option<Pose>) -> Result<Pose, MapError> {
    let pose = match given {
        Some(p) => p,
        None => match map.keyframes().first() {
            Some(k) => k.pose,
            None => {
                return Err(MapError::format(
                    map.dir(),
                    "the map has no keyframe to start from; give an initial pose",
                ))
            }
        },
    };
    let Some(b) = &map.manifest().bounds else {
        return Err(MapError::format(
            map.dir(),
            "the map holds no point to localise in",
        ));
    };
    let p = pose.translation.vector;
    let outside =
        (0..3).any(|k| p[k] < b.min[k] - OUTSIDE_MARGIN_M || p[k] > b.max[k] + OUTSIDE_MARGIN_M);
    if outside {
        return Err(MapError::format(
            map.dir(),
            format!(
                "the initial pose ({:.2}, {:.2}, {:.2}) lies outside the map (box {:.2?} .. \
                 {:.2?}, {OUTSIDE_MARGIN_M} m margin): expected a pose in the map's world frame",
                p.x, p.y, p.z, b.min, b.max
            ),
        ));
    }
    Ok(pose)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_from_numbers_and_what_is_wrong() {
        let p = pose_of_text("1 2 3 0 0 0 1").unwrap();
        assert_eq!(p.translation.vector.x, 1.0);
        let p = pose_of_text("1,2,3,0,0,0.7071068,0.7071068").unwrap();
        assert!((p.rotation.angle() - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
        let cases = [
            ("1 2 3", "3 numbers; expected seven"),
            ("1 2 3 0 0 0 2", "norm is 2"),
            ("1 2 x 0 0 0 1", "expected seven numbers"),
            ("1 2 NaN 0 0 0 1", "not every number is finite"),
        ];
        for (text, want) in cases {
            let e = pose_of_text(text).unwrap_err();
            assert!(e.contains(want) && e.contains(text), "{text}: {e}");
        }
    }
}
