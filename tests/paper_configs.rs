//! Every config in `configs/paper/` (and the SuperPoint examples) resolves, and runs as is on the real OS-0-128 sample
//! (what `keylo run FILE --data PCAP` does).

use std::path::{Path, PathBuf};

use keylo::config::RawConfig;
use keylo::Pipeline;

/// Every config of `configs/paper/`, plus the keypoint examples of `configs/examples/` that
/// take their data from `--data` (`superpoint-*`).
fn paper_configs() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("configs/paper"))
        .unwrap()
        .chain(std::fs::read_dir(root.join("configs/examples")).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| {
            p.parent().is_some_and(|d| d.ends_with("paper"))
                || p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("superpoint-"))
        })
        .collect();
    files.sort();
    files
}

#[test]
fn paper_configs_run_on_the_real_os0_sample() {
    let pcap = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap");
    let registry = keylo::registry();
    let files = paper_configs();
    assert!(files.len() >= 3, "{files:?}");
    for file in files {
        let mut raw = RawConfig::from_file(&file).unwrap();
        raw.set("source.kind=\"ouster\"").unwrap();
        raw.set(&format!("source.path=\"{}\"", pcap.display()))
            .unwrap();
        let config = registry
            .resolve(&raw)
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let mut pipeline = Pipeline::build(&config, &registry)
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let mut frames = 0;
        while let Some(result) = pipeline.step() {
            let r = result.unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            assert!(r.cloud_points > 0);
            if config.detector.kind != "none" {
                assert!(r.keypoints > 0, "{}", file.display());
                assert!(
                    r.cloud_points < 20_000,
                    "{}: {}",
                    file.display(),
                    r.cloud_points
                );
            }
            frames += 1;
        }
        assert_eq!(frames, 2, "{}", file.display());
    }
}
