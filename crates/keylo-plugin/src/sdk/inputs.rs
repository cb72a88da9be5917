//! The ABI's input buffers copied into keylo's types, checked, for a Rust plugin's trait
//! implementation.

use crate::convert::AbiError;
use std::sync::Arc;

use keylo_core::{
    BeamGeometry, Channel, ChannelFeatures, FrameFeatures, Image, LidarFrame, ScanPoints,
};
use nalgebra::Point3;

use crate::abi::*;
use crate::convert::{c_str, copy_optional, copy_slice, descriptors_from_abi, keypoints_from_abi};

/// An ABI image, copied.
///
/// # Safety
/// `image.data` must point to `height * stride` bytes and `image.name` be NULL or a
/// NUL-terminated string.
pub unsafe fn image_from_abi(image: &KeyloImage) -> Result<Image, AbiError> {
    if image.pixel_type != KEYLO_PIXEL_U8 {
        return Err(format!(
            "image pixel_type {}, this plugin reads only {KEYLO_PIXEL_U8} (u8)",
            image.pixel_type
        )
        .into());
    }
    let (w, h, stride, ch) = (
        image.width as usize,
        image.height as usize,
        image.stride as usize,
        image.channels as usize,
    );
    if stride < w * ch {
        return Err(format!("image stride {stride} < width {w} x channels {ch}").into());
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

/// An ABI frame, copied, with its scan points when it has some (ABI version 2). The ABI
/// carries no beam geometry: the frame's `beams` holds only the column count.
///
/// # Safety
/// `f` must be a frame of ABI version 2 or later (keylo lends one to every plugin built with
/// this SDK). Every grid pointer of `f` must hold `rows * cols` values (`points` three times
/// that, `column_times` `cols`); `pixel_times` may be NULL; `scan` must be NULL or as
/// [`scan_from_abi`] requires.
pub unsafe fn frame_from_abi(f: &KeyloFrame) -> Result<LidarFrame, AbiError> {
    let (rows, cols) = (f.rows as usize, f.cols as usize);
    let n = rows
        .checked_mul(cols)
        .ok_or_else(|| format!("frame {rows} x {cols} overflows"))?;
    // SAFETY: the caller guarantees every grid holds `rows * cols` values.
    let grid = |p: *const f32, what: &str| unsafe { copy_slice(p, n, what) };
    // SAFETY: the caller guarantees the buffer holds the documented values.
    let xyz = unsafe { copy_slice(f.points, 3 * n, "frame points") }?;
    // SAFETY: the caller guarantees a version-2 frame whose `scan` is NULL or valid.
    let scan = unsafe { scan_from_abi(f.scan, n) }?;
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
        beams: Arc::new(BeamGeometry::unknown("unknown (plugin ABI)", cols)),
        scan: scan.map(Arc::new),
    })
}

/// The points of an unorganised scan over a grid of `pixels` pixels, copied and checked
/// ([`ScanPoints::check`]: lengths, indices in range, finite points); `None` for NULL.
///
/// # Safety
/// `scan` must be NULL or point to a [`KeyloScanPoints`] whose arrays hold what its fields
/// say: `xyz` `3 * len` values, `source_index` and `pixel` `len`, `pixel_to_point` `pixels`;
/// `times`, `intensity` and `ring` `len` or NULL.
pub unsafe fn scan_from_abi(
    scan: *const KeyloScanPoints,
    pixels: usize,
) -> Result<Option<ScanPoints>, AbiError> {
    if scan.is_null() {
        return Ok(None);
    }
    // SAFETY: non-NULL, and valid for the call per the caller.
    let s = unsafe { &*scan };
    let n = s.len;
    if n.checked_mul(3 * std::mem::size_of::<f64>()).is_none() {
        return Err(format!("scan: {n} points overflow").into());
    }
    // SAFETY: `Point3<f64>` is `#[repr(C)]` over `[f64; 3]` and `xyz` holds `3 * len`
    // doubles (caller's contract): `len` points.
    let points = unsafe { copy_slice(s.xyz.cast::<Point3<f64>>(), n, "scan xyz") }?;
    let scan = ScanPoints {
        points,
        // SAFETY: the caller guarantees `len` values or NULL.
        times: unsafe { copy_optional(s.times, n) },
        // SAFETY: as above.
        intensity: unsafe { copy_optional(s.intensity, n) },
        // SAFETY: as above.
        ring: unsafe { copy_optional(s.ring, n) },
        // SAFETY: the caller guarantees `len` values.
        source_index: unsafe { copy_slice(s.source_index, n, "scan source_index") }?,
        // SAFETY: as above.
        pixel: unsafe { copy_slice(s.pixel, n, "scan pixel") }?,
        // SAFETY: the caller guarantees `pixels` values.
        pixel_to_point: unsafe { copy_slice(s.pixel_to_point, pixels, "scan pixel_to_point") }?,
    };
    scan.check(pixels).map_err(|e| e.to_string())?;
    Ok(Some(scan))
}

/// ABI frame features, copied.
///
/// # Safety
/// `f.images` must point to `f.len` entries whose buffers hold what their lengths say.
pub unsafe fn features_from_abi(f: &KeyloFeatures) -> Result<FrameFeatures, AbiError> {
    let mut out = FrameFeatures::default();
    if f.len == 0 {
        return Ok(out);
    }
    if f.images.is_null() {
        return Err(format!("features: NULL pointer for {} images", f.len).into());
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
