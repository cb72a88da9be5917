//! The `extern "C"` functions of a Rust plugin, generic over its backend type. Each one
//! catches panics and turns every failure into a code + message.

use std::ffi::{c_char, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

use keylo_core::registry::parse_params;
use keylo_core::{Descriptor, Detector, Downsampler, Registrar};

use super::{blank_kind, FromConfig};
use crate::abi::*;
use crate::convert;

/// An instance: the backend once configured, and the output buffers it hands out.
pub(super) struct Slot<T> {
    inner: Option<T>,
    keypoints: Vec<keylo_core::Keypoint>,
    descriptors: Option<keylo_core::Descriptors>,
    cloud: keylo_core::PointCloud,
    /// A registrar's local map, xyz interleaved, as last lent out.
    pub(super) map: Vec<f64>,
}

pub(super) type Failure = (i32, String);

pub(super) fn internal(e: impl std::fmt::Display) -> Failure {
    (KEYLO_ERR_INTERNAL, e.to_string())
}

pub(super) fn input(e: impl std::fmt::Display) -> Failure {
    (KEYLO_ERR_INPUT, e.to_string())
}

/// Runs `f`, writing its error or panic into `err`; returns the status code.
pub(super) fn guard(err: *mut KeyloError, f: impl FnOnce() -> Result<(), Failure>) -> i32 {
    let (code, message) = match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => return KEYLO_OK,
        Ok(Err(failure)) => failure,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "non-string panic payload".into());
            (KEYLO_ERR_PANIC, format!("plugin panicked: {what}"))
        }
    };
    // SAFETY: keylo passes a valid error (or NULL, which `write_error` ignores).
    unsafe { convert::write_error(err, code, &message) };
    code
}

/// The configured backend behind `state`.
///
/// # Safety
/// `state` must come from [`create`] for the same `T` and not be used elsewhere meanwhile.
pub(super) unsafe fn slot<'a, T>(state: *mut c_void) -> Result<&'a mut Slot<T>, Failure> {
    if state.is_null() {
        return Err(internal("NULL instance"));
    }
    // SAFETY: `state` is a live `Slot<T>` from `create` (caller's contract).
    Ok(unsafe { &mut *state.cast::<Slot<T>>() })
}

pub(super) fn configured<T>(slot: &mut Slot<T>) -> Result<&mut T, Failure> {
    slot.inner
        .as_mut()
        .ok_or_else(|| internal("instance used before configure"))
}

unsafe extern "C" fn create<T: FromConfig>(err: *mut KeyloError) -> *mut c_void {
    let mut out = std::ptr::null_mut();
    guard(err, || {
        let slot: Slot<T> = Slot {
            inner: None,
            keypoints: Vec::new(),
            descriptors: None,
            cloud: Default::default(),
            map: Vec::new(),
        };
        out = Box::into_raw(Box::new(slot)).cast::<c_void>();
        Ok(())
    });
    out
}

unsafe extern "C" fn configure<T: FromConfig>(
    state: *mut c_void,
    text: *const c_char,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made.
        let slot = unsafe { slot::<T>(state) }?;
        if text.is_null() {
            return Err((KEYLO_ERR_CONFIG, "NULL configuration".into()));
        }
        // SAFETY: keylo passes a NUL-terminated string.
        let text = unsafe { CStr::from_ptr(text) }
            .to_str()
            .map_err(|_| (KEYLO_ERR_CONFIG, "configuration is not UTF-8".to_string()))?;
        let table: toml::Table = text
            .parse()
            .map_err(|e| (KEYLO_ERR_CONFIG, format!("invalid TOML: {e}")))?;
        let params = parse_params::<T::Params>(&table).map_err(|(path, message)| {
            let at = if path.is_empty() {
                String::new()
            } else {
                format!("`{path}`: ")
            };
            (KEYLO_ERR_CONFIG, format!("{at}{message}"))
        })?;
        slot.inner = Some(T::from_params(params).map_err(|m| (KEYLO_ERR_CONFIG, m))?);
        Ok(())
    })
}

