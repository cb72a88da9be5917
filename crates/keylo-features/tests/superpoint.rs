//! SuperPoint through ONNX Runtime on a real OS-0-128 frame, against ONNX Runtime's Python API
//! on the same image (golden made by `tests/fixtures/superpoint/make_golden.py`), plus the
//! one-channel path, the descriptor stage and every bad-model error.

mod common;

use std::path::PathBuf;

use keylo_core::{
    BuildContext, Descriptor, DescriptorData, Descriptors, Detector, Image, Keypoint,
};
use keylo_features::image::LidarImageConfig;
use keylo_features::superpoint::{ExecutionProvider, Precision, SuperPoint, SuperPointParams};
use serde_json::Value;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/superpoint")
}

fn cpu_params() -> SuperPointParams {
    SuperPointParams {
        execution_provider: ExecutionProvider::Cpu,
        ..SuperPointParams::default()
    }
}

fn with_model(file: &str) -> SuperPointParams {
    SuperPointParams {
        model: fixtures().join(file).display().to_string(),
        ..cpu_params()
    }
}

/// The two-plane signal+range image of the sample's first frame, as the golden saw it.
fn signal_range_image() -> Image {
    let frame = common::os0_frames().remove(0);
    let config = LidarImageConfig {
        images: vec!["signal+range".into()],
        ..LidarImageConfig::default()
    };
    common::images(&frame, config).remove(0)
}

