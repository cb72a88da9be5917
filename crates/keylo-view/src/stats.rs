//! The frame's figures as JSON (Foxglove's Plot and Raw Message panels read them).

use keylo_core::FrameResult;
use serde_json::json;

/// The JSON schema of the stats messages.
pub const SCHEMA: &str = r#"{
  "title": "keylo.FrameStats",
  "type": "object",
  "properties": {
    "frame": {"type": "integer", "description": "frame index in the source"},
    "stamp": {"type": "number", "description": "time the pose refers to, s"},
    "keypoints": {"type": "integer"},
    "cloud_points": {"type": "integer", "description": "points the downsampler kept"},
    "registered_points": {"type": "integer", "description": "points the registrar used"},
    "map_points": {"type": "integer"},
    "iterations": {"type": "integer"},
    "converged": {"type": "boolean"},
    "odometry_ms": {"type": "number", "description": "time of every stage of the frame, ms"},
    "degenerate": {"type": ["string", "null"], "description": "why the pose is (partly) predicted"},
    "fitness": {"type": ["number", "null"], "description": "share of points near the prior map (localisation)"},
    "tracking": {"type": ["boolean", "null"], "description": "fitness reached the threshold (localisation)"}
  }
}"#;

/// One frame's figures, serialised.
pub fn message(r: &FrameResult, odometry_ms: f64) -> Vec<u8> {
    let v = json!({
        "frame": r.index,
        "stamp": r.stamp,
        "keypoints": r.keypoints,
        "cloud_points": r.cloud_points,
        "registered_points": r.registered_points,
        "map_points": r.map_points,
        "iterations": r.iterations,
        "converged": r.converged,
        "odometry_ms": odometry_ms,
        "degenerate": r.degenerate.map(|d| d.label()),
        "fitness": r.fit.map(|f| f.fitness),
        "tracking": r.fit.map(|f| f.tracking),
    });
    v.to_string().into_bytes()
}
