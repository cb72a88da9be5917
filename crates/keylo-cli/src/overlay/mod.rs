//! Pictures of one frame as the pipeline saw it (`keylo run --images`, `keylo info --image`,
//! `keylo keypoints eval --images`): each detector image with its keypoints and the pixels
//! the downsampler kept, and a top view of the raw points with the selected ones.

mod canvas;
mod image_view;
mod pictures;
mod single;
mod top_view;

use std::path::Path;

use anyhow::{Context, Result};
use keylo::{Channel, FrameFeatures, LidarFrame, PointCloud};
use serde::{Deserialize, Serialize};

pub use canvas::Canvas;
pub use image_view::{draw, draw_image, ImageView, Kept};
pub use pictures::{Pictures, INDEX};
pub use single::Single;
pub use top_view::draw as draw_top;

/// What one frame gave the pictures.
pub struct FrameOverlay<'a> {
    pub frame: &'a LidarFrame,
    /// The detector images and their keypoints (empty without an image builder).
    pub features: &'a FrameFeatures,
    /// Frame-grid pixels the downsampler kept, when it selects by pixel.
    pub selected_pixels: Option<&'a [usize]>,
    /// The cloud the downsampler gave the registrar.
    pub cloud: Option<&'a PointCloud>,
    /// Every point of the frame (`LidarFrame::to_cloud`), made once for the top view and
    /// the PLY.
    pub raw: &'a PointCloud,
}

/// One frame's pictures, as listed in `images/pictures.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Pictured {
    pub frame: u64,
    pub images: Vec<PicturedImage>,
    pub top: PicturedTop,
    /// `[raw, selected]` PLY files, for the frame that has them.
    pub clouds: Option<[String; 2]>,
}

/// One image picture: file name, image name, keypoints drawn.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PicturedImage {
    pub file: String,
    pub image: String,
    pub keypoints: usize,
}

/// The top view: file name, its scale and the points in it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PicturedTop {
    pub file: String,
    pub half_extent_m: f64,
    pub ring_step_m: f64,
    pub raw_points: usize,
    pub selected_points: usize,
}

/// File name stem of frame `index`'s pictures.
pub fn stem(index: u64) -> String {
    format!("frame_{index:06}")
}

/// Writes `frame_NNNNNN_<image>.png` for every detector image (every channel with data when
/// there is none) and `frame_NNNNNN_top.png` into `dir`; returns what it wrote.
pub fn write(dir: &Path, o: &FrameOverlay) -> Result<Pictured> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let stem = stem(o.frame.index);
    let kept = o.selected_pixels.map(|pixels| Kept {
        pixels,
        rows: o.frame.rows,
        cols: o.frame.cols,
    });
    let mut images = Vec::new();
    let save = |name: &str, canvas: Canvas| -> Result<String> {
        let file = format!("{stem}_{name}.png");
        canvas.write_png(&dir.join(&file))?;
        Ok(file)
    };
    for c in &o.features.per_image {
        let img = &c.image;
        images.push(PicturedImage {
            file: save(&img.name(), draw_image(img, &c.keypoints, kept.as_ref()))?,
            image: img.name(),
            keypoints: c.keypoints.len(),
        });
    }
    if o.features.per_image.is_empty() {
        for channel in channels_with_data(o.frame) {
            let gray = keylo::io::export::png_image::stretched(o.frame, channel);
            let view = ImageView {
                gray: &gray,
                width: o.frame.cols,
                height: o.frame.rows,
                scale_x: 1.0,
                scale_y: 1.0,
                keypoints: &[],
            };
            images.push(PicturedImage {
                file: save(channel.name(), draw(&view, kept.as_ref()))?,
                image: channel.name().into(),
                keypoints: 0,
            });
        }
    }
    let raw = o.raw;
    let selected = o.cloud.map_or(&[][..], |c| &c.points[..]);
    let top = draw_top(&raw.points, selected);
    Ok(Pictured {
        frame: o.frame.index,
        images,
        top: PicturedTop {
            file: save("top", top.canvas)?,
            half_extent_m: top.half_extent_m,
            ring_step_m: top.ring_step_m,
            raw_points: raw.len(),
            selected_points: selected.len(),
        },
        clouds: None,
    })
}

/// Writes the frame's raw points and the registered ones as `frame_NNNNNN_raw.ply` and
/// `frame_NNNNNN_selected.ply` (sensor frame), for 3-D views; returns their names.
pub fn write_clouds(dir: &Path, o: &FrameOverlay) -> Result<[String; 2]> {
    let stem = stem(o.frame.index);
    let names = [format!("{stem}_raw.ply"), format!("{stem}_selected.ply")];
    let (raw_path, sel_path) = (dir.join(&names[0]), dir.join(&names[1]));
    let what = format!("frame {} of keylo run", o.frame.index);
    crate::cloud_ply::write(&raw_path, &o.raw.points, &format!("raw {what}"))?;
    let selected = o.cloud.map_or(&[][..], |c| &c.points[..]);
    crate::cloud_ply::write(&sel_path, selected, &format!("registered points, {what}"))?;
    Ok(names)
}

/// The channels with a valid, non-zero pixel (a sensor without near-IR leaves it all zero).
fn channels_with_data(frame: &LidarFrame) -> Vec<Channel> {
    if frame.rows * frame.cols == 0 {
        return Vec::new();
    }
    Channel::ALL
        .into_iter()
        .filter(|&c| {
            frame
                .channel(c)
                .iter()
                .zip(&frame.valid)
                .any(|(v, ok)| *ok && v.is_finite() && *v != 0.0)
        })
        .collect()
}
