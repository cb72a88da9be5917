//! Structs that start with their size: read and written as far as both sides know them.

use std::mem::{size_of, MaybeUninit};

use super::types::{KeyloDegeneracy, KeyloFrameIn, KeyloFrameStats, KeyloPose};
use crate::CapiError;

/// A `#[repr(C)]` struct whose first field is `size: u32`.
///
/// # Safety
/// Implementors are `#[repr(C)]`, start with a `u32` size, and the all-zero bit pattern is a
/// valid value of them (numbers, `bool`, raw pointers).
pub(crate) unsafe trait Versioned: Copy {
    /// The C name, for messages.
    const NAME: &'static str;
    /// The smallest `size` accepted: the struct as it was first published.
    const MIN: usize;
    fn set_size(&mut self, size: u32);
}

macro_rules! sized {
    ($($ty:ident: $min:expr;)+) => {$(
        // SAFETY: repr(C), `size: u32` first, all fields zero-valid.
        unsafe impl Versioned for $ty {
            const NAME: &'static str = stringify!($ty);
            const MIN: usize = $min;
            fn set_size(&mut self, size: u32) {
                self.size = size;
            }
        }
    )+};
}

sized! {
    KeyloFrameIn: size_of::<KeyloFrameIn>();
    KeyloPose: size_of::<KeyloPose>();
    KeyloDegeneracy: size_of::<KeyloDegeneracy>();
    KeyloFrameStats: std::mem::offset_of!(KeyloFrameStats, frame) + size_of::<u64>();
}

/// The caller's `size` at `ptr`, checked against `T::MIN`.
///
/// # Safety
/// `ptr` is NULL or points to at least 4 readable bytes.
unsafe fn size_at<T: Versioned>(ptr: *const T, what: &str) -> Result<usize, CapiError> {
    if ptr.is_null() {
        return Err(CapiError::Argument(format!("{what} is NULL")));
    }
    // SAFETY: `size`, the first field, is readable per the contract.
    let size = unsafe { ptr.cast::<u32>().read_unaligned() } as usize;
    if size < T::MIN {
        return Err(CapiError::Argument(format!(
            "{what}->size = {size}: set it to sizeof({}) (at least {})",
            T::NAME,
            T::MIN
        )));
    }
    Ok(size)
}

/// The caller's struct: the bytes its `size` covers (up to ours), the rest zero (NULL).
///
/// # Safety
/// `ptr` is NULL or points to `ptr->size` readable bytes.
pub(crate) unsafe fn read_in<T: Versioned>(ptr: *const T, what: &str) -> Result<T, CapiError> {
    // SAFETY: forwarded.
    let n = unsafe { size_at(ptr, what) }?.min(size_of::<T>());
    let mut value = MaybeUninit::<T>::zeroed();
    // SAFETY: `n` bytes readable at `ptr` and writable in `value`; zero is valid for `T`.
    unsafe {
        std::ptr::copy_nonoverlapping(ptr.cast::<u8>(), value.as_mut_ptr().cast::<u8>(), n);
        Ok(value.assume_init())
    }
}

/// Writes `value` to the caller's struct as far as its `size` reaches, and sets `size` to
/// the bytes written.
///
/// # Safety
/// `out` is NULL or points to `out->size` writable bytes.
pub(crate) unsafe fn write_out<T: Versioned>(
    out: *mut T,
    mut value: T,
    what: &str,
) -> Result<(), CapiError> {
    // SAFETY: forwarded.
    let n = unsafe { size_at(out, what) }?.min(size_of::<T>());
    value.set_size(n as u32);
    // SAFETY: `n` ≤ both the caller's buffer and the struct; a prefix of a repr(C) struct is
    // a valid prefix of any later version of it.
    unsafe {
        std::ptr::copy_nonoverlapping((&value as *const T).cast::<u8>(), out.cast::<u8>(), n);
    }
    Ok(())
}
