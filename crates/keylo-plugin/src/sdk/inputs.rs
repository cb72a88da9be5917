//! The ABI's input buffers copied into keylo's types, checked, for a Rust plugin's trait
//! implementation.

use std::sync::Arc;

use keylo_core::{BeamGeometry, Channel, ChannelFeatures, FrameFeatures, Image, LidarFrame};
use nalgebra::Point3;

use crate::abi::*;
use crate::convert::{c_str, copy_optional, copy_slice, descriptors_from_abi, keypoints_from_abi};

/// An ABI image, copied.
///
/// # Safety
/// `image.data` must point to `height * stride` bytes and `image.name` be NULL or a
/// NUL-terminated string.
pub unsafe fn image_from_abi(image: &KeyloImage) -> Result<Image, String> {
    if image.pixel_type != KEYLO_PIXEL_U8 {
        return Err(format!(
            "image pixel_type {}, this plugin reads only {KEYLO_PIXEL_U8} (u8)",
            image.pixel_type
        ));
    }
    let (w, h, stride, ch) = (
        image.width as usize,
        image.height as usize,
        image.stride as usize,
        image.channels as usize,
    );
    if stride < w * ch {
        return Err(format!("image stride {stride} < width {w} x channels {ch}"));
    }
    // SAFETY: forwarded from the caller.
    let data = unsafe { copy_slice(image.data, h * stride, "image data") }?;
    // SAFETY: forwarded from the caller.
    let name = unsafe { c_str(image.name, "image name") }.unwrap_or_default();
    let sources = name
        .split('+')
        .filter_map(|c| c.parse::<Channel>().ok())
        .collect();
    Ok(Image {
        width: w,
        height: h,
        channels: ch,
        stride,
        data,
        sources,
        scale_x: image.scale_x,
        scale_y: image.scale_y,
    })
}

/// An ABI frame, copied. ABI version 1 carries no beam geometry: the frame's `beams` holds
/// only the column count.
///
/// # Safety
/// Every grid pointer of `f` must hold `rows * cols` values (`points` three times that,
/// `column_times` `cols`); `pixel_times` may be NULL.
pub unsafe fn frame_from_abi(f: &KeyloFrame) -> Result<LidarFrame, String> {
    let (rows, cols) = (f.rows as usize, f.cols as usize);
    let n = rows
        .checked_mul(cols)
        .ok_or_else(|| format!("frame {rows} x {cols} overflows"))?;
    // SAFETY: the caller guarantees every grid holds `rows * cols` values.
    let grid = |p: *const f32, what: &str| unsafe { copy_slice(p, n, what) };
    // SAFETY: the caller guarantees the buffer holds the documented values.
    let xyz = unsafe { copy_slice(f.points, 3 * n, "frame points") }?;
    Ok(LidarFrame {
        index: f.index,
        timestamp: f.timestamp,
        rows,
        cols,
        // SAFETY: the caller guarantees the buffer holds the documented values.
        column_times: unsafe { copy_slice(f.column_times, cols, "column_times") }?,
        // SAFETY: the caller guarantees the buffer holds the documented values.
        pixel_times: unsafe { copy_optional(f.pixel_times, n) },
        range: grid(f.range, "range")?,
        signal: grid(f.signal, "signal")?,
        reflectivity: grid(f.reflectivity, "reflectivity")?,
        near_ir: grid(f.near_ir, "near_ir")?,
        points: xyz
            .chunks_exact(3)
            .map(|p| Point3::new(p[0], p[1], p[2]))
            .collect(),
        // SAFETY: the caller guarantees the buffer holds the documented values.
        valid: unsafe { copy_slice(f.valid, n, "valid") }?,
        beams: Arc::new(BeamGeometry::unknown("unknown (plugin ABI v1)", cols)),
        scan: None,
    })
}

/// ABI frame features, copied.
///
/// # Safety
/// `f.images` must point to `f.len` entries whose buffers hold what their lengths say.
pub unsafe fn features_from_abi(f: &KeyloFeatures) -> Result<FrameFeatures, String> {
    let mut out = FrameFeatures::default();
    if f.len == 0 {
        return Ok(out);
    }
    if f.images.is_null() {
        return Err(format!("features: NULL pointer for {} images", f.len));
    }
    // SAFETY: non-null, and the caller guarantees `len` entries.
    let entries = unsafe { std::slice::from_raw_parts(f.images, f.len) };
    for e in entries {
        // SAFETY: forwarded from the caller.
        let image = unsafe { image_from_abi(&e.image) }?;
        // SAFETY: forwarded from the caller.
        let keypoints = unsafe { keypoints_from_abi(&e.keypoints) }?;
        let descriptors = if e.descriptors.rows == 0 {
            None
        } else {
            // SAFETY: forwarded from the caller.
            Some(unsafe { descriptors_from_abi(&e.descriptors) }?)
        };
        out.per_image.push(ChannelFeatures {
            image,
            keypoints,
            descriptors,
        });
    }
    Ok(out)
}
