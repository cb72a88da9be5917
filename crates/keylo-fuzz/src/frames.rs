//! keylo's own frame folders: `.klf` frame files and the `keylo-frames.json` manifest.

use std::path::Path;
use std::sync::Arc;

use keylo_core::{BeamGeometry, BuildContext};
use keylo_io::frames::{codec, FramesSource, FramesSourceConfig, FRAMES_DIR, MANIFEST};

use crate::{parts, scratch};

/// One `.klf` frame file.
pub fn klf(data: &[u8]) {
    let beams = Arc::new(BeamGeometry::unknown("fuzz", 16));
    if let Ok(frame) = codec::decode(Path::new("fuzz.klf"), data, &beams) {
        crate::check_frame(&frame);
    }
}

/// A frame folder of two parts ([`parts::split`]): the manifest and one frame file, read as
/// source kind `frames`.
pub fn frames_folder(data: &[u8]) {
    let [manifest, frame] = parts::split::<2>(data);
    let frame_name = format!("{FRAMES_DIR}/000000.klf");
    let files = [(MANIFEST, manifest), (frame_name.as_str(), frame)];
    scratch::with_files(&files, true, |dir| {
        let config = FramesSourceConfig {
            path: ".".into(),
            ..FramesSourceConfig::default()
        };
        let ctx = BuildContext {
            base_dir: dir.to_path_buf(),
            ..Default::default()
        };
        if let Ok(mut source) = FramesSource::open(&config, &ctx) {
            crate::drain(&mut source);
        }
    });
}
