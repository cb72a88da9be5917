//! keylo's types as Foxglove messages.

use foxglove::bytes::Bytes;
use foxglove::messages::{
    packed_element_field::NumericType, FrameTransform, PackedElementField, PointCloud, Pose,
    Quaternion, Timestamp, Vector3,
};
use keylo_core::Pose as KPose;
use nalgebra::Point3;

/// Nanoseconds since the epoch of a stamp in seconds (negative and non-finite stamps are 0:
/// MCAP log times are unsigned).
pub fn nanos(stamp: f64) -> u64 {
    if stamp.is_finite() && stamp > 0.0 {
        (stamp * 1e9).round() as u64
    } else {
        0
    }
}

/// A Foxglove timestamp of a stamp in seconds.
pub fn timestamp(stamp: f64) -> Timestamp {
    let ns = nanos(stamp);
    Timestamp::new(
        u32::try_from(ns / 1_000_000_000).unwrap_or(u32::MAX),
        (ns % 1_000_000_000) as u32,
    )
}

/// A keylo pose as a Foxglove pose.
pub fn pose(p: &KPose) -> Pose {
    let t = p.translation.vector;
    let q = p.rotation.quaternion();
    Pose {
        position: Some(Vector3 {
            x: t.x,
            y: t.y,
            z: t.z,
        }),
        orientation: Some(Quaternion {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        }),
    }
}

/// The transform `parent → child` whose child sits at `p` in the parent.
pub fn transform(stamp: f64, parent: &str, child: &str, p: &KPose) -> FrameTransform {
    let fp = pose(p);
    FrameTransform {
        timestamp: Some(timestamp(stamp)),
        parent_frame_id: parent.into(),
        child_frame_id: child.into(),
        translation: fp.position,
        rotation: fp.orientation,
    }
}

/// Points as an `x y z` (float32) Foxglove point cloud in `frame`.
pub fn cloud<'a>(
    stamp: f64,
    frame: &str,
    points: impl ExactSizeIterator<Item = &'a Point3<f64>>,
) -> PointCloud {
    let mut data = Vec::with_capacity(points.len() * 12);
    for p in points {
        for v in [p.x, p.y, p.z] {
            data.extend_from_slice(&(v as f32).to_le_bytes());
        }
    }
    let field = |name: &str, offset| PackedElementField {
        name: name.into(),
        offset,
        r#type: NumericType::Float32.into(),
    };
    PointCloud {
        timestamp: Some(timestamp(stamp)),
        frame_id: frame.into(),
        pose: None,
        point_stride: 12,
        fields: vec![field("x", 0), field("y", 4), field("z", 8)],
        data: Bytes::from(data),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};

    #[test]
    fn stamps_and_poses() {
        assert_eq!(nanos(1.5), 1_500_000_000);
        assert_eq!(nanos(-1.0), 0);
        assert_eq!(nanos(f64::NAN), 0);
        let t = timestamp(12.25);
        assert_eq!((t.sec(), t.nsec()), (12, 250_000_000));
        let p = Isometry3::from_parts(
            Translation3::new(1.0, 2.0, 3.0),
            UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2),
        );
        let fp = pose(&p);
        let q = fp.orientation.unwrap();
        assert!((q.z - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
        assert!((q.w - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
        assert_eq!(fp.position.unwrap().y, 2.0);
    }

    #[test]
    fn clouds_are_packed_float32() {
        let pts = [Point3::new(1.0, -2.0, 0.5), Point3::new(0.0, 0.0, 9.0)];
        let c = cloud(1.0, "odom", pts.iter());
        assert_eq!(c.point_stride, 12);
        assert_eq!(c.data.len(), 24);
        assert_eq!(&c.data[4..8], &(-2.0f32).to_le_bytes());
        assert_eq!(c.fields.len(), 3);
    }
}
