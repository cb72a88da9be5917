//! Range → XYZ as ouster-sdk's `make_xyz_lut` + `cartesian` compute it: along each beam from
//! its origin (off the lidar axis), then the lidar → sensor transform; range 0 gives no point.
//! Written in the angle-sum form, per-column encoder terms times per-row beam terms, so no
//! per-pixel table is built or read (one would be 3 MB per 128×1024 frame in f32).

use std::f64::consts::PI;
use std::ops::{Add, Mul, Sub};

use nalgebra::Point3;

use super::metadata::OusterMetadata;

/// One beam's terms: cos(azimuth)·cos(altitude), sin(azimuth)·cos(altitude), sin(altitude).
pub type BeamTerms<T> = [T; 3];

/// The terms of the formula in one precision.
#[derive(Debug, Clone)]
struct Terms<T> {
    /// Per column (measurement id), cos and sin of the encoder angle.
    columns: Vec<[T; 2]>,
    beams: Vec<BeamTerms<T>>,
    /// lidar → sensor rotation and translation, scaled mm → m.
    rot: [[T; 3]; 3],
    trans: [T; 3],
    /// Beam origin off the lidar axis and its height, mm.
    n: T,
    z0: T,
}

impl<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T>> Terms<T> {
    /// The point of `beam` at encoder angle `[cos, sin]` and `range_mm`, metres.
    #[inline]
    fn point(&self, [a, b, s]: BeamTerms<T>, [cos_enc, sin_enc]: [T; 2], range_mm: T) -> [T; 3] {
        // The point in the lidar frame, mm: along the beam from its origin, `n` off the axis.
        let along = range_mm - self.n;
        let p = [
            (cos_enc * a - sin_enc * b) * along + cos_enc * self.n,
            (sin_enc * a + cos_enc * b) * along + sin_enc * self.n,
            s * along + self.z0,
        ];
        let (m, t) = (&self.rot, &self.trans);
        std::array::from_fn(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + t[i])
    }
}

/// Range → XYZ for a `rows × cols` staggered grid (column = measurement id): in f64 for exact
/// comparisons with ouster-sdk, in f32 for the frames (error < 0.1 mm at 500 m).
#[derive(Debug, Clone)]
pub struct XyzLut {
    exact: Terms<f64>,
    fast: Terms<f32>,
}

impl XyzLut {
    /// The terms for `meta`, points in the sensor frame, metres.
    pub fn new(meta: &OusterMetadata) -> Self {
        let (rows, cols) = (meta.pixels_per_column, meta.columns_per_frame);
        let beam = &meta.beam_to_lidar_transform;
        let t = &meta.lidar_to_sensor_transform;
        let exact = Terms {
            columns: (0..cols)
                .map(|c| {
                    let (sin, cos) = (2.0 * PI - c as f64 * (2.0 * PI / cols as f64)).sin_cos();
                    [cos, sin]
                })
                .collect(),
            beams: (0..rows)
                .map(|r| {
                    let (sin_az, cos_az) = (-meta.beam_azimuth_angles[r] * PI / 180.0).sin_cos();
                    let (sin_alt, cos_alt) = (meta.beam_altitude_angles[r] * PI / 180.0).sin_cos();
                    [cos_az * cos_alt, sin_az * cos_alt, sin_alt]
                })
                .collect(),
            rot: std::array::from_fn(|i| std::array::from_fn(|j| t[(i, j)] * 1e-3)),
            trans: std::array::from_fn(|i| t[(i, 3)] * 1e-3),
            n: beam[(0, 3)],
            z0: beam[(2, 3)],
        };
        let fast = Terms {
            columns: exact.columns.iter().map(|c| c.map(|v| v as f32)).collect(),
            beams: exact.beams.iter().map(|b| b.map(|v| v as f32)).collect(),
            rot: exact.rot.map(|row| row.map(|v| v as f32)),
            trans: exact.trans.map(|v| v as f32),
            n: exact.n as f32,
            z0: exact.z0 as f32,
        };
        Self { exact, fast }
    }

    /// The point of pixel `(row, col)` at `range_mm` in f64; `None` for range 0 (no return).
    #[inline]
    pub fn point(&self, row: usize, col: usize, range_mm: u32) -> Option<Point3<f64>> {
        if range_mm == 0 {
            return None;
        }
        let e = &self.exact;
        Some(Point3::from(e.point(
            e.beams[row],
            e.columns[col],
            f64::from(range_mm),
        )))
    }

    /// The f32 terms of beam (row) `row`.
    #[inline]
    pub fn beam(&self, row: usize) -> BeamTerms<f32> {
        self.fast.beams[row]
    }

    /// cos/sin of the encoder angle of every column, f32.
    #[inline]
    pub fn columns(&self) -> &[[f32; 2]] {
        &self.fast.columns
    }

    /// The point of `beam` at encoder angle `[cos, sin]` and `range_mm` in f32 (any range: the
    /// caller treats range 0 as no return).
    #[inline]
    pub fn point_of(&self, beam: BeamTerms<f32>, angle: [f32; 2], range_mm: u32) -> [f32; 3] {
        self.fast.point(beam, angle, range_mm as f32)
    }
}
