//! The evaluated input: one full-resolution 8-bit plane per frame, from a LiDAR frame's
//! channel or from a PNG file, resized per evaluated size.

use std::path::Path;

use keylo_core::{Channel, Image, LidarFrame};
use keylo_features::image::{resize_plane, Interpolation, Normalise};

use crate::KpEvalError;

/// A row-major 8-bit image at the frame's own resolution.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    pub rows: usize,
    pub cols: usize,
    pub data: Vec<u8>,
    /// Where it came from (frame index or file name), for messages and the CSV.
    pub label: String,
}

impl Plane {
    /// `channel` of `frame`, made 8-bit by `normalise` (invalid pixels 0).
    pub fn from_frame(
        frame: &LidarFrame,
        channel: Channel,
        normalise: &Normalise,
        label: String,
    ) -> Self {
        Self {
            rows: frame.rows,
            cols: frame.cols,
            data: normalise.to_u8(frame.channel(channel), &frame.valid),
            label,
        }
    }

    /// A grey PNG (8-bit as it is, 16-bit through `normalise`; colour converted to grey with
    /// the ITU-R 601 weights, as OpenCV's `cvtColor` does).
    pub fn from_png(path: &Path, normalise: &Normalise) -> Result<Self, KpEvalError> {
        let bad = |m: String| KpEvalError::Format {
            path: path.to_path_buf(),
            message: m,
        };
        let file = std::fs::File::open(path).map_err(|e| KpEvalError::io(path, e))?;
        let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder
            .read_info()
            .map_err(|e| bad(format!("not a readable PNG: {e}")))?;
        let mut buf = vec![0; reader.output_buffer_size().unwrap_or(0)];
        let info = reader
            .next_frame(&mut buf)
            .map_err(|e| bad(format!("not a readable PNG: {e}")))?;
        let (cols, rows) = (info.width as usize, info.height as usize);
        let samples = info.color_type.samples();
        let wide = info.bit_depth == png::BitDepth::Sixteen;
        let bytes = &buf[..info.buffer_size()];
        let sample = |i: usize| -> f32 {
            if wide {
                f32::from(u16::from_be_bytes([bytes[2 * i], bytes[2 * i + 1]]))
            } else {
                f32::from(bytes[i])
            }
        };
        let grey: Vec<f32> = (0..rows * cols)
            .map(|p| match samples {
                1 | 2 => sample(p * samples),
                _ => {
                    let (r, g, b) = (
                        sample(p * samples),
                        sample(p * samples + 1),
                        sample(p * samples + 2),
                    );
                    0.299 * r + 0.587 * g + 0.114 * b
                }
            })
            .collect();
        let data = if wide {
            normalise.to_u8(&grey, &vec![true; grey.len()])
        } else {
            grey.iter()
                .map(|v| v.round().clamp(0.0, 255.0) as u8)
                .collect()
        };
        if rows == 0 || cols == 0 {
            return Err(bad("the image is empty".into()));
        }
        Ok(Self {
            rows,
            cols,
            data,
            label: path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        })
    }

    /// This plane resized to `width × height` (0: its own size) as a one-plane image.
    pub fn image(
        &self,
        width: usize,
        height: usize,
        interpolation: Interpolation,
        source: Channel,
    ) -> Result<Image, KpEvalError> {
        let w = if width == 0 { self.cols } else { width };
        let h = if height == 0 { self.rows } else { height };
        let data = resize_plane(&self.data, self.rows, self.cols, w, h, interpolation)?;
        let mut image = Image::new_gray(w, h, source);
        image.data = data;
        image.scale_x = self.cols as f64 / w as f64;
        image.scale_y = self.rows as f64 / h as f64;
        Ok(image)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write_png(path: &Path, w: u32, h: u32, depth: png::BitDepth, data: &[u8]) {
        let f = std::fs::File::create(path).unwrap();
        let mut e = png::Encoder::new(f, w, h);
        e.set_color(png::ColorType::Grayscale);
        e.set_depth(depth);
        e.write_header().unwrap().write_image_data(data).unwrap();
    }

    #[test]
    fn png_planes_eight_and_sixteen_bit() {
        let dir = tempfile::tempdir().unwrap();
        let p8 = dir.path().join("a.png");
        write_png(&p8, 3, 2, png::BitDepth::Eight, &[0, 10, 20, 30, 40, 255]);
        let plane = Plane::from_png(&p8, &Normalise::default()).unwrap();
        assert_eq!((plane.rows, plane.cols), (2, 3));
        assert_eq!(plane.data, vec![0, 10, 20, 30, 40, 255]);
        assert_eq!(plane.label, "a.png");
        let p16 = dir.path().join("b.png");
        let values: Vec<u8> = [0u16, 1000, 2000, 3000]
            .iter()
            .flat_map(|v| v.to_be_bytes())
            .collect();
        write_png(&p16, 2, 2, png::BitDepth::Sixteen, &values);
        let plane = Plane::from_png(&p16, &Normalise::default()).unwrap();
        assert_eq!(plane.data.len(), 4);
        assert!(plane.data[0] < plane.data[3], "{:?}", plane.data);
        let img = plane
            .image(4, 4, Interpolation::Linear, Channel::Signal)
            .unwrap();
        assert_eq!((img.width, img.height, img.data.len()), (4, 4, 16));
        assert_eq!(img.scale_x, 0.5);
    }

    #[test]
    fn a_broken_png_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bad.png");
        std::fs::write(&p, b"not a png").unwrap();
        let e = Plane::from_png(&p, &Normalise::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("bad.png") && e.contains("PNG"), "{e}");
    }
}
