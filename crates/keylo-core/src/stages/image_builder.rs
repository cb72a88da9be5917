use crate::{CoreError, Image, LidarFrame};

/// Turns a frame's channels into the 8-bit images detectors run on (normalisation, resize).
///
/// Owns: its normalisation and interpolation settings. Returns one [`Image`] per configured
/// channel (or channel pair), with `scale_x/scale_y` set so keypoints map back to the grid.
pub trait ImageBuilder: Send {
    /// Images for one frame.
    fn build(&mut self, frame: &LidarFrame) -> Result<Vec<Image>, CoreError>;

    /// The names ([`Image::name`]) of the images every frame yields, in order, when known in
    /// advance. The pipeline then gives each image its own detector and descriptor instance
    /// and runs the images in parallel. Empty (the default): unknown, one shared instance.
    fn image_names(&self) -> Vec<String> {
        Vec::new()
    }
}
