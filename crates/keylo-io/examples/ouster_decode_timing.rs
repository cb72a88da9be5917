//! Times reading an Ouster capture into destaggered frames with XYZ (packet decode, batching,
//! destagger, XYZ, per-pixel times): prints milliseconds per frame as JSON. Opening the
//! source (metadata, XYZ table) is per sensor, not per frame, and is timed apart.
//! `scripts/bench/ouster_vs_sdk.sh` runs it beside ouster-sdk on the same capture.
//!
//! Usage: ouster_decode_timing PCAP [REPEATS]

use std::path::PathBuf;
use std::time::Instant;

use keylo_core::{BuildContext, ImageSource};
use keylo_io::ouster::{OusterSource, OusterSourceConfig, PartialFrames};

// The allocator the `keylo` binary uses: frames are large, short-lived buffers, which glibc's
// malloc hands back to the kernel and faults in again for every frame.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let pcap = args
        .next()
        .ok_or("usage: ouster_decode_timing PCAP [REPEATS]")?;
    let repeats: usize = args.next().map_or(Ok(20), |r| r.parse())?;
    let config = OusterSourceConfig {
        path: pcap.clone(),
        partial_frames: PartialFrames::Keep,
        ..OusterSourceConfig::default()
    };
    let ctx = BuildContext {
        base_dir: PathBuf::from("."),
        ..Default::default()
    };
    let (mut frames, mut checksum) = (0usize, 0.0f64);
    let (mut open_s, mut frames_s) = (0.0, 0.0);
    for _ in 0..repeats {
        let t = Instant::now();
        let mut source = OusterSource::open(&config, &ctx)?;
        open_s += t.elapsed().as_secs_f64();
        let t = Instant::now();
        while let Some(frame) = source.next_frame() {
            let f = frame?;
            checksum += f64::from(f.points[f.points.len() / 2].x);
            frames += 1;
        }
        frames_s += t.elapsed().as_secs_f64();
    }
    let ms = frames_s * 1e3 / frames.max(1) as f64;
    let open_ms = open_s * 1e3 / repeats.max(1) as f64;
    println!(
        "{{\"tool\": \"keylo\", \"frames\": {frames}, \"ms_per_frame\": {ms:.3}, \
         \"open_ms\": {open_ms:.3}, \"checksum\": {checksum:.3}}}"
    );
    Ok(())
}
