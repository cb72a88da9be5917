//! Hot paths of the keypoint front end on a real OS-0-128 frame (1024×128): building the
//! signal and range images (normalise + resize to 1024×64), AKAZE and SuperPoint detection, and the
//! keypoint-neighbourhood selection; and the native BRIEF / FREAK descriptors on the parity
//! fixture (tests/fixtures/native_descriptors: 14 images × 2 keypoint sets per iteration, the
//! workload `make_golden.py` times OpenCV on). Run: `cargo bench -p keylo-features`.

use criterion::{criterion_group, criterion_main, Criterion};
use keylo_core::{
    BuildContext, Channel, ChannelFeatures, Descriptor, Detector, Downsampler, FrameFeatures,
    Image, ImageBuilder, ImageSource, Keypoint, LidarFrame, Registry,
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

/// The parity fixture's images, each with its FAST and Shi-Tomasi keypoints.
fn fixture() -> Vec<(Image, Vec<Keypoint>)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/fixtures/native_descriptors");
    let text = std::fs::read_to_string(dir.join("keypoints.json")).expect("fixture");
    let doc: serde_json::Value = serde_json::from_str(&text).expect("json");
    let mut out = Vec::new();
    for v in doc["images"].as_object().expect("images").values() {
        let file = std::fs::File::open(dir.join(v["file"].as_str().expect("file"))).expect("png");
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .expect("png");
        let mut buf = vec![0; reader.output_buffer_size().expect("size")];
        let info = reader.next_frame(&mut buf).expect("frame");
        let mut img = Image::new_gray(info.width as usize, info.height as usize, Channel::Signal);
        img.data = buf[..img.data.len()].to_vec();
        for rows in v["keypoints"].as_object().expect("sets").values() {
            let kps = rows
                .as_array()
                .expect("rows")
                .iter()
                .map(|r| Keypoint {
                    x: r[0].as_f64().expect("x") as f32,
                    y: r[1].as_f64().expect("y") as f32,
                    size: r[2].as_f64().expect("size") as f32,
                    angle: r[3].as_f64().expect("angle") as f32,
                    ..Keypoint::default()
                })
                .collect();
            out.push((img.clone(), kps));
        }
    }
    out
}

fn bench_native(c: &mut Criterion) {
    let cases = fixture();
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    for kind in ["brief", "freak"] {
        let f = registry.descriptors.get(kind).expect("kind");
        let mut d: Box<dyn Descriptor> = f
            .build(
                &f.resolve(&toml::Table::new()).expect("params"),
                &BuildContext::default(),
            )
            .expect("descriptor");
        let name = format!("describe: {kind}, {} fixture calls", cases.len());
        c.bench_function(&name, |b| {
            b.iter(|| {
                for (img, kps) in &cases {
                    let mut kps = kps.clone();
                    d.describe(img, &mut kps).expect("describe");
                }
            })
        });
    }
}

criterion_group!(benches, bench, bench_native);
criterion_main!(benches);
