//! A `sensor_msgs/PointCloud2`'s points read straight from its bytes, one [`PointRecord`] at a
//! time, for frames that need no grid: the same values as [`super::to_raw_cloud`] gives,
//! without first copying every field into a [`crate::cloud::RawCloud`].

use super::{check_sizes, times_unit, Column, Layout, PointCloud2, Scalar, ABSOLUTE_S};
use crate::cloud::{PointFields, PointRecord};

/// The points of an unorganised message, read from its bytes.
pub(crate) struct DirectPoints<'a> {
    msg: &'a PointCloud2<'a>,
    n: usize,
    xyz: [Column; 3],
    intensity: Option<Column>,
    time: Option<TimeField>,
}

/// The time field of a message, and how its values become seconds after the stamp.
#[derive(Clone, Copy)]
struct TimeField {
    column: Column,
    /// Seconds per unit of the field.
    unit: f64,
    /// For absolute times: the factor to seconds and the stamp (seconds) subtracted.
    absolute: Option<(f64, f64)>,
}

impl<'a> DirectPoints<'a> {
    /// The points of `msg` when it is unorganised (`height` 1) and has no ring field (rings
    /// are checked against the whole cloud first); `Ok(None)` for other messages. Refuses
    /// exactly what [`super::to_raw_cloud`] refuses, with the same message.
    pub(crate) fn of(msg: &'a PointCloud2<'a>) -> Result<Option<Self>, String> {
        let n = check_sizes(msg)?;
        let layout = Layout {
            msg,
            width: (msg.width as usize).max(1),
            n,
        };
        let xyz = super::xyz_columns(&layout)?;
        let intensity = layout.find(&["intensity", "signal"])?.map(|(_, c)| c);
        layout.find(&["reflectivity"])?;
        layout.find(&["near_ir", "nir", "ambient"])?;
        layout.find(&["range"])?;
        let ring = layout.find(&["ring"])?;
        let time = layout.find(&["t", "time", "timestamp"])?.map(|(_, c)| c);
        if msg.height > 1 || ring.is_some() {
            return Ok(None);
        }
        let time = time.map(|c| {
            let unit = times_unit(c.scalar);
            let big = msg.is_bigendian;
            let largest = layout.fold(c, 0.0f64, |m, b| {
                let v = c.scalar.read(b, big) * unit;
                if v.is_finite() {
                    m.max(v.abs())
                } else {
                    m
                }
            });
            let absolute = (largest > ABSOLUTE_S).then(|| {
                (
                    super::absolute_to_s(c.scalar, largest),
                    msg.header.stamp_s(),
                )
            });
            TimeField {
                column: c,
                unit,
                absolute,
            }
        });
        Ok(Some(Self {
            msg,
            n,
            xyz,
            intensity,
            time,
        }))
    }

    /// The per-point fields every record carries, and the number of points.
    pub(crate) fn fields(&self) -> (PointFields, usize) {
        let fields = PointFields {
            time: self.time.is_some(),
            intensity: self.intensity.is_some(),
            ring: false,
        };
        (fields, self.n)
    }

    /// Every point in message order.
    pub(crate) fn records(&self) -> impl Iterator<Item = PointRecord> + '_ {
        let ps = self.msg.point_step as usize;
        let big = self.msg.is_bigendian;
        let [x, y, z] = self.xyz;
        let points = if self.n == 0 {
            &[][..]
        } else {
            &self.msg.data[..self.n * ps]
        };
        points.chunks_exact(ps).enumerate().map(move |(i, p)| {
            let time = self.time.map(|t| {
                let c = t.column;
                let v = c.scalar.read(&p[c.offset..], big) * t.unit;
                t.absolute.map_or(v, |(to_s, stamp_s)| v * to_s - stamp_s)
            });
            PointRecord {
                index: i as u32,
                xyz: [f32_at(x, p, big), f32_at(y, p, big), f32_at(z, p, big)],
                time,
                intensity: self.intensity.map(|c| f32_at(c, p, big)),
                ring: None,
            }
        })
    }
}

/// Field `c` of point `p` as `f32`, as [`Layout::f32s`] reads it.
#[inline(always)]
fn f32_at(c: Column, p: &[u8], big: bool) -> f32 {
    let b = &p[c.offset..];
    match b.first_chunk::<4>() {
        Some(&four) if c.scalar == Scalar::F32 && !big => f32::from_le_bytes(four),
        _ => c.scalar.read(b, big) as f32,
    }
}
