//! What both native descriptors share: the one-plane check and the descriptor matrix.

use keylo_core::{DescriptorData, Descriptors, Image};

use crate::FeaturesError;

/// `Ok` for a one-plane image, else the error the OpenCV wrappers give.
pub(crate) fn one_plane(kind: &str, image: &Image) -> Result<(), FeaturesError> {
    if image.channels != 1 {
        return Err(FeaturesError::BadInput(format!(
            "`{kind}` needs a one-plane image; image `{}` has {} planes \
             (two-plane images are for SuperPoint)",
            image.name(),
            image.channels
        )));
    }
    if image.stride < image.width || image.data.len() < image.stride * image.height {
        return Err(FeaturesError::BadInput(format!(
            "image `{}`: {} bytes for {}×{} pixels with stride {}",
            image.name(),
            image.data.len(),
            image.width,
            image.height,
            image.stride
        )));
    }
    Ok(())
}

/// Binary descriptors of `bytes` per row.
pub(crate) fn binary(bytes: usize, data: Vec<u8>) -> Descriptors {
    Descriptors {
        rows: data.len() / bytes.max(1),
        dim: bytes,
        data: DescriptorData::Binary(data),
    }
}

/// A grey image's plane 0 borrowed as rows.
pub(crate) struct Plane<'a> {
    pub data: &'a [u8],
    pub width: usize,
    pub height: usize,
    pub stride: usize,
}

impl<'a> Plane<'a> {
    /// Plane 0 of a one-plane `image`.
    pub fn of(image: &'a Image) -> Self {
        Self {
            data: &image.data,
            width: image.width,
            height: image.height,
            stride: image.stride,
        }
    }

    #[inline]
    pub fn at(&self, x: usize, y: usize) -> u8 {
        self.data[y * self.stride + x]
    }
}