fn golden() -> Value {
    let text = std::fs::read_to_string(fixtures().join("golden_signal_range.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn fixture_image_is_what_the_image_builder_makes() {
    let image = signal_range_image();
    assert_eq!((image.width, image.height, image.channels), (1024, 64, 2));
    let path = fixtures().join("signal_range_1024x64x2.u8");
    if std::env::var_os("KEYLO_WRITE_FIXTURES").is_some() {
        std::fs::write(&path, &image.data).unwrap();
    }
    let stored = std::fs::read(&path).unwrap();
    assert!(
        stored == image.data,
        "the image builder changed: regenerate the golden (README.md)"
    );
}

#[test]
fn keypoints_and_descriptors_match_onnxruntime_python() {
    let golden = golden();
    let image = signal_range_image();
    let mut sp = SuperPoint::new(cpu_params(), &BuildContext::default()).unwrap();
    assert_eq!(sp.model_channels(), Some(2));
    let (keypoints, descriptors) = sp.run(&image).unwrap();
    let expected = golden["keypoints"].as_array().unwrap();
    assert!(
        expected.len() > 20,
        "golden has {} keypoints",
        expected.len()
    );
    assert_eq!(keypoints.len(), expected.len());
    for (k, e) in keypoints.iter().zip(expected) {
        let (x, y, s) = (
            e[0].as_f64().unwrap(),
            e[1].as_f64().unwrap(),
            e[2].as_f64().unwrap(),
        );
        assert_eq!((f64::from(k.x), f64::from(k.y)), (x, y));
        assert!(
            (f64::from(k.response) - s).abs() < 1e-5,
            "{} vs {s}",
            k.response
        );
        assert!(k.x >= 4.0 && k.y >= 4.0 && k.x < 1020.0 && k.y < 60.0);
    }
    let DescriptorData::Float(d) = &descriptors.data else {
        panic!("SuperPoint descriptors are floats")
    };
    assert_eq!((descriptors.rows, descriptors.dim), (keypoints.len(), 256));
    for (row, e) in d
        .chunks_exact(256)
        .zip(golden["descriptors_first"].as_array().unwrap())
    {
        for (a, b) in row.iter().zip(e.as_array().unwrap()) {
            assert!((f64::from(*a) - b.as_f64().unwrap()).abs() < 1e-4);
        }
    }
    let w: Vec<f64> = (0..256).map(|j| (1.0 + j as f64).sin()).collect();
    for (row, e) in d
        .chunks_exact(256)
        .zip(golden["descriptor_projections"].as_array().unwrap())
    {
        let norm: f64 = row.iter().map(|v| f64::from(*v).powi(2)).sum();
        assert!((norm - 1.0).abs() < 1e-4, "{norm}");
        let p: f64 = row.iter().zip(&w).map(|(a, b)| f64::from(*a) * b).sum();
        assert!((p - e.as_f64().unwrap()).abs() < 1e-3, "{p} vs {e}");
    }
}

#[test]
fn one_channel_model_on_one_plane_equals_two_channel_model_on_that_plane_twice() {
    let frame = common::os0_frames().remove(0);
    let signal = common::signal_image(&frame);
    let mut two = SuperPoint::new(cpu_params(), &BuildContext::default()).unwrap();
    let mut one =
        SuperPoint::new(with_model("superpoint_1ch.onnx"), &BuildContext::default()).unwrap();
    assert_eq!(one.model_channels(), Some(1));
    let a = two.detect(&signal).unwrap();
    let b = one.detect(&signal).unwrap();
    assert!(a.len() > 20, "{}", a.len());
    let same = a
        .iter()
        .filter(|k| b.iter().any(|j| j.x == k.x && j.y == k.y))
        .count();
    assert!(
        same * 100 >= a.len() * 99 && b.len().abs_diff(a.len()) * 100 <= a.len(),
        "{same} of {} / {}",
        a.len(),
        b.len()
    );
    // A two-plane image cannot feed the one-channel model.
    let e = one.detect(&signal_range_image()).unwrap_err().to_string();
    assert!(e.contains("1 channel") && e.contains("signal+range"), "{e}");
}

#[test]
fn describes_other_detectors_keypoints_and_caps_keypoints() {
    let image = signal_range_image();
    let params = SuperPointParams {
        max_keypoints: 25,
        ..cpu_params()
    };
    let mut sp = SuperPoint::new(params, &BuildContext::default()).unwrap();
    let (k, d) = sp.detect_and_describe(&image).unwrap();
    assert_eq!(k.len(), 25);
    assert_eq!(d.unwrap().rows, 25);
    let mut others = k.clone();
    others.push(keylo_core::Keypoint {
        x: 5000.0,
        y: 3.0,
        ..k[0]
    });
    others.push(keylo_core::Keypoint {
        x: f32::NAN,
        y: 3.0,
        ..k[0]
    });
    let d = Descriptor::describe(&mut sp, &image, &mut others).unwrap();
    assert_eq!((others.len(), d.rows, d.dim), (25, 25, 256));
}

#[test]
fn bad_models_are_refused_with_their_path() {
    let ctx = BuildContext::default();
    let e = SuperPoint::new(with_model("missing.onnx"), &ctx)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("model") && e.contains("missing.onnx"), "{e}");
    let e = SuperPoint::new(with_model("not_superpoint_3ch.onnx"), &ctx)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("3 channels") && e.contains("not_superpoint_3ch.onnx"),
        "{e}"
    );
    let mut sp = SuperPoint::new(with_model("wrong_outputs.onnx"), &ctx).unwrap();
    let frame = common::os0_frames().remove(0);
    let e = sp
        .detect(&common::signal_image(&frame))
        .unwrap_err()
        .to_string();
    assert!(e.contains("wrong_outputs.onnx") && e.contains("65"), "{e}");
    let bad = SuperPointParams {
        confidence: 1.5,
        ..cpu_params()
    };
    let e = SuperPoint::new(bad, &ctx).err().unwrap().to_string();
    assert!(e.contains("confidence"), "{e}");
    // INT8 is the shipped model's; a model of one's own runs as it is.
    let own_int8 = SuperPointParams {
        precision: Precision::Int8,
        ..with_model("superpoint_1ch.onnx")
    };
    let e = SuperPoint::new(own_int8, &ctx).err().unwrap().to_string();
    assert!(e.contains("precision") && e.contains("quantize"), "{e}");
}

/// Share of `a`'s keypoints with one of `b`'s within 1 px, and the mean cosine of their
/// descriptors (unit vectors: the dot product).
fn reproduced(a: &(Vec<Keypoint>, Descriptors), b: &(Vec<Keypoint>, Descriptors)) -> (f64, f64) {
    let (DescriptorData::Float(da), DescriptorData::Float(db)) = (&a.1.data, &b.1.data) else {
        panic!("SuperPoint descriptors are floats")
    };
    let (mut found, mut cosine) = (0usize, 0.0f64);
    for (i, p) in a.0.iter().enumerate() {
        if let Some(j) = b.0.iter().position(|q| (p.x - q.x).hypot(p.y - q.y) <= 1.0) {
            found += 1;
            let (x, y) = (&da[i * 256..(i + 1) * 256], &db[j * 256..(j + 1) * 256]);
            cosine += x.iter().zip(y).map(|(u, v)| f64::from(u * v)).sum::<f64>();
        }
    }
    (
        found as f64 / a.0.len().max(1) as f64,
        cosine / found.max(1) as f64,
    )
}

