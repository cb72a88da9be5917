//! keylo's `akaze` (only the scale levels an image size can use) against OpenCV's AKAZE at its
//! defaults, all levels built: the same keypoints, bit for bit, and the same descriptors, on
//! real OS0-128 images (the committed sample; the paper's 600 signal images in
//! `../shared/data/tiers_signal` where present) and on simulated frames, at the sizes keylo
//! uses.

mod common;

use std::path::{Path, PathBuf};

use common::{read_png, resized as image};

use keylo_core::{Descriptor, Detector, Image, Keypoint, Registry};
use keylo_features::classic::{AkazeParams, CvFeature};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/kpeval/images")
}

fn registry() -> Registry {
    let mut r = Registry::default();
    keylo_features::register(&mut r);
    r
}

/// keylo's `akaze` detector, describing in the same pass.
fn keylo_detector() -> Box<dyn Detector> {
    let r = registry();
    let f = r.detectors.get("akaze").unwrap();
    let table: toml::Table = "describe = true".parse().unwrap();
    f.build(&f.resolve(&table).unwrap(), &Default::default())
        .unwrap()
}

/// keylo's `akaze` descriptor.
fn keylo_descriptor() -> Box<dyn Descriptor> {
    let r = registry();
    let f = r.descriptors.get("akaze").unwrap();
    f.build(
        &f.resolve(&toml::Table::new()).unwrap(),
        &Default::default(),
    )
    .unwrap()
}

fn bits(k: &[Keypoint]) -> Vec<[u32; 7]> {
    k.iter()
        .map(|k| {
            [
                k.x.to_bits(),
                k.y.to_bits(),
                k.size.to_bits(),
                k.angle.to_bits(),
                k.response.to_bits(),
                k.octave as u32,
                k.class_id as u32,
            ]
        })
        .collect()
}

/// Checks keylo's `akaze` detector and descriptor against OpenCV's default AKAZE on every
/// image; returns the keypoints found.
fn check_equal(images: &[(String, Image)]) -> usize {
    let (mut det, mut desc) = (keylo_detector(), keylo_descriptor());
    let mut opencv = CvFeature::new(&AkazeParams {
        describe: true,
        ..AkazeParams::default()
    })
    .unwrap();
    let mut found = 0;
    for (name, img) in images {
        let (want_k, want_d) = Detector::detect_and_describe(&mut opencv, img).unwrap();
        let (got_k, got_d) = det.detect_and_describe(img).unwrap();
        assert_eq!(bits(&got_k), bits(&want_k), "{name}: keypoints differ");
        assert_eq!(got_d, want_d, "{name}: descriptors differ");
        // The descriptor stage on the detector's keypoints.
        let mut k = got_k.clone();
        let d = desc.describe(img, &mut k).unwrap();
        assert_eq!(Some(d), want_d, "{name}: descriptor stage differs");
        found += want_k.len();
    }
    found
}

fn fixture_images(sizes: &[(usize, usize)]) -> Vec<(String, Image)> {
    let mut out = Vec::new();
    for set in ["os0", "sim"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(fixtures().join(set))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "png"))
            .collect();
        files.sort();
        for f in files {
            let png = read_png(&f);
            for &(w, h) in sizes {
                out.push((format!("{} at {w}x{h}", f.display()), image(&png, w, h)));
            }
        }
    }
    out
}

#[test]
fn real_and_simulated_images_give_opencvs_keypoints_and_descriptors() {
    // 1024×64: the paper's size, where level 0 alone can hold keypoints; 1024×128 and
    // 2048×128: more levels are searchable; 512×32: none is.
    let images = fixture_images(&[(1024, 64), (1024, 128), (2048, 128), (512, 32), (2048, 64)]);
    assert_eq!(images.len(), 7 * 5);
    let found = check_equal(&images);
    assert!(
        found > 500,
        "only {found} keypoints: the check would prove little"
    );
}

#[test]
fn keypoints_of_levels_a_pruned_akaze_lacks_are_described_by_the_full_one() {
    // Keypoints detected on a 1024×128 image, of levels 0–3, described on the same image
    // resized to 1024×64, where OpenCV builds levels 0–3 and keylo level 0 only: the
    // descriptor must fall back to all levels and give OpenCV's answer (a level OpenCV does
    // not build either is OpenCV's own error).
    let png = read_png(&fixtures().join("os0/frame000000_signal.png"));
    let (tall, short) = (image(&png, 1024, 128), image(&png, 1024, 64));
    let mut opencv = CvFeature::new(&AkazeParams::default()).unwrap();
    let mut k: Vec<Keypoint> = Detector::detect(&mut opencv, &tall)
        .unwrap()
        .into_iter()
        .filter(|k| k.y < 64.0 && k.class_id < 4)
        .collect();
    assert!(
        k.iter().any(|k| k.class_id > 0),
        "no keypoint above level 0"
    );
    let mut want_k = k.clone();
    let want = Descriptor::describe(&mut opencv, &short, &mut want_k).unwrap();
    let got = keylo_descriptor().describe(&short, &mut k).unwrap();
    assert_eq!((bits(&k), got), (bits(&want_k), want));
}

/// The paper's real images (all 600 here), where `../shared` is beside the repository.
#[test]
fn the_papers_real_images_give_opencvs_keypoints_and_descriptors() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/tiers_signal");
    if !dir.is_dir() {
        eprintln!("skipped: {} is absent", dir.display());
        return;
    }
    let images: Vec<(String, Image)> = (0..600)
        .map(|i| {
            let path = dir.join(format!("image_{i:04}.png"));
            (
                path.display().to_string(),
                image(&read_png(&path), 1024, 64),
            )
        })
        .collect();
    let found = check_equal(&images);
    assert!(found > 20_000, "{found} keypoints on 600 images");
}
