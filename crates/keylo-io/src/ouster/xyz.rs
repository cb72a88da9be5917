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
    /// The per-frame path in f32 without a per-pixel table (a table is 3 MB to read per
    /// 128×1024 frame, more than the frame's channels): per column cos/sin of the encoder
    /// angle, per row the beam's terms (error < 0.1 mm at 500 m).
    columns: Vec<[f32; 2]>,
    beams: Vec<BeamTerms>,
    /// lidar → sensor rotation and translation, scaled mm → m.
    rot: [[f32; 3]; 3],
    trans: [f32; 3],
    /// Beam origin off the lidar axis and its height, mm.
    n: f32,
    z0: f32,
}

/// One beam's terms of the angle-sum form of ouster-sdk's formula.
#[derive(Debug, Clone, Copy)]
pub struct BeamTerms {
    /// cos(azimuth)·cos(altitude), sin(azimuth)·cos(altitude), sin(altitude).
    a: f32,
    b: f32,
    s: f32,
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
        // cos/sin of (encoder + azimuth) from per-column and per-row terms (angle sum), so the
        // table costs `rows + cols` sin/cos evaluations instead of `rows × cols`.
        let encoder: Vec<(f64, f64)> = (0..cols)
            .map(|c| (2.0 * PI - c as f64 * (2.0 * PI / cols as f64)).sin_cos())
            .collect();
        let mut direction = Vec::with_capacity(rows * cols);
        let mut offset = Vec::with_capacity(rows * cols);
        for r in 0..rows {
            let (sin_az, cos_az) = (-meta.beam_azimuth_angles[r] * PI / 180.0).sin_cos();
            let (sin_alt, cos_alt) = (meta.beam_altitude_angles[r] * PI / 180.0).sin_cos();
            for &(sin_enc, cos_enc) in &encoder {
                let cos_sum = cos_enc * cos_az - sin_enc * sin_az;
                let sin_sum = sin_enc * cos_az + cos_enc * sin_az;
                let d = Vector3::new(cos_sum * cos_alt, sin_sum * cos_alt, sin_alt);
                let o = Vector3::new(cos_enc * n - d.x * n, sin_enc * n - d.y * n, -d.z * n + z0);
                direction.push(rot * d * 1e-3);
                offset.push((rot * o + trans) * 1e-3);
            }
        }
        let columns = encoder
            .iter()
            .map(|&(sin_enc, cos_enc)| [cos_enc as f32, sin_enc as f32])
            .collect();
        let beams = (0..rows)
            .map(|r| {
                let (sin_az, cos_az) = (-meta.beam_azimuth_angles[r] * PI / 180.0).sin_cos();
                let (sin_alt, cos_alt) = (meta.beam_altitude_angles[r] * PI / 180.0).sin_cos();
                BeamTerms {
                    a: (cos_az * cos_alt) as f32,
                    b: (sin_az * cos_alt) as f32,
                    s: sin_alt as f32,
                }
            })
            .collect();
        Self {
            cols,
            direction,
            offset,
            columns,
            beams,
            rot: std::array::from_fn(|i| std::array::from_fn(|j| (rot[(i, j)] * 1e-3) as f32)),
            trans: std::array::from_fn(|i| (trans[i] * 1e-3) as f32),
            n: n as f32,
            z0: z0 as f32,
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

    /// [`Self::point`] in f32 arithmetic (the frame's precision): `None` for range 0.
    #[inline]
    pub fn point_f32(&self, row: usize, col: usize, range_mm: u32) -> Option<[f32; 3]> {
        if range_mm == 0 {
            return None;
        }
        Some(self.point_of(self.beams[row], self.columns[col], range_mm))
    }

    /// The terms of beam (row) `row`.
    #[inline]
    pub fn beam(&self, row: usize) -> BeamTerms {
        self.beams[row]
    }

    /// cos/sin of the encoder angle of every column.
    #[inline]
    pub fn columns(&self) -> &[[f32; 2]] {
        &self.columns
    }

    /// The point of `beam` at encoder angle `[cos, sin]` and `range_mm` (any range: the
    /// caller treats range 0 as no return).
    #[inline]
    pub fn point_of(
        &self,
        beam: BeamTerms,
        [cos_enc, sin_enc]: [f32; 2],
        range_mm: u32,
    ) -> [f32; 3] {
        // The point in the lidar frame, mm: along the beam from its origin, `n` off the axis.
        let along = range_mm as f32 - self.n;
        let p = [
            (cos_enc * beam.a - sin_enc * beam.b) * along + cos_enc * self.n,
            (sin_enc * beam.a + cos_enc * beam.b) * along + sin_enc * self.n,
            beam.s * along + self.z0,
        ];
        let (m, t) = (&self.rot, &self.trans);
        std::array::from_fn(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + t[i])
    }
}
