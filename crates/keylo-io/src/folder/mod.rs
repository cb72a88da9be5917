//! What every folder-of-files source shares: listing files in natural order, time stamps
//! from file names, mapping file fields to cloud channels, the selected files with their
//! times, and turning clouds into frames.

mod columns;
pub mod fields;
mod framer;
mod listing;
mod sequence;

pub use columns::Columns;
pub use framer::Framer;
pub use listing::{
    frame_stamps, has_extension, has_files, index_stamps, list_files, name_stamp, natural_cmp,
};
pub use sequence::{FileEntry, FileSequence};
