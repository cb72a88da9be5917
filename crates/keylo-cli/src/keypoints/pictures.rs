//! `keylo keypoints eval --images N`: each detector's keypoints drawn on every N-th image,
//! into OUT/images/DETECTOR_NNNNN.png.

use std::path::Path;

use anyhow::{Context, Result};
use keylo::kpeval::pictures::Pictured;

use crate::overlay::draw_image;

/// Writes one picture per detector and image; returns how many.
pub fn write(out: &Path, pictured: &[Pictured]) -> Result<usize> {
    let dir = out.join("images");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    for p in pictured {
        let name = crate::compare::slug(&p.detector);
        draw_image(&p.image, &p.keypoints, None)
            .write_png(&dir.join(format!("{name}_{:05}.png", p.index)))?;
    }
    Ok(pictured.len())
}
