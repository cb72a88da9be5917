//! One point of a cloud as a source holds it, so a frame can be made while a source's points
//! are read (a message's bytes) as well as from a decoded [`RawCloud`].

use super::RawCloud;

/// One point of a cloud, with the per-point fields its cloud has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointRecord {
    /// Index of the point in its file or message.
    pub index: u32,
    /// Coordinates in the sensor frame, metres.
    pub xyz: [f32; 3],
    /// Firing time, seconds relative to the cloud's stamp.
    pub time: Option<f64>,
    /// Intensity (signal), as stored.
    pub intensity: Option<f32>,
    /// Beam (ring) index.
    pub ring: Option<u16>,
}

impl PointRecord {
    /// Point `i` of `cloud` (which holds more than `i` points and passed
    /// [`RawCloud::check`]).
    #[inline(always)]
    pub fn of(cloud: &RawCloud, i: usize) -> Self {
        Self {
            index: i as u32,
            xyz: cloud.points[i],
            time: cloud.time.as_ref().map(|t| t[i]),
            intensity: cloud.intensity.as_ref().map(|v| v[i]),
            ring: cloud.ring.as_ref().map(|r| r[i]),
        }
    }
}

/// Which per-point fields every [`PointRecord`] of a cloud carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PointFields {
    /// Firing times.
    pub time: bool,
    /// Intensities.
    pub intensity: bool,
    /// Rings.
    pub ring: bool,
}

impl PointFields {
    /// The fields `cloud` has.
    pub fn of(cloud: &RawCloud) -> Self {
        Self {
            time: cloud.time.is_some(),
            intensity: cloud.intensity.is_some(),
            ring: cloud.ring.is_some(),
        }
    }
}
