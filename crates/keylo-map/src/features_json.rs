//! A keyframe's keypoints, their 3-D points and descriptors as JSON
//! (`keyframes/NNNNNN.features.json`, docs/maps.md), readable from any language.

use keylo_core::{keypoint_points, DescriptorData, FrameFeatures, LidarFrame};
use serde_json::{json, Value};

/// The features of `frame` as the JSON a keyframe keeps; `None` when the pipeline made none.
pub(crate) fn features_json(frame: &LidarFrame, features: &FrameFeatures) -> Option<Value> {
    if features.per_image.is_empty() {
        return None;
    }
    let images: Vec<Value> = features
        .per_image
        .iter()
        .map(|c| {
            let points = keypoint_points(frame, c);
            let keypoints: Vec<Value> = c
                .keypoints
                .iter()
                .zip(&points)
                .map(|(k, p)| {
                    json!({
                        "x": k.x, "y": k.y, "size": k.size, "angle": k.angle,
                        "response": k.response, "octave": k.octave, "class_id": k.class_id,
                        "point": p.map(|p| [p.x, p.y, p.z]),
                    })
                })
                .collect();
            let descriptors = c.descriptors.as_ref().map(|d| match &d.data {
                DescriptorData::Binary(bytes) => json!({
                    "kind": "binary",
                    "dim": d.dim,
                    "rows": bytes.chunks(d.dim.max(1)).map(hex).collect::<Vec<_>>(),
                }),
                DescriptorData::Float(values) => json!({
                    "kind": "float",
                    "dim": d.dim,
                    "rows": values.chunks(d.dim.max(1)).collect::<Vec<_>>(),
                }),
            });
            json!({
                "image": c.image.name(),
                "width": c.image.width,
                "height": c.image.height,
                "keypoints": keypoints,
                "descriptors": descriptors,
            })
        })
        .collect();
    Some(json!({
        "frame": frame.index,
        "point_frame": "sensor (the keyframe's own, at the scan's end; x y z in metres)",
        "images": images,
    }))
}

/// Bytes as lowercase hex, two digits each.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
