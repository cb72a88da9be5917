//! Moving keypoints across the OpenCV boundary in one copy.
//!
//! The `opencv` crate boxes every `cv::KeyPoint`: reading a vector of them element by element
//! costs an allocation and seven foreign calls per keypoint (15–35 µs for a FAST image). keylo's
//! [`Keypoint`] is `#[repr(C)]` with exactly `cv::KeyPoint`'s fields in its order (pt.x, pt.y,
//! size, angle, response, octave, class_id), so a `std::vector<cv::KeyPoint>`'s storage is a
//! `[Keypoint]`. Its storage pointer is the vector's first word in libstdc++ and libc++; the
//! fast path is used only there, and each use is checked against the element-wise accessors
//! (first and last element); any mismatch falls back to the element-wise path.

use keylo_core::Keypoint;
use opencv::core::{KeyPoint, Vector};
use opencv::prelude::*;
use opencv::traits::Boxed;

use crate::FeaturesError;

fn same(a: &KeyPoint, b: &Keypoint) -> bool {
    let pt = a.pt();
    pt.x.to_bits() == b.x.to_bits()
        && pt.y.to_bits() == b.y.to_bits()
        && a.size().to_bits() == b.size.to_bits()
        && a.angle().to_bits() == b.angle.to_bits()
        && a.response().to_bits() == b.response.to_bits()
        && a.octave() == b.octave
        && a.class_id() == b.class_id
}

/// The vector's storage as keylo keypoints, when the layout checks pass.
#[cfg(any(target_os = "linux", target_os = "macos"))]
fn storage(v: &Vector<KeyPoint>) -> Option<*mut Keypoint> {
    const _: () = assert!(std::mem::size_of::<Keypoint>() == 28);
    // SAFETY: `as_raw` is a live `std::vector<cv::KeyPoint>*` (the `opencv` crate's
    // representation), an object of at least three pointers; reading its first word is a
    // read inside that object.
    let begin = unsafe { *(v.as_raw() as *const *mut Keypoint) };
    let aligned = (begin as usize).is_multiple_of(std::mem::align_of::<Keypoint>());
    (!begin.is_null() && aligned).then_some(begin)
}

#[cfg(not(any(target_os = "linux", target_os = "macos")))]
fn storage(_: &Vector<KeyPoint>) -> Option<*mut Keypoint> {
    None
}

/// Whether `slice` (claimed to be `v`'s storage) agrees with `v` at both ends.
fn agrees(v: &Vector<KeyPoint>, slice: &[Keypoint]) -> bool {
    let n = slice.len();
    match (v.get(0), v.get(n - 1)) {
        (Ok(first), Ok(last)) => same(&first, &slice[0]) && same(&last, &slice[n - 1]),
        _ => false,
    }
}

/// OpenCV keypoints as keylo keypoints.
pub fn read(v: &Vector<KeyPoint>) -> Vec<Keypoint> {
    let n = v.len();
    if n == 0 {
        return Vec::new();
    }
    if let Some(begin) = storage(v) {
        // SAFETY: on libstdc++/libc++ `begin` is the vector's storage of `n` cv::KeyPoints,
        // which have `Keypoint`'s layout; `agrees` confirms it before the slice is used.
        let slice = unsafe { std::slice::from_raw_parts(begin, n) };
        if agrees(v, slice) {
            return slice.to_vec();
        }
    }
    read_each(v)
}

fn read_each(v: &Vector<KeyPoint>) -> Vec<Keypoint> {
    v.iter()
        .map(|kp| {
            let pt = kp.pt();
            Keypoint {
                x: pt.x,
                y: pt.y,
                size: kp.size(),
                angle: kp.angle(),
                response: kp.response(),
                octave: kp.octave(),
                class_id: kp.class_id(),
            }
        })
        .collect()
}

/// keylo keypoints as OpenCV keypoints.
pub fn write(keypoints: &[Keypoint]) -> Result<Vector<KeyPoint>, FeaturesError> {
    let n = keypoints.len();
    if n == 0 {
        return Ok(Vector::new());
    }
    let mut v = Vector::<KeyPoint>::with_capacity(n);
    let blank = KeyPoint::default().map_err(|e| FeaturesError::opencv("KeyPoint::default", e))?;
    for _ in 0..n {
        v.push(blank.clone());
    }
    if let Some(begin) = storage(&v) {
        // SAFETY: as in `read`; the vector owns `n` elements and nothing else refers to them.
        let slice = unsafe { std::slice::from_raw_parts_mut(begin, n) };
        slice.copy_from_slice(keypoints);
        if agrees(&v, keypoints) {
            return Ok(v);
        }
    }
    write_each(keypoints)
}

fn write_each(keypoints: &[Keypoint]) -> Result<Vector<KeyPoint>, FeaturesError> {
    keypoints
        .iter()
        .map(|k| {
            KeyPoint::new_coords(k.x, k.y, k.size, k.angle, k.response, k.octave, k.class_id)
                .map_err(|e| FeaturesError::opencv("KeyPoint::new", e))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(n: usize) -> Vec<Keypoint> {
        (0..n)
            .map(|i| Keypoint {
                x: i as f32 * 1.5,
                y: 100.0 - i as f32,
                size: 7.0 + i as f32,
                angle: if i % 2 == 0 { -1.0 } else { 33.25 },
                response: 1.0 / (i + 1) as f32,
                octave: i as i32 % 4,
                class_id: i as i32 - 3,
            })
            .collect()
    }

    #[test]
    fn round_trips_and_agrees_with_the_element_wise_path() {
        for n in [0, 1, 2, 17, 1000] {
            let k = sample(n);
            let v = write(&k).unwrap();
            assert_eq!(v.len(), n);
            assert_eq!(read(&v), k);
            assert_eq!(read_each(&v), k);
            assert_eq!(read(&write_each(&k).unwrap()), k);
        }
    }

    #[cfg(any(target_os = "linux", target_os = "macos"))]
    #[test]
    fn the_fast_path_is_taken_here() {
        let v = write_each(&sample(5)).unwrap();
        let begin = storage(&v).expect("storage pointer");
        let slice = unsafe { std::slice::from_raw_parts(begin, 5) };
        assert!(agrees(&v, slice));
    }
}
