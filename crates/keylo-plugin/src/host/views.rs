//! Borrowed ABI views of a frame and its features for a downsampler plugin.

use std::ffi::CString;

use keylo_core::{FrameFeatures, LidarFrame};

use crate::abi::*;
use crate::convert::{descriptors_view, image_name, image_view, keypoints_view, to_u32};

/// A view of `frame`, borrowing its buffers.
pub fn frame_view(frame: &LidarFrame) -> Result<KeyloFrame, String> {
    frame.check_shape()?;
    Ok(KeyloFrame {
        index: frame.index,
        timestamp: frame.timestamp,
        rows: to_u32(frame.rows, "frame rows")?,
        cols: to_u32(frame.cols, "frame cols")?,
        column_times: frame.column_times.as_ptr(),
        pixel_times: frame
            .pixel_times
            .as_ref()
            .map_or(std::ptr::null(), |t| t.as_ptr()),
        range: frame.range.as_ptr(),
        signal: frame.signal.as_ptr(),
        reflectivity: frame.reflectivity.as_ptr(),
        near_ir: frame.near_ir.as_ptr(),
        // `Point3<f32>` is `#[repr(C)]` over `[f32; 3]`: `3 * rows * cols` floats.
        points: frame.points.as_ptr().cast::<f32>(),
        valid: frame.valid.as_ptr(),
    })
}

/// The per-image entries of a features view with the names they point to.
pub struct FeaturesView {
    _names: Vec<CString>,
    entries: Vec<KeyloImageFeatures>,
}

impl FeaturesView {
    /// A view of `features`, borrowing its images, keypoints and descriptors.
    pub fn new(features: &FrameFeatures) -> Result<Self, String> {
        let names: Vec<CString> = features
            .per_image
            .iter()
            .map(|c| image_name(&c.image))
            .collect();
        let mut entries = Vec::with_capacity(names.len());
        for (c, name) in features.per_image.iter().zip(&names) {
            entries.push(KeyloImageFeatures {
                image: image_view(&c.image, name)?,
                keypoints: keypoints_view(&c.keypoints),
                descriptors: descriptors_view(c.descriptors.as_ref()),
            });
        }
        Ok(Self {
            _names: names,
            entries,
        })
    }

    /// The ABI struct, valid while `self` and the features live.
    pub fn abi(&self) -> KeyloFeatures {
        KeyloFeatures {
            images: self.entries.as_ptr(),
            len: self.entries.len(),
        }
    }
}
