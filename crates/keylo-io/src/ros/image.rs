//! `sensor_msgs/Image` → one channel grid (`f32`, row-major), and the column shift between
//! destaggered images and the staggered clouds ouster-ros publishes.

use super::msgs::Image;

/// Pixel values of `mono8`/`8UC1` (u8), `mono16`/`16UC1` (u16, byte order from
/// `is_bigendian`) and `32FC1` (f32) images, row-major, `step` padding skipped.
pub(crate) fn pixels(img: &Image) -> Result<Vec<f32>, String> {
    let (h, w, step) = (img.height as usize, img.width as usize, img.step as usize);
    let size = match img.encoding {
        "mono8" | "8UC1" => 1,
        "mono16" | "16UC1" => 2,
        "32FC1" => 4,
        other => {
            return Err(format!(
                "image encoding `{other}` is not supported (expected mono8, mono16 or 32FC1)"
            ))
        }
    };
    let row_bytes = w.saturating_mul(size);
    if step < row_bytes {
        return Err(format!(
            "step {step} is less than width {w} × {size} bytes = {row_bytes}"
        ));
    }
    let expected = h.saturating_mul(step);
    if img.data.len() != expected {
        return Err(format!(
            "data holds {} bytes but height × step = {h} × {step} = {expected}",
            img.data.len()
        ));
    }
    let big = img.is_bigendian;
    let mut out = Vec::with_capacity(h * w);
    for row in img.data.chunks_exact(step.max(1)).take(h) {
        let row = &row[..row_bytes];
        match size {
            1 => out.extend(row.iter().map(|&b| f32::from(b))),
            2 => out.extend(row.chunks_exact(2).map(|b| {
                let v = [b[0], b[1]];
                f32::from(if big {
                    u16::from_be_bytes(v)
                } else {
                    u16::from_le_bytes(v)
                })
            })),
            _ => out.extend(row.chunks_exact(4).map(|b| {
                let v = [b[0], b[1], b[2], b[3]];
                if big {
                    f32::from_be_bytes(v)
                } else {
                    f32::from_le_bytes(v)
                }
            })),
        }
    }
    Ok(out)
}

/// The grid in the cloud's (staggered) column order: cloud pixel `(r, c)` is image pixel
/// `(r, (c + shift[r]) mod cols)`, which undoes ouster-ros' destaggering. A one-entry
/// `shift` applies to every row.
pub fn restagger(image: &[f32], rows: usize, cols: usize, shift: &[i64]) -> Vec<f32> {
    if cols == 0 || shift.iter().all(|&s| s == 0) {
        return image.to_vec();
    }
    let mut out = vec![0.0; rows * cols];
    for r in 0..rows {
        let s = shift.get(r).or(shift.last()).copied().unwrap_or(0);
        let s = s.rem_euclid(cols as i64) as usize;
        for c in 0..cols {
            out[r * cols + c] = image[r * cols + (c + s) % cols];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ros::msgs::Header;

    fn image<'a>(encoding: &'a str, w: u32, step: u32, big: bool, data: &'a [u8]) -> Image<'a> {
        Image {
            header: Header {
                stamp_ns: 0,
                frame_id: "",
            },
            height: (data.len() / step as usize) as u32,
            width: w,
            encoding,
            is_bigendian: big,
            step,
            data,
        }
    }

    #[test]
    fn encodings_byte_orders_and_padding() {
        assert_eq!(
            pixels(&image("mono8", 2, 3, false, &[1, 2, 0, 3, 4, 0])).unwrap(),
            vec![1.0, 2.0, 3.0, 4.0]
        );
        assert_eq!(
            pixels(&image("mono16", 1, 2, true, &[1, 2])).unwrap(),
            vec![258.0]
        );
        assert_eq!(
            pixels(&image("16UC1", 1, 2, false, &[1, 2])).unwrap(),
            vec![513.0]
        );
        let f = 1.5f32.to_le_bytes();
        assert_eq!(pixels(&image("32FC1", 1, 4, false, &f)).unwrap(), vec![1.5]);
    }

    #[test]
    fn bad_images_are_errors() {
        let e = pixels(&image("rgb8", 1, 3, false, &[0; 3])).unwrap_err();
        assert!(e.contains("rgb8"), "{e}");
        let mut img = image("mono16", 2, 4, false, &[0; 8]);
        img.step = 3;
        assert!(pixels(&img).unwrap_err().contains("step 3"));
        img.step = 4;
        img.height = 3;
        assert!(pixels(&img).unwrap_err().contains("data holds 8 bytes"));
    }

    #[test]
    fn restagger_undoes_destaggering() {
        // Destaggered image(u, v) = staggered(u, v - shift[u]).
        let staggered = [0.0, 1.0, 2.0, 3.0, 10.0, 11.0, 12.0, 13.0];
        let shift = [1i64, -2];
        let mut destaggered = [0.0f32; 8];
        for u in 0..2 {
            for v in 0..4i64 {
                let src = (v - shift[u]).rem_euclid(4) as usize;
                destaggered[u * 4 + v as usize] = staggered[u * 4 + src];
            }
        }
        assert_eq!(restagger(&destaggered, 2, 4, &shift), staggered.to_vec());
        assert_eq!(restagger(&staggered, 2, 4, &[0]), staggered.to_vec());
    }
}
