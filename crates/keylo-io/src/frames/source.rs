use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use keylo_core::{BeamGeometry, BuildContext, CoreError, ImageSource, LidarFrame, SourceInfo};
use serde::{Deserialize, Serialize};

use super::{codec, Manifest, FRAMES_DIR, MANIFEST};
use crate::select::FrameSelection;
use crate::IoError;

/// `[source] kind = "frames"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct FramesSourceConfig {
    /// The frame folder (holding keylo-frames.json); relative to the config file.
    pub path: String,
    /// Index of the first frame to read.
    pub start: usize,
    /// Read every `stride`-th frame.
    pub stride: usize,
    /// Frames to read at most; 0 = all.
    pub max_frames: usize,
}

impl Default for FramesSourceConfig {
    fn default() -> Self {
        Self {
            path: String::new(),
            start: 0,
            stride: 1,
            max_frames: 0,
        }
    }
}

/// True when `path` is a folder with a `keylo-frames.json` manifest.
pub fn is_frames_dir(path: &Path) -> bool {
    path.join(MANIFEST).is_file()
}

/// Reads a keylo frame folder frame by frame.
pub struct FramesSource {
    dir: PathBuf,
    rows: usize,
    cols: usize,
    files: Vec<PathBuf>,
    next: usize,
    beams: Arc<BeamGeometry>,
    /// The last frame file's bytes (the allocation is reused).
    buf: Vec<u8>,
}

impl FramesSource {
    /// Opens a folder; errors name the folder or file that is wrong.
    pub fn open(config: &FramesSourceConfig, ctx: &BuildContext) -> Result<Self, IoError> {
        if config.path.is_empty() {
            return Err(IoError::format(
                Path::new("source.path"),
                "no frame folder given: set `[source] path` or pass --data",
            ));
        }
        let dir = ctx.resolve_path(&config.path);
        let manifest_path = dir.join(MANIFEST);
        if !manifest_path.is_file() {
            return Err(IoError::format(
                &dir,
                format!("not a keylo frame folder: {MANIFEST} is missing"),
            ));
        }
        let manifest = Manifest::read(&manifest_path)?;
        let files = list_frames(&dir.join(FRAMES_DIR))?;
        if files.len() != manifest.frames {
            return Err(IoError::format(
                &manifest_path,
                format!(
                    "lists {} frames but {} holds {}",
                    manifest.frames,
                    FRAMES_DIR,
                    files.len()
                ),
            ));
        }
        if files.is_empty() {
            return Err(IoError::format(&dir, "the folder holds no frame"));
        }
        let selection = FrameSelection::new(config.start, config.stride, config.max_frames)
            .and_then(|s| s.indices(files.len()))
            .map_err(|m| IoError::format(&dir, m))?;
        let files = selection.into_iter().map(|i| files[i].clone()).collect();
        Ok(Self {
            dir,
            rows: manifest.rows,
            cols: manifest.cols,
            files,
            next: 0,
            beams: Arc::new(manifest.beams),
            buf: Vec::new(),
        })
    }
}

/// Reads the file at `path` into `buf`, whose allocation is reused from frame to frame (a
/// fresh 4 MB buffer per frame costs the kernel's zeroing of fresh pages).
fn read_into(path: &Path, buf: &mut Vec<u8>) -> Result<(), IoError> {
    buf.clear();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(buf))
        .map(|_| ())
        .map_err(|e| IoError::io(path, e))
}

fn list_frames(dir: &Path) -> Result<Vec<PathBuf>, IoError> {
    let entries = std::fs::read_dir(dir).map_err(|e| IoError::io(dir, e))?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "klf"))
        .collect();
    files.sort();
    Ok(files)
}

impl ImageSource for FramesSource {
    fn info(&self) -> SourceInfo {
        SourceInfo {
            description: format!("keylo frames {}", self.dir.display()),
            frames: Some(self.files.len()),
        }
    }

    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
        let path = self.files.get(self.next)?;
        self.next += 1;
        let (rows, cols) = (self.rows, self.cols);
        let frame = read_into(path, &mut self.buf)
            .and_then(|()| codec::decode(path, &self.buf, &self.beams))
            .and_then(|f| {
                if (f.rows, f.cols) == (rows, cols) {
                    Ok(f)
                } else {
                    let msg = format!(
                        "frame is {}x{}, the folder's manifest says {rows}x{cols}",
                        f.rows, f.cols
                    );
                    Err(IoError::format(path, msg))
                }
            });
        Some(frame.map_err(CoreError::from))
    }
}
