//! Consistency of a capture with its metadata, checked frame by frame, so that a metadata
//! JSON of another lidar mode is an error and not a silently wrong image.

use super::metadata::OusterMetadata;
use super::packet::RawFrame;

/// Checks that the packets of `raw` fit `meta`'s columns per frame: no measurement id at or
/// past the column count, and column timestamps spaced as `columns_per_frame` at `fps`
/// implies (within 25 %; frames with fewer than 16 columns are not timed).
pub(crate) fn check_frame(raw: &RawFrame, meta: &OusterMetadata) -> Result<(), String> {
    let cols = meta.columns_per_frame;
    if raw.out_of_range_columns > 0 {
        return Err(format!(
            "frame {}: {} columns have a measurement id >= {cols}, the metadata's \
             columns_per_frame ({}); is the metadata JSON of another lidar mode?",
            raw.frame_id, raw.out_of_range_columns, meta.lidar_mode
        ));
    }
    let valid: Vec<usize> = (0..cols).filter(|&m| raw.column_valid[m]).collect();
    let (Some(&first), Some(&last)) = (valid.first(), valid.last()) else {
        return Ok(());
    };
    if valid.len() < 16 || meta.fps == 0 {
        return Ok(());
    }
    let span_ns = raw.column_ns[last].abs_diff(raw.column_ns[first]) as f64;
    let measured = span_ns / (last - first) as f64;
    let expected = 1e9 / (f64::from(meta.fps) * cols as f64);
    if measured == 0.0 || (measured / expected - 1.0).abs() <= 0.25 {
        return Ok(());
    }
    let implied = 1e9 / (f64::from(meta.fps) * measured);
    Err(format!(
        "frame {}: columns are {:.1} µs apart, as for about {implied:.0} columns per turn at \
         {} Hz, but the metadata says {cols} ({}); is the metadata JSON of another lidar mode?",
        raw.frame_id,
        measured * 1e-3,
        meta.fps,
        meta.lidar_mode
    ))
}
