//! Every config in `configs/paper/` resolves, and runs as is on the real OS-0-128 sample
//! (what `keylo run FILE --data PCAP` does).

use std::path::{Path, PathBuf};

use keylo::config::RawConfig;
use keylo::Pipeline;

fn paper_configs() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/paper");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
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
