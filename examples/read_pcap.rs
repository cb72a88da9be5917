//! Reading an Ouster capture frame by frame, without the pipeline: the source alone.
//!
//! `cargo run --example read_pcap -- tests/fixtures/ouster/OS-0-32-U1_v2.2.0_1024x10.pcap`
//! (the metadata JSON is found beside the capture).

use std::path::Path;

/// One line per frame: index, time, grid size and valid pixels. Returns the lines.
pub fn run(pcap: &Path) -> Result<Vec<String>, keylo::CoreError> {
    let registry = keylo::registry();
    let text = format!(
        "[source]\nkind = \"ouster\"\npath = {}\n",
        toml::Value::String(pcap.display().to_string())
    );
    let raw = keylo::config::RawConfig::parse("read_pcap", &text)?;
    let config = registry.resolve(&raw)?;
    let mut source = keylo::build_source(&config, &registry)?;
    let mut lines = Vec::new();
    while let Some(frame) = source.next_frame() {
        let frame = frame?;
        lines.push(format!(
            "frame {} at {:.3} s: {} x {} pixels, {} valid",
            frame.index,
            frame.timestamp,
            frame.rows,
            frame.cols,
            frame.valid_count()
        ));
    }
    Ok(lines)
}

#[allow(dead_code)] // a test includes this file as a module
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: read_pcap CAPTURE.pcap")?;
    for line in run(Path::new(&path))? {
        println!("{line}");
    }
    Ok(())
}
