//! Casts every pixel of a frame, columns in parallel, and assembles the [`LidarFrame`].

use std::sync::Arc;

use keylo_core::{BeamGeometry, LidarFrame, Pose};
use nalgebra::Vector3;
use parry3d::math::Vector as GVec;
use rayon::prelude::*;

use crate::appearance::BeamResponse;
use crate::noise::PixelRng;
use crate::scenes::Scene;
use crate::sensor::SensorModel;
use crate::shading::{PixelReturn, Shading};
use crate::Appearance;

/// Everything needed to render frames of one configuration.
#[derive(Debug)]
pub(crate) struct Renderer {
    pub sensor: SensorModel,
    pub shading: Shading,
    pub seed: u64,
    pub beams: Arc<BeamGeometry>,
    /// `(cos, sin)` of each beam's elevation.
    altitudes: Vec<(f64, f64)>,
    /// Signal response of each beam (row): gain 1 for the ideal appearance.
    beam_responses: Vec<BeamResponse>,
    /// Rays are cast this far (a bit past the max range, for the near-IR of far surfaces).
    cast_range: f32,
    /// Per column, `(sin, cos)` of its azimuth.
    column_trig: Vec<(f64, f64)>,
    /// Per row, the beam's azimuth offset, radians (empty: none).
    beam_azimuths: Vec<f64>,
    /// Distance from the lidar origin to the beam origins, metres.
    beam_origin_m: f64,
}

impl Renderer {
    /// A renderer for `sensor` with `shading`, noise seeded by `seed`.
    pub fn new(sensor: SensorModel, shading: Shading, seed: u64, look: Appearance) -> Self {
        let altitudes = sensor.altitude_table();
        let beam_responses = look.beam_responses(sensor.rows);
        let beams = sensor.beam_geometry();
        let cast_range = (sensor.max_range_m * 1.2 + 1.0) as f32;
        let column_trig = (0..sensor.cols)
            .map(|c| sensor.azimuth_rad(c).sin_cos())
            .collect();
        let (beam_azimuths, beam_origin_m) = match &sensor.stagger {
            Some(st) => (
                st.azimuth_deg.iter().map(|a| a.to_radians()).collect(),
                st.origin_m,
            ),
            None => (Vec::new(), 0.0),
        };
        Self {
            column_trig,
            beam_azimuths,
            beam_origin_m,
            sensor,
            shading,
            seed,
            beams,
            altitudes,
            beam_responses,
            cast_range,
        }
    }

    /// Renders frame `index` starting at `t0`; `column_times[c]` is column `c`'s firing
    /// time and `poses[c]` the sensor pose (sensor → world) it is cast from.
    pub fn frame(
        &self,
        scene: &Scene,
        index: u64,
        t0: f64,
        column_times: Vec<f64>,
        poses: &[Pose],
    ) -> LidarFrame {
        let (rows, cols) = (self.sensor.rows, self.sensor.cols);
        let mut buf = vec![PixelReturn::default(); rows * cols];
        let placements: Vec<Placement> = poses.iter().map(Placement::of).collect();
        buf.par_chunks_mut(rows)
            .enumerate()
            .for_each(|(c, column)| self.column(scene, index, c, &placements, column));
        let mut f = LidarFrame::empty(index, t0, rows, cols, Arc::clone(&self.beams));
        f.column_times = column_times;
        for (c, column) in buf.chunks(rows).enumerate() {
            for (r, px) in column.iter().enumerate() {
                let i = r * cols + c;
                f.valid[i] = px.valid;
                f.range[i] = px.range;
                f.points[i] = px.point;
                f.signal[i] = px.signal;
                f.reflectivity[i] = px.reflectivity;
                f.near_ir[i] = px.near_ir;
            }
        }
        if let Some(mixed) = &self.shading.mixed_pixels {
            mixed.apply(
                (self.seed, index),
                (rows, cols),
                &f.valid,
                &f.range,
                &mut f.signal,
                &mut f.reflectivity,
            );
            // The sensor reports whole counts, and at least its fewest for a return.
            let least = self.shading.min_return_counts as f32;
            for ((s, r), &ok) in f.signal.iter_mut().zip(&mut f.reflectivity).zip(&f.valid) {
                if ok {
                    *s = s.round().max(least);
                    *r = r.round();
                }
            }
        }
        f
    }

    /// Casts the `rows` pixels of destaggered column `col` into `out` (top row first), each
    /// from the placement (sensor pose) of the column it fired in.
    fn column(
        &self,
        scene: &Scene,
        frame: u64,
        col: usize,
        placements: &[Placement],
        out: &mut [PixelReturn],
    ) {
        let cols = self.sensor.cols;
        let lags = &self.beams.column_lag_by_row;
        let beams = self.altitudes.iter().zip(&self.beam_responses);
        for ((row, px), (&(ca, sa), beam)) in out.iter_mut().enumerate().zip(beams) {
            let fired = match lags.get(row) {
                Some(&lag) => (col + cols - lag) % cols,
                None => col,
            };
            let place = &placements[fired];
            let (s_enc, c_enc) = self.column_trig[fired];
            let (saz, caz) = match self.beam_azimuths.get(row) {
                Some(&offset) => (self.sensor.azimuth_rad(fired) - offset).sin_cos(),
                None => (s_enc, c_enc),
            };
            let dir_s = Vector3::new(ca * caz, ca * saz, sa);
            let w = place.rot * dir_s.cast::<f32>();
            let dir_w = GVec::new(w.x, w.y, w.z).normalize();
            // The beam starts on the column's azimuth, `beam_origin_m` from the lidar origin.
            let start_s = Vector3::new(c_enc, s_enc, 0.0) * self.beam_origin_m;
            let origin = if self.beam_origin_m == 0.0 {
                place.origin
            } else {
                let o = place.rot * start_s.cast::<f32>();
                place.origin + GVec::new(o.x, o.y, o.z)
            };
            let hit = scene.world.cast(origin, dir_w, self.cast_range);
            let mut rng = PixelRng::for_pixel(self.seed, frame, row, col);
            *px = self
                .shading
                .pixel(hit.as_ref(), &dir_s, dir_w, beam, &mut rng);
            if px.valid && self.beam_origin_m != 0.0 {
                // Ouster's range runs from the lidar origin through the beam origin.
                px.range += self.beam_origin_m as f32;
                px.point += start_s.cast::<f32>();
            }
        }
    }
}

/// A sensor pose as the caster uses it.
#[derive(Debug, Clone, Copy)]
struct Placement {
    rot: nalgebra::Matrix3<f32>,
    origin: GVec,
}

impl Placement {
    fn of(pose: &Pose) -> Self {
        let rot = pose
            .rotation
            .to_rotation_matrix()
            .into_inner()
            .cast::<f32>();
        let t = pose.translation.vector.cast::<f32>();
        Self {
            rot,
            origin: GVec::new(t.x, t.y, t.z),
        }
    }
}
