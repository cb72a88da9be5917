//! Conversions between keylo's types and the ABI's plain buffers, used by both sides: the
//! host (inputs out, outputs in) and the Rust SDK (inputs in, outputs out).
//!
//! `*_view` functions borrow: the returned ABI struct points into the argument, which must
//! outlive every use of it. `*_from_abi` functions copy and check what they read.

use std::ffi::{c_char, CStr, CString};

use keylo_core::{DescriptorData, Descriptors, Image, Keypoint, PointCloud, Registration};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion};

use crate::abi::*;

/// A buffer crossing the plugin ABI that does not hold what its fields say (a NULL pointer
/// with a length, a length that overflows, a non-finite pose, a string that is not UTF-8);
/// the message names the field.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct AbiError {
    message: String,
}

impl AbiError {
    /// What is wrong.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl From<String> for AbiError {
    fn from(message: String) -> Self {
        Self { message }
    }
}

impl From<&str> for AbiError {
    fn from(message: &str) -> Self {
        Self {
            message: message.into(),
        }
    }
}

/// `value` as a `u32` ABI field, or a message naming `what`.
pub fn to_u32(value: usize, what: &str) -> Result<u32, AbiError> {
    u32::try_from(value)
        .map_err(|_| AbiError::from(format!("{what} = {value} does not fit the ABI's 32 bits")))
}

/// A borrowed ABI view of `image`; `name` is the image name as a C string.
pub fn image_view(image: &Image, name: &CStr) -> Result<KeyloImage, AbiError> {
    Ok(KeyloImage {
        width: to_u32(image.width, "image width")?,
        height: to_u32(image.height, "image height")?,
        stride: to_u32(image.stride, "image stride")?,
        channels: to_u32(image.channels, "image channels")?,
        pixel_type: KEYLO_PIXEL_U8,
        data: image.data.as_ptr(),
        scale_x: image.scale_x,
        scale_y: image.scale_y,
        name: name.as_ptr(),
    })
}

/// The image name as a C string (names are channel names joined by `+`: never a NUL).
pub fn image_name(image: &Image) -> CString {
    CString::new(image.name()).unwrap_or_default()
}

/// A borrowed ABI view of `keypoints` (`KeyloKeypoint` and `Keypoint` have the same layout).
pub fn keypoints_view(keypoints: &[Keypoint]) -> KeyloKeypoints {
    KeyloKeypoints {
        data: keypoints.as_ptr().cast::<KeyloKeypoint>(),
        len: keypoints.len(),
    }
}

/// A borrowed ABI view of `descriptors` (`rows` 0 for `None`).
pub fn descriptors_view(descriptors: Option<&Descriptors>) -> KeyloDescriptors {
    match descriptors {
        None => KeyloDescriptors {
            element_type: KEYLO_DESCRIPTOR_U8,
            rows: 0,
            dim: 0,
            data: std::ptr::null(),
        },
        Some(d) => {
            let (element_type, data) = match &d.data {
                DescriptorData::Binary(v) => (KEYLO_DESCRIPTOR_U8, v.as_ptr().cast()),
                DescriptorData::Float(v) => (KEYLO_DESCRIPTOR_F32, v.as_ptr().cast()),
            };
            KeyloDescriptors {
                element_type,
                rows: d.rows,
                dim: d.dim,
                data,
            }
        }
    }
}

/// A borrowed ABI view of `cloud`.
pub fn cloud_view(cloud: &PointCloud) -> KeyloCloud {
    KeyloCloud {
        timestamp: cloud.timestamp,
        len: cloud.len(),
        // `Point3<f64>` is `#[repr(C)]` over `[f64; 3]`: the points are `3 * len` doubles.
        xyz: cloud.points.as_ptr().cast::<f64>(),
        times: cloud
            .times
            .as_ref()
            .map_or(std::ptr::null(), |t| t.as_ptr()),
        intensities: cloud
            .intensities
            .as_ref()
            .map_or(std::ptr::null(), |t| t.as_ptr()),
    }
}

