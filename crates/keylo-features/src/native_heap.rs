//! Keeping OpenCV's scratch buffers in the C heap.
//!
//! OpenCV allocates its per-call images (pyramids, diffusion steps) with C++ `new`, i.e.
//! glibc's `malloc`, not Rust's allocator. glibc serves blocks above its mmap threshold
//! (128 KiB, raised dynamically only after such blocks are freed) with fresh `mmap`s and unmaps
//! them on `free`, so every frame faults in zeroed pages again. Measured on real 1024×64
//! images (`scripts/bench/detect_vs_opencv_python.sh`): KAZE 42.8 → 28.8 ms and AKAZE
//! 3.6 → 2.0 ms per image once the thresholds are raised.

/// Raises glibc's mmap threshold to 64 MiB and its trim threshold to 256 MiB for this
/// process, so large, short-lived C allocations are reused instead of re-mapped. Call once at
/// start-up, before threads that allocate. A no-op off glibc.
pub fn keep_native_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: mallopt only changes allocator tunables; it is called before worker threads
        // start and its failure (return 0) leaves the defaults in place.
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, 64 << 20);
            libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
        }
    }
}
