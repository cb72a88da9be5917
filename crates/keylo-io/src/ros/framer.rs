//! One decoded `sensor_msgs/PointCloud2` → one [`LidarFrame`]: organised clouds pixel for
//! pixel (beam geometry from Ouster metadata when it fits, else estimated from the first
//! cloud), unorganised ones through the [`Projector`]. Shared by the recorded sources (`mcap`,
//! `ros1-bag`) and the live ROS 2 node, so a cloud read from a bag and the same cloud received
//! from DDS give the same frame, deskew times included.

use std::sync::Arc;

use keylo_core::{BeamGeometry, LidarFrame};

use super::beams;
use super::pointcloud2::{to_raw_cloud, DirectPoints};
use super::PointCloud2;
use crate::cloud::{organised, Projector, RawCloud};
use crate::ouster::OusterMetadata;

/// Turns clouds of one stream into frames, keeping the stream's beam geometry.
pub struct CloudFramer {
    projector: Projector,
    metadata: Option<OusterMetadata>,
    /// Names the stream in an estimated geometry (`model`), e.g. the topic.
    model: String,
    beams: Option<Arc<BeamGeometry>>,
}

impl CloudFramer {
    /// A framer projecting unorganised clouds with `projector`; `metadata` (when it matches an
    /// organised cloud's size) gives that cloud's beam geometry.
    pub fn new(projector: Projector, metadata: Option<OusterMetadata>, model: &str) -> Self {
        Self {
            projector,
            metadata,
            model: model.to_string(),
            beams: None,
        }
    }

    /// See [`keylo_core::ImageSource::set_grid_needed`].
    pub fn set_grid_needed(&mut self, needed: bool) {
        self.projector.set_grid_needed(needed);
    }

    /// The frame of a decoded cloud; `Err` says what is wrong with it.
    pub fn frame(&mut self, cloud: &RawCloud, index: u64) -> Result<LidarFrame, String> {
        match cloud.grid {
            Some((rows, cols)) => {
                let beams = self.beams_for(cloud, rows, cols);
                Ok(organised::to_frame(cloud, rows, cols, index, beams))
            }
            None => self
                .projector
                .project(cloud, index)
                .map_err(|e| e.to_string()),
        }
    }

    /// The frame of a message's cloud (the same frame as [`CloudFramer::frame`] of its
    /// [`to_raw_cloud`]); `Err` says what is wrong with it. When no grid is needed, an
    /// unorganised cloud without rings is framed straight from the message's bytes.
    pub fn frame_message(&mut self, msg: &PointCloud2, index: u64) -> Result<LidarFrame, String> {
        if !self.projector.grid_needed() {
            if let Some(points) = DirectPoints::of(msg)? {
                let (timestamp, fields) = (msg.header.stamp_s(), points.fields());
                return self
                    .projector
                    .points_only_from(timestamp, fields, points.records(), index)
                    .map_err(|e| e.to_string());
            }
        }
        let cloud = to_raw_cloud(msg).map_err(|e| e.to_string())?;
        self.frame(&cloud, index)
    }

    /// The beams of the stream: decided on the first cloud, again if the grid size changes.
    fn beams_for(&mut self, cloud: &RawCloud, rows: usize, cols: usize) -> Arc<BeamGeometry> {
        if let Some(b) = &self.beams {
            if b.altitude_deg.len() == rows && b.columns_per_frame == cols {
                return Arc::clone(b);
            }
        }
        let beams = Arc::new(match &self.metadata {
            Some(m) if m.pixels_per_column == rows && m.columns_per_frame == cols => {
                beams::from_metadata(m)
            }
            _ => beams::estimate(cloud, rows, cols, &self.model),
        });
        self.beams = Some(Arc::clone(&beams));
        beams
    }

    /// The Ouster metadata given to the framer, if any.
    pub fn metadata(&self) -> Option<&OusterMetadata> {
        self.metadata.as_ref()
    }
}

#[cfg(test)]
#[path = "framer_tests.rs"]
mod tests;