/// The registration as the ABI struct.
pub fn registration_to_abi(reg: &Registration, map_size: usize) -> KeyloRegistration {
    let t = reg.pose.translation.vector;
    let q = reg.pose.rotation.quaternion();
    KeyloRegistration {
        stamp: reg.stamp,
        translation: [t.x, t.y, t.z],
        rotation: [q.i, q.j, q.k, q.w],
        source_points: reg.source_points,
        iterations: reg.iterations,
        converged: reg.converged,
        map_size,
    }
}

/// `len` elements at `ptr`, copied; NULL is allowed only when `len` is 0.
///
/// # Safety
/// `ptr` must point to `len` readable, initialised elements (or be NULL).
pub unsafe fn copy_slice<T: Copy>(
    ptr: *const T,
    len: usize,
    what: &str,
) -> Result<Vec<T>, AbiError> {
    if len == 0 {
        return Ok(Vec::new());
    }
    if ptr.is_null() {
        return Err(format!("{what}: NULL pointer for {len} elements").into());
    }
    // SAFETY: non-null, and the caller guarantees `len` initialised elements.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) }.to_vec())
}

/// `Some(copy)` of `len` elements, `None` for a NULL pointer.
///
/// # Safety
/// As [`copy_slice`].
pub unsafe fn copy_optional<T: Copy>(ptr: *const T, len: usize) -> Option<Vec<T>> {
    // SAFETY: forwarded from the caller.
    (!ptr.is_null()).then(|| unsafe { copy_slice(ptr, len, "") }.unwrap_or_default())
}

/// The keypoints of an ABI list, copied.
///
/// # Safety
/// `list.data` must point to `list.len` keypoints (or be NULL with `len` 0).
pub unsafe fn keypoints_from_abi(list: &KeyloKeypoints) -> Result<Vec<Keypoint>, AbiError> {
    // SAFETY: forwarded from the caller.
    let raw = unsafe { copy_slice(list.data, list.len, "keypoints") }?;
    Ok(raw
        .into_iter()
        .map(|k| Keypoint {
            x: k.x,
            y: k.y,
            size: k.size,
            angle: k.angle,
            response: k.response,
            octave: k.octave,
            class_id: k.class_id,
        })
        .collect())
}

/// A descriptor matrix of the ABI, copied and checked.
///
/// # Safety
/// `d.data` must point to `rows * dim` elements of `element_type` (or be NULL with 0 rows).
pub unsafe fn descriptors_from_abi(d: &KeyloDescriptors) -> Result<Descriptors, AbiError> {
    let n = d
        .rows
        .checked_mul(d.dim)
        .ok_or_else(|| format!("descriptors: {} rows x {} overflows", d.rows, d.dim))?;
    let data = match d.element_type {
        // SAFETY: forwarded from the caller.
        KEYLO_DESCRIPTOR_U8 => DescriptorData::Binary(unsafe {
            copy_slice(d.data.cast::<u8>(), n, "descriptors")
        }?),
        // SAFETY: forwarded from the caller.
        KEYLO_DESCRIPTOR_F32 => DescriptorData::Float(unsafe {
            copy_slice(d.data.cast::<f32>(), n, "descriptors")
        }?),
        other => {
            return Err(format!(
                "descriptors: element_type {other}, expected {KEYLO_DESCRIPTOR_U8} (u8) or {KEYLO_DESCRIPTOR_F32} (f32)"
            ).into())
        }
    };
    Ok(Descriptors {
        rows: d.rows,
        dim: d.dim,
        data,
    })
}

/// An ABI cloud, copied.
///
/// # Safety
/// The pointers of `c` must hold `3 * len`, `len` and `len` elements (or be NULL where
/// optional).
pub unsafe fn cloud_from_abi(c: &KeyloCloud) -> Result<PointCloud, AbiError> {
    let n3 = c
        .len
        .checked_mul(3)
        .ok_or_else(|| format!("cloud: {} points overflow", c.len))?;
    // SAFETY: forwarded from the caller.
    let xyz = unsafe { copy_slice(c.xyz, n3, "cloud xyz") }?;
    let points = xyz
        .chunks_exact(3)
        .map(|p| Point3::new(p[0], p[1], p[2]))
        .collect();
    Ok(PointCloud {
        timestamp: c.timestamp,
        points,
        // SAFETY: forwarded from the caller.
        times: unsafe { copy_optional(c.times, c.len) },
        // SAFETY: forwarded from the caller.
        intensities: unsafe { copy_optional(c.intensities, c.len) },
    })
}

