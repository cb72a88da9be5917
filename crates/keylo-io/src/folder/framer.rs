//! Clouds become frames: organised clouds pixel for pixel, the others by spherical
//! projection.

use std::sync::Arc;

use keylo_core::{BeamGeometry, LidarFrame};

use crate::cloud::projection_config::even_altitudes;
use crate::cloud::{
    organised, CloudError, ProjectionConfig, Projector, RawCloud, Sensor, VerticalAngleCorrection,
};

/// Turns the clouds of one sequence into frames.
#[derive(Debug, Clone)]
pub struct Framer {
    projector: Projector,
    /// Beams of organised clouds, per grid shape seen last.
    organised: Option<((usize, usize), Arc<BeamGeometry>)>,
}

impl Framer {
    /// A framer for `config` (validated) in a source whose `auto` sensor is
    /// `source_default`.
    pub fn new(config: &ProjectionConfig, source_default: Sensor) -> Result<Self, CloudError> {
        let grid = config.resolve(source_default)?;
        Ok(Self {
            projector: Projector::new(grid),
            organised: None,
        })
    }

    /// Applies `correction` to the points of unorganised clouds as they are read.
    pub fn with_correction(mut self, correction: Option<VerticalAngleCorrection>) -> Self {
        self.projector = self.projector.with_correction(correction);
        self
    }

    /// Whether unorganised clouds get an image grid ([`Projector::set_grid_needed`]).
    pub fn set_grid_needed(&mut self, needed: bool) {
        self.projector.set_grid_needed(needed);
    }

    /// The frame of `cloud` (organised when `cloud.grid` is set); the error says which field
    /// is inconsistent.
    pub fn frame(&mut self, cloud: &RawCloud, index: u64) -> Result<LidarFrame, CloudError> {
        match cloud.grid {
            Some((rows, cols)) => {
                cloud.check()?;
                let beams = self.organised_beams(rows, cols);
                Ok(organised::to_frame(cloud, rows, cols, index, beams))
            }
            None => self.projector.project(cloud, index),
        }
    }

    /// Beams of a `rows × cols` organised grid: the projection's beam table when it has
    /// `rows` entries, else `rows` beams spread evenly over its vertical field of view.
    fn organised_beams(&mut self, rows: usize, cols: usize) -> Arc<BeamGeometry> {
        if let Some((shape, beams)) = &self.organised {
            if *shape == (rows, cols) {
                return Arc::clone(beams);
            }
        }
        let grid = self.projector.grid();
        let table = &grid.altitudes_deg;
        let altitudes = if table.len() == rows {
            table.clone()
        } else {
            let (up, down) = (
                table.first().copied().unwrap_or(0.0),
                table.last().copied().unwrap_or(0.0),
            );
            even_altitudes(up, down, rows)
        };
        let beams = Arc::new(BeamGeometry {
            model: grid.model.clone(),
            azimuth_deg: vec![0.0; rows],
            altitude_deg: altitudes,
            origin_to_beam_mm: 0.0,
            columns_per_frame: cols,
            frame_rate_hz: grid.frame_rate_hz,
            column_lag_by_row: Vec::new(),
        });
        self.organised = Some(((rows, cols), Arc::clone(&beams)));
        beams
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn organised_clouds_keep_their_grid_and_others_are_projected() {
        let mut f = Framer::new(&ProjectionConfig::default(), Sensor::Generic).unwrap();
        let cloud = RawCloud {
            points: vec![[1.0, 0.0, 0.0]; 6],
            grid: Some((2, 3)),
            ..RawCloud::default()
        };
        let frame = f.frame(&cloud, 3).unwrap();
        assert_eq!((frame.rows, frame.cols, frame.index), (2, 3, 3));
        assert_eq!(frame.beams.altitude_deg, vec![3.0, -25.0]);
        assert!(frame.scan.is_none());
        let loose = RawCloud {
            grid: None,
            ..cloud
        };
        let frame = f.frame(&loose, 4).unwrap();
        assert_eq!((frame.rows, frame.cols), (64, 1024));
        assert!(frame.scan.is_some());
    }
}
