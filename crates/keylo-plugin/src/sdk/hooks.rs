//! The SLAM hooks of a Rust registrar plugin (ABI 3): the C functions forward to the
//! `keylo_core::Registrar` methods (whose defaults say "does not offer").

use std::ffi::c_void;

use keylo_core::rigid::pose_from_matrix;
use keylo_core::{Pose, Registrar};

use super::shims::{configured, guard, input, internal, slot, Failure};
use super::FromConfig;
use crate::abi::*;

/// Sets the hooks of a registrar kind.
pub(super) fn fill<T: FromConfig + Registrar>(kind: &mut KeyloPluginKind) {
    kind.set_motion_prior = Some(set_motion_prior::<T>);
    kind.set_pose = Some(set_pose::<T>);
    kind.reset = Some(reset::<T>);
    kind.local_map = Some(local_map::<T>);
}

/// The pose of keylo's row-major 4x4 `matrix`.
///
/// # Safety
/// `matrix` is NULL or points to 16 doubles.
unsafe fn matrix_in(matrix: *const f64) -> Result<Pose, Failure> {
    if matrix.is_null() {
        return Err(input("NULL matrix"));
    }
    let mut m = [0.0; 16];
    // SAFETY: 16 doubles per the caller.
    m.copy_from_slice(unsafe { std::slice::from_raw_parts(matrix, 16) });
    pose_from_matrix(&m).map_err(|why| input(format!("not a rigid transform ({why})")))
}

unsafe extern "C" fn set_motion_prior<T: FromConfig + Registrar>(
    state: *mut c_void,
    matrix: *const f64,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made and 16 doubles.
        let (slot, delta) = unsafe { (slot::<T>(state)?, matrix_in(matrix)?) };
        configured(slot)?.set_motion_prior(&delta).map_err(internal)
    })
}

unsafe extern "C" fn set_pose<T: FromConfig + Registrar>(
    state: *mut c_void,
    matrix: *const f64,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made and 16 doubles.
        let (slot, pose) = unsafe { (slot::<T>(state)?, matrix_in(matrix)?) };
        configured(slot)?.set_pose(&pose).map_err(internal)
    })
}

unsafe extern "C" fn reset<T: FromConfig + Registrar>(
    state: *mut c_void,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        // SAFETY: keylo passes the instance `create` made.
        let slot = unsafe { slot::<T>(state) }?;
        configured(slot)?.reset().map_err(internal)
    })
}

unsafe extern "C" fn local_map<T: FromConfig + Registrar>(
    state: *mut c_void,
    xyz: *mut *const f64,
    n: *mut usize,
    err: *mut KeyloError,
) -> i32 {
    guard(err, || {
        if xyz.is_null() || n.is_null() {
            return Err(input("NULL output"));
        }
        // SAFETY: keylo passes the instance `create` made.
        let slot = unsafe { slot::<T>(state) }?;
        let points = configured(slot)?.local_map();
        slot.map = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
        // SAFETY: writable outputs per the ABI; the buffer lives in the instance.
        unsafe {
            *xyz = slot.map.as_ptr();
            *n = points.len();
        }
        Ok(())
    })
}
