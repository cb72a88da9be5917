//! PCL PCD point files: ascii, binary and binary_compressed data, parsed by `pcd-rs`;
//! organised when `HEIGHT > 1`.

mod reader;

pub use reader::{pcd_fields, read_pcd};
