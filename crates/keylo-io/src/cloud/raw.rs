/// A point cloud as a file or message holds it, before it becomes a `LidarFrame`.
///
/// Every per-point field is either absent or has one entry per point. Readers fill what the
/// format carries and leave the rest `None`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawCloud {
    /// Time of the cloud (the first firing when known), seconds.
    pub timestamp: f64,
    /// Point coordinates in the sensor frame, metres.
    pub points: Vec<[f32; 3]>,
    /// Intensity or signal (photon counts for Ouster), as the source names it.
    pub intensity: Option<Vec<f32>>,
    /// Calibrated reflectivity.
    pub reflectivity: Option<Vec<f32>>,
    /// Ambient / near-infrared light.
    pub near_ir: Option<Vec<f32>>,
    /// Range, metres, when the source measured it (else it is computed from the point).
    pub range: Option<Vec<f32>>,
    /// Beam (ring) index of every point.
    pub ring: Option<Vec<u16>>,
    /// Firing time of every point, seconds relative to `timestamp`.
    pub time: Option<Vec<f64>>,
    /// `(rows, cols)` when the cloud is organised row-major (e.g. a PointCloud2 with
    /// `height > 1`), else `None`.
    pub grid: Option<(usize, usize)>,
}

impl RawCloud {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True when the cloud holds no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Checks that every per-point field has one entry per point and that `grid` covers
    /// exactly the points; the error names the field.
    pub fn check(&self) -> Result<(), super::CloudError> {
        let n = self.points.len();
        let lens = [
            ("intensity", self.intensity.as_ref().map(Vec::len)),
            ("reflectivity", self.reflectivity.as_ref().map(Vec::len)),
            ("near_ir", self.near_ir.as_ref().map(Vec::len)),
            ("range", self.range.as_ref().map(Vec::len)),
            ("ring", self.ring.as_ref().map(Vec::len)),
            ("time", self.time.as_ref().map(Vec::len)),
        ];
        for (name, len) in lens {
            if let Some(len) = len.filter(|&l| l != n) {
                return Err(super::CloudError::FieldLength {
                    field: name,
                    len,
                    points: n,
                });
            }
        }
        if let Some((rows, cols)) = self.grid {
            if rows.checked_mul(cols) != Some(n) {
                return Err(super::CloudError::GridSize {
                    rows,
                    cols,
                    points: n,
                });
            }
        }
        Ok(())
    }
}
