//! What the timing examples share: the paper's real images (`image_0000.png`…, 8-bit grey)
//! read and resized linearly, as the paper does.
#![allow(dead_code)]

use std::path::Path;

use keylo_core::{Channel, Image};
use keylo_features::image::{resize_plane, Interpolation};

/// An 8-bit grey PNG: (pixels, rows, cols).
pub fn read_png(path: &Path) -> Result<(Vec<u8>, usize, usize), Box<dyn std::error::Error>> {
    let file = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info()?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("PNG too large")?];
    let info = reader.next_frame(&mut buf)?;
    if info.color_type != png::ColorType::Grayscale || info.bit_depth != png::BitDepth::Eight {
        return Err(format!("{}: expected an 8-bit grey PNG", path.display()).into());
    }
    buf.truncate(info.buffer_size());
    Ok((buf, info.height as usize, info.width as usize))
}

/// Images `image_0000.png` … of `dir`, `count` of them, resized to `width × height`.
pub fn load(
    dir: &Path,
    count: usize,
    (width, height): (usize, usize),
) -> Result<Vec<Image>, Box<dyn std::error::Error>> {
    (0..count)
        .map(|i| {
            let (data, rows, cols) = read_png(&dir.join(format!("image_{i:04}.png")))?;
            let mut img = Image::new_gray(width, height, Channel::Signal);
            img.data = resize_plane(&data, rows, cols, width, height, Interpolation::Linear)?;
            Ok(img)
        })
        .collect()
}