#[test]
fn int8_model_finds_the_fp32_keypoints_and_descriptors() {
    // Both frames of a real OS0-128 capture (not the images the INT8 model was calibrated on),
    // as the paper's configs see them: signal and range images, 1024×64, range gamma 0.5.
    let mut config = LidarImageConfig {
        images: vec!["signal".into(), "range".into()],
        ..LidarImageConfig::default()
    };
    config.normalise_by_channel.insert(
        "range".into(),
        keylo_features::image::Normalise {
            gamma: 0.5,
            ..Default::default()
        },
    );
    let ctx = BuildContext::default();
    let mut fp32 = SuperPoint::new(cpu_params(), &ctx).unwrap();
    let int8 = SuperPointParams {
        precision: Precision::Int8,
        ..cpu_params()
    };
    let mut int8 = SuperPoint::new(int8, &ctx).unwrap();
    // Measured: signal 95 % and 96 % of the FP32 keypoints within 1 px (the bench's 97 % is on
    // the TIERS images 100-199), range 91 % and 89 % (range images were not in the calibration
    // set); descriptors' cosine 0.995. INT8 also finds weak keypoints that FP32 rounds below
    // the confidence threshold on these low-texture frames of a small room: 137 / 124 and
    // 139 / 119 keypoints on the signal images, 61 / 35 and 59 / 47 on the range images, 1.22
    // times FP32's count over the four (1.02 on the TIERS images; the model's header says
    // why). Bounds leave room for other CPUs' kernels (FP32 parts of the graph round
    // differently with AVX-512).
    let (mut found, mut total, mut found_count) = (0.0, 0usize, 0usize);
    for frame in common::os0_frames() {
        for image in common::images(&frame, config.clone()) {
            let (a, b) = (fp32.run(&image).unwrap(), int8.run(&image).unwrap());
            let (share, cosine) = reproduced(&a, &b);
            let name = image.name();
            assert!(a.0.len() > 20, "{name}: {}", a.0.len());
            if name == "signal" {
                assert!(
                    share >= 0.85,
                    "{name}: {share} of the FP32 keypoints within 1 px"
                );
            }
            let count = b.0.len() as f64 / a.0.len() as f64;
            assert!(
                (0.75..=2.0).contains(&count),
                "{name}: {} vs {}",
                b.0.len(),
                a.0.len()
            );
            assert!(cosine > 0.99, "{name}: mean cosine {cosine}");
            found += share * a.0.len() as f64;
            total += a.0.len();
            found_count += b.0.len();
        }
    }
    let share = found / total as f64;
    assert!(
        share >= 0.88,
        "{share} of the FP32 keypoints within 1 px over every image"
    );
    let count = found_count as f64 / total as f64;
    assert!(
        (0.8..=1.4).contains(&count),
        "INT8 found {count} times FP32's keypoints over every image"
    );
}

#[test]
fn same_image_same_keypoints() {
    let image = signal_range_image();
    let mut sp = SuperPoint::new(cpu_params(), &BuildContext::default()).unwrap();
    let a = sp.detect(&image).unwrap();
    let b = sp.detect(&image).unwrap();
    assert_eq!(a, b);
}

/// `spinning` only changes how ONNX Runtime's threads wait (each setting its own session):
/// the keypoints are the same either way.
#[test]
fn spinning_threads_give_the_same_keypoints() {
    let image = signal_range_image();
    let run = |spinning| {
        let params = SuperPointParams {
            spinning,
            ..cpu_params()
        };
        SuperPoint::new(params, &BuildContext::default())
            .unwrap()
            .detect(&image)
            .unwrap()
    };
    let (sleeping, spinning) = (run(false), run(true));
    assert!(!sleeping.is_empty());
    assert_eq!(sleeping, spinning);
}
