//! The native part of the `keylo` Python package (`keylo._keylo`); the package in
//! `python/keylo` re-exports it with type stubs.

mod arrays;
mod config;
mod detectors;
mod downsampler;
mod errors;
mod eval;
mod frames;
mod keypoints;
mod odometry;
mod result;
mod verdict;

use pyo3::prelude::*;

// mimalloc, as the `keylo` binary: a frame owns several MB of fresh buffers, and glibc's
// malloc hands them back to the kernel and maps them again frame after frame
// (docs/results/ouster-decode.md). Arrays lent to numpy are freed by Rust, so by it as well.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[pymodule]
fn _keylo(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    m.add_class::<odometry::Odometry>()?;
    m.add_class::<result::FrameResult>()?;
    m.add_class::<frames::Frame>()?;
    m.add_class::<frames::Reader>()?;
    m.add_function(wrap_pyfunction!(frames::open, m)?)?;
    m.add_function(wrap_pyfunction!(detectors::register_detector, m)?)?;
    m.add_function(wrap_pyfunction!(eval::evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(verdict::judge, m)?)?;
    m.add_function(wrap_pyfunction!(keypoints::evaluate_keypoints, m)?)?;
    Ok(())
}