/// An ABI registration as keylo's, checked to be finite with a non-zero quaternion.
pub fn registration_from_abi(r: &KeyloRegistration) -> Result<Registration, AbiError> {
    let [x, y, z] = r.translation;
    let [qx, qy, qz, qw] = r.rotation;
    let all = [r.stamp, x, y, z, qx, qy, qz, qw];
    if all.iter().any(|v| !v.is_finite()) {
        return Err(format!(
            "registration is not finite: stamp {}, translation {:?}, rotation {:?}",
            r.stamp, r.translation, r.rotation
        )
        .into());
    }
    let q = Quaternion::new(qw, qx, qy, qz);
    if q.norm() < 1e-9 {
        return Err("registration rotation is a zero quaternion".into());
    }
    Ok(Registration {
        stamp: r.stamp,
        pose: Isometry3::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_quaternion(q),
        ),
        source_points: r.source_points,
        iterations: r.iterations,
        converged: r.converged,
        // ABI v1 has no degeneracy report.
        degeneracy: None,
        fit: None,
    })
}

/// A NUL-terminated string the plugin handed out, checked to be UTF-8.
///
/// # Safety
/// `ptr` must be NULL or point to a NUL-terminated string.
pub unsafe fn c_str(ptr: *const c_char, what: &str) -> Result<String, AbiError> {
    if ptr.is_null() {
        return Err(format!("{what} is NULL").into());
    }
    // SAFETY: non-null and NUL-terminated per the caller.
    let s = unsafe { CStr::from_ptr(ptr) };
    s.to_str()
        .map(str::to_string)
        .map_err(|_| AbiError::from(format!("{what} is not UTF-8")))
}

/// Writes `message` into `err` (truncated to fit, NUL-terminated) with `code`.
///
/// # Safety
/// `err` must be NULL or point to a writable [`KeyloError`].
pub unsafe fn write_error(err: *mut KeyloError, code: i32, message: &str) {
    if err.is_null() {
        return;
    }
    // SAFETY: non-null and writable per the caller.
    let err = unsafe { &mut *err };
    err.code = code;
    let bytes = message.as_bytes();
    let mut n = bytes.len().min(KEYLO_ERROR_MESSAGE_LEN - 1);
    while n > 0 && !message.is_char_boundary(n) {
        n -= 1;
    }
    for (dst, &b) in err.message.iter_mut().zip(&bytes[..n]) {
        *dst = b as c_char;
    }
    err.message[n] = 0;
}

/// A fresh, empty error.
pub fn empty_error() -> KeyloError {
    KeyloError {
        code: KEYLO_OK,
        message: [0; KEYLO_ERROR_MESSAGE_LEN],
    }
}

/// The message of `err` (up to its first NUL), lossily decoded.
pub fn read_error(err: &KeyloError) -> String {
    let bytes: Vec<u8> = err
        .message
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keypoint_layouts_match() {
        assert_eq!(
            std::mem::size_of::<Keypoint>(),
            std::mem::size_of::<KeyloKeypoint>()
        );
        assert_eq!(
            std::mem::align_of::<Keypoint>(),
            std::mem::align_of::<KeyloKeypoint>()
        );
        assert_eq!(std::mem::size_of::<Point3<f64>>(), 24);
        assert_eq!(std::mem::size_of::<Point3<f32>>(), 12);
    }

    #[test]
    fn errors_round_trip_and_truncate() {
        let mut e = empty_error();
        // SAFETY: `e` is a valid, writable error.
        unsafe { write_error(&mut e, KEYLO_ERR_INPUT, "bad") };
        assert_eq!((e.code, read_error(&e).as_str()), (KEYLO_ERR_INPUT, "bad"));
        let long = "é".repeat(600);
        // SAFETY: as above.
        unsafe { write_error(&mut e, KEYLO_ERR_INPUT, &long) };
        let back = read_error(&e);
        assert!(back.len() < KEYLO_ERROR_MESSAGE_LEN && back.chars().all(|c| c == 'é'));
    }
}
