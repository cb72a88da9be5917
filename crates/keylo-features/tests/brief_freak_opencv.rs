//! keylo's native `brief` and `freak` against OpenCV contrib's on the same keypoints of the
//! committed real and simulated images (golden fixture `tests/fixtures/brief_freak/golden.json`,
//! made by `scripts/peers/brief_freak_golden.py` with opencv-contrib-python 4.14): the same
//! keypoints kept, the same descriptors bit for bit (BRIEF upright and oriented), and FREAK's
//! angles.

mod common;

use common::{png_image as image, root};

use keylo_core::{DescriptorData, Descriptors, Image, Keypoint, Registry};

fn golden() -> serde_json::Value {
    let path = root().join("tests/fixtures/brief_freak/golden.json");
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The fixture's keypoints, each tagged with its index in `class_id`.
fn keypoints(v: &serde_json::Value) -> Vec<Keypoint> {
    let rows = v.as_array().unwrap();
    rows.iter()
        .enumerate()
        .map(|(i, k)| {
            let f = |j: usize| k[j].as_f64().unwrap() as f32;
            Keypoint {
                x: f(0),
                y: f(1),
                size: f(2),
                angle: f(3),
                response: f(4),
                octave: k[5].as_i64().unwrap() as i32,
                class_id: i as i32,
            }
        })
        .collect()
}

fn describe(kind: &str, params: &str, img: &Image, kps: &mut Vec<Keypoint>) -> Descriptors {
    let mut r = Registry::default();
    keylo_features::register(&mut r);
    let f = r.descriptors.get(kind).unwrap();
    let table: toml::Table = params.parse().unwrap();
    let mut d = f
        .build(&f.resolve(&table).unwrap(), &Default::default())
        .unwrap();
    d.describe(img, kps).unwrap()
}

fn hex_rows(d: &Descriptors) -> Vec<String> {
    let DescriptorData::Binary(b) = &d.data else {
        panic!("binary descriptors expected")
    };
    b.chunks(d.dim)
        .map(|r| r.iter().map(|v| format!("{v:02x}")).collect())
        .collect()
}

/// Describes each golden image's keypoint sets with `kind` (`variants`: the fixture's entry
/// and the settings that give it) and checks the kept keypoints and rows against OpenCV's;
/// returns how many rows were compared.
fn check_against_opencv(kind: &str, variants: &[(&str, &str)]) -> usize {
    let g = golden();
    let mut described = 0;
    for (name, sets) in g["images"].as_object().unwrap() {
        let img = image(&root().join(name));
        for set in ["fast", "orb"] {
            for (variant, params) in variants {
                let want = &sets[set][variant];
                let mut kps = keypoints(&sets[set]["keypoints"]);
                let d = describe(kind, params, &img, &mut kps);
                let kept: Vec<i64> = kps.iter().map(|k| i64::from(k.class_id)).collect();
                let want_kept: Vec<i64> = (want["kept"].as_array().unwrap().iter())
                    .map(|v| v.as_i64().unwrap())
                    .collect();
                assert_eq!(kept, want_kept, "{name} {set} {variant}: keypoints kept");
                let want_rows: Vec<&str> = (want["descriptors"].as_array().unwrap().iter())
                    .map(|v| v.as_str().unwrap())
                    .collect();
                assert_eq!(
                    hex_rows(&d),
                    want_rows,
                    "{name} {set} {variant}: descriptors"
                );
                described += kps.len();
            }
        }
    }
    described
}

#[test]
fn brief_is_opencv_contribs_bit_for_bit() {
    let described = check_against_opencv(
        "brief",
        &[("brief", ""), ("brief_oriented", "use_orientation = true")],
    );
    assert!(described > 1000, "{described} descriptors");
}

#[test]
fn freak_is_opencv_contribs_bit_for_bit() {
    let described = check_against_opencv("freak", &[("freak", "")]);
    assert!(described > 800, "{described} descriptors");
}
