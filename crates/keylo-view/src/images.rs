//! LiDAR images and their keypoints as Foxglove messages.

use foxglove::bytes::Bytes;
use foxglove::messages::{
    points_annotation, Color, ImageAnnotations, Point2, PointsAnnotation, RawImage,
};
use keylo_core::{Image, Keypoint};

use crate::convert::timestamp;

/// An 8-bit image as `mono8` (one plane) or `rgb8` (three); other plane counts show plane 0.
pub fn raw_image(stamp: f64, frame_id: &str, image: &Image) -> RawImage {
    let (encoding, planes) = match image.channels {
        3 => ("rgb8", 3),
        _ => ("mono8", 1),
    };
    let row = image.width * planes;
    let mut data = Vec::with_capacity(row * image.height);
    for y in 0..image.height {
        let start = y * image.stride;
        match (planes, image.channels) {
            (p, c) if p == c => {
                data.extend_from_slice(image.data.get(start..start + row).unwrap_or(&[]));
            }
            _ => data.extend((0..image.width).map(|x| {
                image
                    .data
                    .get(start + x * image.channels)
                    .copied()
                    .unwrap_or(0)
            })),
        }
    }
    data.resize(row * image.height, 0);
    RawImage {
        timestamp: Some(timestamp(stamp)),
        frame_id: frame_id.into(),
        width: image.width as u32,
        height: image.height as u32,
        encoding: encoding.into(),
        step: row as u32,
        data: Bytes::from(data),
    }
}

/// The keypoints as one points annotation (green dots; pixel centres at +0.5, as Foxglove
/// places pixel corners at integers).
pub fn keypoints(stamp: f64, keypoints: &[Keypoint]) -> ImageAnnotations {
    let green = Color {
        r: 0.1,
        g: 1.0,
        b: 0.2,
        a: 1.0,
    };
    ImageAnnotations {
        timestamp: Some(timestamp(stamp)),
        circles: Vec::new(),
        points: vec![PointsAnnotation {
            timestamp: Some(timestamp(stamp)),
            r#type: points_annotation::Type::Points.into(),
            points: keypoints
                .iter()
                .map(|k| Point2 {
                    x: f64::from(k.x) + 0.5,
                    y: f64::from(k.y) + 0.5,
                })
                .collect(),
            outline_color: Some(green),
            outline_colors: Vec::new(),
            fill_color: Some(green),
            thickness: 3.0,
            metadata: Vec::new(),
        }],
        texts: Vec::new(),
        metadata: Vec::new(),
    }
}
