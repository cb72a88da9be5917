//! Ouster sensor metadata JSON and pcap captures.

use std::path::Path;

use keylo_core::BuildContext;
use keylo_io::ouster::{
    Destaggerer, OusterMetadata, OusterSource, OusterSourceConfig, PacketFormat, PartialFrames,
    XyzLut,
};

use crate::scratch;

/// The metadata of the committed Ouster samples (BSD-3, `tests/fixtures/ouster/`): an
/// `ouster_pcap` input's first byte picks one (`fuzz/make_seeds.py` lists them in this order).
const METADATA: [&str; 8] = [
    include_str!("../../../tests/fixtures/ouster/OS-0-32-U1_v2.2.0_1024x10.json"),
    include_str!("../../../tests/fixtures/ouster/OS-1-32-G_v2.1.1_1024x10.json"),
    include_str!("../../../tests/fixtures/ouster/OS-1-64_1024x10_fw20.json"),
    include_str!("../../../tests/fixtures/ouster/OS-1-128_v2.3.0_1024x10_lb_n3.json"),
    include_str!("../../../tests/fixtures/ouster/OS-2-128-U1_v2.3.0_1024x10.json"),
    include_str!("../../../tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf.json"),
    include_str!("../../../tests/fixtures/ouster/OS-0-128_v3.2.0-rc7_2048x10_dual_from_osf.json"),
    include_str!("../../../tests/fixtures/ouster/crc_test.json"),
];

/// A metadata JSON: parsed, then everything built from it (packet format, destaggering,
/// XYZ table).
pub fn ouster_metadata(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(meta) = OusterMetadata::parse(Path::new("fuzz.json"), text) else {
        return;
    };
    let _ = PacketFormat::new(&meta);
    let _ = Destaggerer::new(&meta);
    let _ = XyzLut::new(&meta);
}

/// A pcap capture after one selector byte (its value modulo the number of samples picks the
/// metadata; bit 7 asks for the second return), read as source kind
/// `ouster` with one of the sample metadata files.
pub fn ouster_pcap(data: &[u8]) {
    let Some((&selector, pcap)) = data.split_first() else {
        return;
    };
    let meta = METADATA[usize::from(selector) % METADATA.len()];
    let files = [("capture.pcap", pcap), ("capture.json", meta.as_bytes())];
    scratch::with_files(&files, true, |dir| {
        let config = OusterSourceConfig {
            path: "capture.pcap".into(),
            partial_frames: PartialFrames::Keep,
            return_number: 1 + (selector >> 7),
            ..OusterSourceConfig::default()
        };
        let ctx = BuildContext {
            base_dir: dir.to_path_buf(),
            ..Default::default()
        };
        if let Ok(mut source) = OusterSource::open(&config, &ctx) {
            crate::drain(&mut source);
        }
    });
}
