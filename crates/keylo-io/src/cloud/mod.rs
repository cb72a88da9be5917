//! Point clouds as files and messages hold them ([`RawCloud`]), and their conversion to the
//! organised [`keylo_core::LidarFrame`] every stage works on: organised clouds map pixel for
//! pixel ([`organised`]), unorganised ones are projected onto a spherical grid
//! ([`projection`]).

mod azimuth;
mod correction;
mod error;
pub mod organised;
pub mod projection;
pub(crate) mod projection_config;
mod raw;
mod records;
mod rows;
mod sensors;

pub use correction::{VerticalAngleCorrection, KISS_ICP_KITTI_DEG};
pub use error::CloudError;
pub use projection::{Grid, ProjectionConfig, Projector, RowSource, Sensor};
pub use raw::RawCloud;
pub use records::{PointFields, PointRecord};
