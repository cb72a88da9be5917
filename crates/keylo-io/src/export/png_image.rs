//! Channel images as 8-bit greyscale PNG for viewing: the values of valid pixels stretched
//! between their 1st and 99th percentile (as ouster-sdk's auto-exposure does), invalid
//! pixels black.

use std::path::Path;

use keylo_core::{Channel, LidarFrame};

use crate::IoError;

/// The 8-bit, contrast-stretched image of `channel`, row-major.
pub fn stretched(frame: &LidarFrame, channel: Channel) -> Vec<u8> {
    let values = frame.channel(channel);
    let mut sorted: Vec<f32> = values
        .iter()
        .zip(&frame.valid)
        .filter(|(v, ok)| **ok && v.is_finite())
        .map(|(v, _)| *v)
        .collect();
    sorted.sort_by(f32::total_cmp);
    let pick = |q: f64| -> f32 {
        let k = ((sorted.len().saturating_sub(1)) as f64 * q).round() as usize;
        sorted.get(k).copied().unwrap_or(0.0)
    };
    let (lo, hi) = (pick(0.01), pick(0.99));
    let span = if hi > lo { hi - lo } else { 1.0 };
    values
        .iter()
        .zip(&frame.valid)
        .map(|(v, ok)| {
            if *ok && v.is_finite() {
                (((v - lo) / span).clamp(0.0, 1.0) * 254.0 + 1.0).round() as u8
            } else {
                0
            }
        })
        .collect()
}

/// Writes `channel` of `frame` to `path` as a `cols × rows` greyscale PNG.
pub fn write_channel_png(path: &Path, frame: &LidarFrame, channel: Channel) -> Result<(), IoError> {
    let file = std::fs::File::create(path).map_err(|e| IoError::io(path, e))?;
    let mut encoder = png::Encoder::new(
        std::io::BufWriter::new(file),
        frame.cols as u32,
        frame.rows as u32,
    );
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Eight);
    let to_err = |e: png::EncodingError| IoError::format(path, format!("writing PNG: {e}"));
    let mut writer = encoder.write_header().map_err(to_err)?;
    writer
        .write_image_data(&stretched(frame, channel))
        .map_err(to_err)?;
    writer.finish().map_err(to_err)
}
