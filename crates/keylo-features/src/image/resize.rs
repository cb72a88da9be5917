//! Resizing 8-bit planes with OpenCV and interleaving them into one [`Image`].

use keylo_core::{Channel, Image};
use opencv::core::{Mat, Size};
use opencv::prelude::*;

use super::Interpolation;
use crate::cv::mat_bytes;
use crate::FeaturesError;

/// `plane` (`rows × cols`, row-major) resized to `width × height`.
pub fn resize_plane(
    plane: &[u8],
    rows: usize,
    cols: usize,
    width: usize,
    height: usize,
    interpolation: Interpolation,
) -> Result<Vec<u8>, FeaturesError> {
    if (width, height) == (cols, rows) {
        return Ok(plane.to_vec());
    }
    let as_i32 = |v: usize, what: &str| {
        i32::try_from(v).map_err(|_| FeaturesError::BadInput(format!("{what} {v} too large")))
    };
    let flat = Mat::from_slice(plane).map_err(|e| FeaturesError::opencv("Mat::from_slice", e))?;
    let src = flat
        .reshape(1, as_i32(rows, "rows")?)
        .and_then(|m| m.try_clone())
        .map_err(|e| FeaturesError::opencv("Mat::reshape", e))?;
    let mut dst = Mat::default();
    let size = Size::new(as_i32(width, "width")?, as_i32(height, "height")?);
    opencv::imgproc::resize(&src, &mut dst, size, 0.0, 0.0, interpolation.cv_flag())
        .map_err(|e| FeaturesError::opencv("resize", e))?;
    mat_bytes(&dst)
}

/// One image from equally sized planes (interleaved when more than one).
pub fn interleave(
    planes: Vec<Vec<u8>>,
    sources: Vec<Channel>,
    width: usize,
    height: usize,
) -> Image {
    let channels = planes.len();
    let data = if channels == 1 {
        planes.into_iter().next().unwrap_or_default()
    } else {
        let mut data = vec![0u8; width * height * channels];
        for (p, plane) in planes.iter().enumerate() {
            for (i, v) in plane.iter().enumerate() {
                data[i * channels + p] = *v;
            }
        }
        data
    };
    Image {
        width,
        height,
        channels,
        stride: width * channels,
        data,
        sources,
        scale_x: 1.0,
        scale_y: 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_with_linear_interpolation() {
        // 2x4 -> 1x2: linear at exactly half averages 2x2 blocks.
        let plane = [0, 100, 50, 50, 100, 200, 50, 50];
        let out = resize_plane(&plane, 2, 4, 2, 1, Interpolation::Linear).unwrap();
        assert_eq!(out, vec![100, 50]);
    }

    #[test]
    fn every_interpolation_gives_the_requested_size() {
        let plane: Vec<u8> = (0..128 * 64).map(|i| (i % 251) as u8).collect();
        for interp in [
            Interpolation::Nearest,
            Interpolation::Linear,
            Interpolation::Cubic,
            Interpolation::Area,
            Interpolation::Lanczos4,
        ] {
            let out = resize_plane(&plane, 64, 128, 100, 30, interp).unwrap();
            assert_eq!(out.len(), 3000, "{interp:?}");
        }
    }

    #[test]
    fn interleaves_two_planes() {
        let img = interleave(
            vec![vec![1, 2], vec![3, 4]],
            vec![Channel::Signal, Channel::Range],
            2,
            1,
        );
        assert_eq!(img.data, vec![1, 3, 2, 4]);
        assert_eq!(img.name(), "signal+range");
    }
}
