//! The boundary to OpenCV: keylo [`Image`]s as `Mat`s, keypoints both ways, descriptor matrices.

use keylo_core::{DescriptorData, Descriptors, Image, Keypoint};
use opencv::core::{KeyPoint, Mat, Vector, CV_32F, CV_8U};
use opencv::prelude::*;

use crate::FeaturesError;

/// A `Mat` holding a copy of `image` (8-bit, 1 or more planes).
pub fn to_mat(image: &Image) -> Result<Mat, FeaturesError> {
    let planes = i32::try_from(image.channels)
        .map_err(|_| FeaturesError::BadInput(format!("{} image planes", image.channels)))?;
    let rows = i32::try_from(image.height)
        .map_err(|_| FeaturesError::BadInput(format!("image height {}", image.height)))?;
    let row_bytes = image.width * image.channels;
    let needed = image.stride * image.height.saturating_sub(1) + row_bytes;
    if image.stride < row_bytes || image.data.len() < needed {
        return Err(FeaturesError::BadInput(format!(
            "image {}x{}x{} with stride {} needs {needed} bytes, has {}",
            image.width,
            image.height,
            image.channels,
            image.stride,
            image.data.len()
        )));
    }
    let mut packed = Vec::with_capacity(row_bytes * image.height);
    for y in 0..image.height {
        let start = y * image.stride;
        packed.extend_from_slice(&image.data[start..start + row_bytes]);
    }
    let flat = Mat::from_slice(&packed).map_err(|e| FeaturesError::opencv("Mat::from_slice", e))?;
    let shaped = flat
        .reshape(planes, rows)
        .map_err(|e| FeaturesError::opencv("Mat::reshape", e))?;
    shaped
        .try_clone()
        .map_err(|e| FeaturesError::opencv("Mat::clone", e))
}

/// The bytes of a continuous 8-bit `Mat` as an owned vector.
pub fn mat_bytes(mat: &Mat) -> Result<Vec<u8>, FeaturesError> {
    if mat.depth() != CV_8U {
        return Err(FeaturesError::BadInput(format!(
            "expected an 8-bit matrix, got depth {}",
            mat.depth()
        )));
    }
    let owned;
    let m = if mat.is_continuous() {
        mat
    } else {
        owned = mat
            .try_clone()
            .map_err(|e| FeaturesError::opencv("Mat::clone", e))?;
        &owned
    };
    m.data_bytes()
        .map(<[u8]>::to_vec)
        .map_err(|e| FeaturesError::opencv("Mat::data_bytes", e))
}

/// keylo keypoints as OpenCV keypoints (one copy; see `cv_keypoints`).
pub fn to_cv_keypoints(keypoints: &[Keypoint]) -> Result<Vector<KeyPoint>, FeaturesError> {
    crate::cv_keypoints::write(keypoints)
}

/// OpenCV keypoints as keylo keypoints (one copy; see `cv_keypoints`).
pub fn from_cv_keypoints(keypoints: &Vector<KeyPoint>) -> Vec<Keypoint> {
    crate::cv_keypoints::read(keypoints)
}

/// An OpenCV descriptor matrix (rows = keypoints; `CV_8U` binary or `CV_32F` float).
pub fn to_descriptors(mat: &Mat) -> Result<Descriptors, FeaturesError> {
    let rows = usize::try_from(mat.rows()).unwrap_or(0);
    if rows == 0 || mat.cols() <= 0 {
        return Ok(Descriptors {
            rows: 0,
            dim: 0,
            data: DescriptorData::Binary(Vec::new()),
        });
    }
    let dim = usize::try_from(mat.cols()).unwrap_or(0);
    let continuous = mat
        .try_clone()
        .map_err(|e| FeaturesError::opencv("Mat::clone", e))?;
    let data = match mat.depth() {
        CV_8U => DescriptorData::Binary(mat_bytes(&continuous)?),
        CV_32F => DescriptorData::Float(
            continuous
                .data_typed::<f32>()
                .map_err(|e| FeaturesError::opencv("Mat::data_typed", e))?
                .to_vec(),
        ),
        depth => {
            return Err(FeaturesError::BadInput(format!(
                "descriptor matrix of depth {depth}: expected 8-bit or 32-bit float"
            )))
        }
    };
    Ok(Descriptors { rows, dim, data })
}

/// keylo descriptors as an OpenCV matrix (for matching).
pub fn descriptors_to_mat(d: &Descriptors) -> Result<Mat, FeaturesError> {
    let rows = i32::try_from(d.rows).map_err(|_| FeaturesError::BadInput("rows".into()))?;
    let flat = match &d.data {
        DescriptorData::Binary(b) => Mat::from_slice(b),
        DescriptorData::Float(f) => Mat::from_slice(f),
    }
    .map_err(|e| FeaturesError::opencv("Mat::from_slice", e))?;
    if d.rows == 0 {
        return Ok(Mat::default());
    }
    flat.reshape(1, rows)
        .map_err(|e| FeaturesError::opencv("Mat::reshape", e))?
        .try_clone()
        .map_err(|e| FeaturesError::opencv("Mat::clone", e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Channel;

    #[test]
    fn image_round_trips_through_mat() {
        let mut img = Image::new_gray(5, 3, Channel::Signal);
        for (i, v) in img.data.iter_mut().enumerate() {
            *v = i as u8;
        }
        let mat = to_mat(&img).unwrap();
        assert_eq!((mat.rows(), mat.cols(), mat.channels()), (3, 5, 1));
        assert_eq!(mat_bytes(&mat).unwrap(), img.data);
    }

    #[test]
    fn short_image_buffer_is_an_error() {
        let mut img = Image::new_gray(5, 3, Channel::Signal);
        img.data.truncate(7);
        assert!(matches!(to_mat(&img), Err(FeaturesError::BadInput(_))));
    }

    #[test]
    fn keypoints_round_trip() {
        let k = Keypoint {
            x: 1.5,
            y: 2.5,
            size: 7.0,
            angle: 30.0,
            response: 0.25,
            octave: 2,
            class_id: 3,
        };
        assert_eq!(from_cv_keypoints(&to_cv_keypoints(&[k]).unwrap()), vec![k]);
    }
}