unsafe extern "C" fn destroy<T: FromConfig>(state: *mut c_void) {
    if state.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: `state` came from `create::<T>` and keylo never uses it again.
        drop(unsafe { Box::from_raw(state.cast::<Slot<T>>()) });
    }));
}

pub(super) fn common<T: FromConfig>(stage: u32) -> KeyloPluginKind {
    let mut kind = blank_kind(stage);
    kind.create = Some(create::<T>);
    kind.configure = Some(configure::<T>);
    kind.destroy = Some(destroy::<T>);
    kind
}

pub(super) unsafe extern "C" fn detect<T: FromConfig + Detector>(
    state: *mut c_void,
    image: *const KeyloImage,
    out: *mut KeyloKeypoints,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made.
        let slot = unsafe { slot::<T>(state) }?;
        // SAFETY: keylo passes a valid image and output for the duration of the call.
        let (image, out) = unsafe { (&*image, &mut *out) };
        // SAFETY: keylo's image points to `height * stride` bytes.
        let image = unsafe { super::image_from_abi(image) }.map_err(input)?;
        slot.keypoints = configured(slot)?.detect(&image).map_err(internal)?;
        *out = convert::keypoints_view(&slot.keypoints);
        Ok(())
    })
}

pub(super) unsafe extern "C" fn describe<T: FromConfig + Descriptor>(
    state: *mut c_void,
    image: *const KeyloImage,
    keypoints: *const KeyloKeypoints,
    out_keypoints: *mut KeyloKeypoints,
    out: *mut KeyloDescriptors,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made.
        let slot = unsafe { slot::<T>(state) }?;
        // SAFETY: keylo passes valid inputs and outputs for the duration of the call.
        let (image, keypoints, out_kp, out) =
            unsafe { (&*image, &*keypoints, &mut *out_keypoints, &mut *out) };
        // SAFETY: keylo's buffers hold what their lengths say.
        let image = unsafe { super::image_from_abi(image) }.map_err(input)?;
        // SAFETY: as above.
        let mut kps = unsafe { convert::keypoints_from_abi(keypoints) }.map_err(input)?;
        let d = configured(slot)?
            .describe(&image, &mut kps)
            .map_err(internal)?;
        slot.keypoints = kps;
        slot.descriptors = Some(d);
        *out_kp = convert::keypoints_view(&slot.keypoints);
        *out = convert::descriptors_view(slot.descriptors.as_ref());
        Ok(())
    })
}

pub(super) unsafe extern "C" fn downsample<T: FromConfig + Downsampler>(
    state: *mut c_void,
    frame: *const KeyloFrame,
    features: *const KeyloFeatures,
    out: *mut KeyloCloud,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made.
        let slot = unsafe { slot::<T>(state) }?;
        // SAFETY: keylo passes valid inputs and outputs for the duration of the call.
        let (frame, features, out) = unsafe { (&*frame, &*features, &mut *out) };
        // SAFETY: keylo's buffers hold what their lengths say.
        let frame = unsafe { super::frame_from_abi(frame) }.map_err(input)?;
        // SAFETY: as above.
        let features = unsafe { super::features_from_abi(features) }.map_err(input)?;
        slot.cloud = configured(slot)?
            .downsample(&frame, &features)
            .map_err(internal)?;
        *out = convert::cloud_view(&slot.cloud);
        Ok(())
    })
}

pub(super) unsafe extern "C" fn register_cloud<T: FromConfig + Registrar>(
    state: *mut c_void,
    cloud: *const KeyloCloud,
    out: *mut KeyloRegistration,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made.
        let slot = unsafe { slot::<T>(state) }?;
        // SAFETY: keylo passes valid inputs and outputs for the duration of the call.
        let (cloud, out) = unsafe { (&*cloud, &mut *out) };
        // SAFETY: keylo's buffers hold what their lengths say.
        let cloud = unsafe { convert::cloud_from_abi(cloud) }.map_err(input)?;
        let registrar = configured(slot)?;
        let reg = registrar.register(&cloud).map_err(internal)?;
        *out = convert::registration_to_abi(&reg, registrar.map_size());
        Ok(())
    })
}
