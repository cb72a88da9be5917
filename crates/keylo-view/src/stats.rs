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
    "degenerate": {"type": "string", "description": "why the pose is (partly) predicted; absent when it is not"},
    "fitness": {"type": "number", "description": "share of points near the prior map (localisation only)"},
    "tracking": {"type": "boolean", "description": "fitness reached the threshold (localisation only)"}
  }
}"#;

/// One frame's figures, serialised (fields without a value are left out: viewers' JSON schema
/// readers take one type per field).
pub fn message(r: &FrameResult, odometry_ms: f64) -> Vec<u8> {
    let mut v = json!({
        "frame": r.index,
        "stamp": r.stamp,
        "keypoints": r.keypoints,
        "cloud_points": r.cloud_points,
        "registered_points": r.registered_points,
        "map_points": r.map_points,
        "iterations": r.iterations,
        "converged": r.converged,
        "odometry_ms": odometry_ms,
    });
    if let Some(d) = r.degenerate {
        v["degenerate"] = json!(d.label());
    }
    if let Some(f) = r.fit {
        v["fitness"] = json!(f.fitness);
        v["tracking"] = json!(f.tracking);
    }
    v.to_string().into_bytes()
}
