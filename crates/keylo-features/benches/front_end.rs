//! Hot paths of the keypoint front end on a real OS-0-128 frame (1024×128): building the
//! signal and range images (normalise + resize to 1024×64), AKAZE and SuperPoint detection, and the
//! keypoint-neighbourhood selection. Run: `cargo bench -p keylo-features`.

use criterion::{criterion_group, criterion_main, Criterion};
use keylo_core::{
    BuildContext, ChannelFeatures, Detector, Downsampler, FrameFeatures, ImageBuilder, ImageSource,
    LidarFrame, Registry,
};
use keylo_features::image::{LidarImageBuilder, LidarImageConfig};
use keylo_features::neighbourhood::{KeypointNeighbourhood, NeighbourhoodConfig};
use keylo_features::superpoint::{ExecutionProvider, SuperPoint, SuperPointParams};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};

fn frame() -> LidarFrame {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap");
    let config = OusterSourceConfig {
        path: path.display().to_string(),
        ..OusterSourceConfig::default()
    };
    let mut source = OusterSource::open(&config, &BuildContext::default()).expect("sample");
    source.next_frame().expect("a frame").expect("decoded")
}

fn bench(c: &mut Criterion) {
    let frame = frame();
    let mut builder = LidarImageBuilder::new(LidarImageConfig {
        images: vec!["signal".into(), "range".into()],
        ..LidarImageConfig::default()
    })
    .expect("config");
    c.bench_function("image: signal + range, 1024x128 -> 1024x64", |b| {
        b.iter(|| builder.build(&frame).expect("images"))
    });
    let images = builder.build(&frame).expect("images");
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let f = registry.detectors.get("akaze").expect("akaze");
    let mut akaze: Box<dyn Detector> = f
        .build(
            &f.resolve(&toml::Table::new()).expect("params"),
            &BuildContext::default(),
        )
        .expect("detector");
    c.bench_function("detect: akaze on signal + range", |b| {
        b.iter(|| {
            for img in &images {
                akaze.detect(img).expect("detect");
            }
        })
    });
    let features = FrameFeatures {
        per_image: images
            .iter()
            .map(|image| ChannelFeatures {
                keypoints: akaze.detect(image).expect("detect"),
                image: image.clone(),
                descriptors: None,
            })
            .collect(),
    };
    let mut two_plane = LidarImageBuilder::new(LidarImageConfig {
        images: vec!["signal+range".into()],
        ..LidarImageConfig::default()
    })
    .expect("config");
    let sr = two_plane.build(&frame).expect("image").remove(0);
    let params = SuperPointParams {
        execution_provider: ExecutionProvider::Cpu,
        ..SuperPointParams::default()
    };
    let mut sp = SuperPoint::new(params, &BuildContext::default()).expect("superpoint");
    c.bench_function(
        "detect+describe: superpoint on signal+range (2 threads)",
        |b| b.iter(|| sp.run(&sr).expect("superpoint")),
    );
    let mut down = KeypointNeighbourhood::new(NeighbourhoodConfig::default()).expect("config");
    c.bench_function("downsample: keypoint-neighbourhood 4_7", |b| {
        b.iter(|| down.downsample(&frame, &features).expect("cloud"))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
