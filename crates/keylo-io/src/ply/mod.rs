//! Stanford PLY point files: the `vertex` element's fields, ascii or binary (either byte
//! order), parsed by `ply-rs-bw`.

mod reader;

pub use reader::{ply_fields, read_ply};
