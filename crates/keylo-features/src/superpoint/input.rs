//! An 8-bit keylo [`Image`] as the network's input: planes mapped to the model's channels,
//! values scaled to [0, 1], zero-padded to multiples of 8.

use keylo_core::Image;

use super::decode::CELL;
use crate::FeaturesError;

/// The input tensor data (`channels × h × w`) and its size.
#[derive(Debug)]
pub struct Input {
    pub data: Vec<f32>,
    pub channels: usize,
    pub w: usize,
    pub h: usize,
}

/// `image` for a model taking `model_channels` channels (`None`: as many as the image has).
/// A one-plane image feeds every channel of a two-channel model; a two-plane image cannot
/// feed a one-channel model.
pub fn prepare(
    image: &Image,
    model_channels: Option<usize>,
    model: &str,
) -> Result<Input, FeaturesError> {
    let planes = image.channels;
    if planes == 0 || planes > 2 {
        return Err(FeaturesError::BadInput(format!(
            "image `{}` has {planes} planes, SuperPoint takes 1 or 2",
            image.name()
        )));
    }
    let channels = model_channels.unwrap_or(planes);
    if channels < planes {
        return Err(FeaturesError::BadInput(format!(
            "SuperPoint model `{model}` takes {channels} channel(s), image `{}` has {planes} planes: \
             use one-channel images (e.g. images = [\"signal\", \"range\"]) or a two-channel model",
            image.name()
        )));
    }
    let row_bytes = image.width * planes;
    let needed = image.stride * image.height.saturating_sub(1) + row_bytes;
    if image.width == 0
        || image.height == 0
        || image.stride < row_bytes
        || image.data.len() < needed
    {
        return Err(FeaturesError::BadInput(format!(
            "image `{}` {}x{}x{planes} with stride {} and {} bytes is not a valid image",
            image.name(),
            image.width,
            image.height,
            image.stride,
            image.data.len()
        )));
    }
    let w = image.width.div_ceil(CELL) * CELL;
    let h = image.height.div_ceil(CELL) * CELL;
    let mut data = vec![0.0f32; channels * w * h];
    for c in 0..channels {
        let plane = c.min(planes - 1);
        let out = &mut data[c * w * h..(c + 1) * w * h];
        for y in 0..image.height {
            let row = &image.data[y * image.stride..y * image.stride + row_bytes];
            for (x, px) in row.iter().skip(plane).step_by(planes).enumerate() {
                out[y * w + x] = f32::from(*px) / 255.0;
            }
        }
    }
    Ok(Input {
        data,
        channels,
        w,
        h,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Channel;

    fn two_plane(w: usize, h: usize) -> Image {
        let mut img = Image::new_gray(w, h, Channel::Signal);
        img.channels = 2;
        img.stride = 2 * w;
        img.sources.push(Channel::Range);
        img.data = (0..2 * w * h).map(|i| (i % 251) as u8).collect();
        img
    }

    #[test]
    fn pads_to_multiples_of_eight_and_deinterleaves() {
        let img = two_plane(10, 3);
        let input = prepare(&img, Some(2), "m").unwrap();
        assert_eq!((input.channels, input.w, input.h), (2, 16, 8));
        // Plane 1 of pixel (x = 4, y = 2) is byte 2·(2·10 + 4) + 1.
        let byte = img.data[2 * (2 * 10 + 4) + 1];
        assert_eq!(input.data[16 * 8 + 2 * 16 + 4], f32::from(byte) / 255.0);
        assert_eq!(input.data[16 * 8 + 2 * 16 + 12], 0.0); // padding
    }

    #[test]
    fn one_plane_feeds_both_channels_but_two_planes_need_two() {
        let mut img = Image::new_gray(8, 8, Channel::Range);
        img.data[9] = 255;
        let input = prepare(&img, Some(2), "m").unwrap();
        assert_eq!((input.data[9], input.data[64 + 9]), (1.0, 1.0));
        let e = prepare(&two_plane(8, 8), Some(1), "m")
            .unwrap_err()
            .to_string();
        assert!(e.contains("1 channel") && e.contains("signal+range"), "{e}");
    }
}
