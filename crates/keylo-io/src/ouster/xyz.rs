//! Range → XYZ as ouster-sdk's `make_xyz_lut` + `cartesian` compute it: a per-pixel unit
//! direction and offset (beam origin off the lidar axis, then the lidar → sensor transform),
//! so `xyz = direction · range + offset`; range 0 gives no point.

use std::f64::consts::PI;

use nalgebra::{Point3, Vector3};

use super::metadata::OusterMetadata;

/// Per-pixel direction and offset for a `rows × cols` staggered grid (column = measurement id).
#[derive(Debug, Clone)]
pub struct XyzLut {
    cols: usize,
    direction: Vec<Vector3<f64>>,
    offset: Vec<Vector3<f64>>,
}

impl XyzLut {
    /// The table for `meta`, points in the sensor frame, metres.
    pub fn new(meta: &OusterMetadata) -> Self {
        let (rows, cols) = (meta.pixels_per_column, meta.columns_per_frame);
        let beam = &meta.beam_to_lidar_transform;
        let (n, z0) = (beam[(0, 3)], beam[(2, 3)]);
        let t = &meta.lidar_to_sensor_transform;
        let rot = t.fixed_view::<3, 3>(0, 0).into_owned();
        let trans = Vector3::new(t[(0, 3)], t[(1, 3)], t[(2, 3)]);
        let mut direction = Vec::with_capacity(rows * cols);
        let mut offset = Vec::with_capacity(rows * cols);
        for r in 0..rows {
            let azimuth = -meta.beam_azimuth_angles[r] * PI / 180.0;
            let altitude = meta.beam_altitude_angles[r] * PI / 180.0;
            for c in 0..cols {
                let encoder = 2.0 * PI - c as f64 * (2.0 * PI / cols as f64);
                let d = Vector3::new(
                    (encoder + azimuth).cos() * altitude.cos(),
                    (encoder + azimuth).sin() * altitude.cos(),
                    altitude.sin(),
                );
                let o = Vector3::new(
                    encoder.cos() * n - d.x * n,
                    encoder.sin() * n - d.y * n,
                    -d.z * n + z0,
                );
                direction.push(rot * d * 1e-3);
                offset.push((rot * o + trans) * 1e-3);
            }
        }
        Self {
            cols,
            direction,
            offset,
        }
    }

    /// The point of pixel `(row, col)` at `range_mm`; `None` for range 0 (no return).
    #[inline]
    pub fn point(&self, row: usize, col: usize, range_mm: u32) -> Option<Point3<f64>> {
        if range_mm == 0 {
            return None;
        }
        let i = row * self.cols + col;
        Some(Point3::from(
            self.direction[i] * f64::from(range_mm) + self.offset[i],
        ))
    }
}
