//! Why a point cloud cannot become a frame, or a projection cannot be built.

/// A point cloud whose fields disagree, or a `[source.projection]` value it cannot take.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CloudError {
    /// A per-point field with another length than the points.
    #[error("field `{field}` has {len} values for {points} points")]
    FieldLength {
        field: &'static str,
        len: usize,
        points: usize,
    },
    /// An organised cloud whose grid does not cover its points exactly.
    #[error("grid {rows}x{cols} does not hold {points} points")]
    GridSize {
        rows: usize,
        cols: usize,
        points: usize,
    },
    /// Rows from rings, but the cloud has none.
    #[error("projection.row_from = \"ring\" but the cloud has no ring field")]
    NoRing,
    /// A ring beyond the projection's rows.
    #[error("ring {ring} is outside the {rows} projection rows (set projection.rows)")]
    RingOutOfRange { ring: u16, rows: usize },
    /// A projection key with a value outside what it allows.
    #[error("projection.{key} = {value}; expected {expected}")]
    Projection {
        key: &'static str,
        value: String,
        expected: &'static str,
    },
}
