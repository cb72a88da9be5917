//! Every OpenCV detector and descriptor on real Ouster signal images.

mod common;

use keylo_core::{Channel, DescriptorData, Image, Registry};

fn registry() -> Registry {
    let mut r = Registry::default();
    keylo_features::register(&mut r);
    r
}

fn detector(r: &Registry, kind: &str, params: &str) -> Box<dyn keylo_core::Detector> {
    let table: toml::Table = params.parse().unwrap();
    let factory = r.detectors.get(kind).unwrap();
    let resolved = factory.resolve(&table).unwrap();
    factory
        .build(&resolved, &keylo_core::BuildContext::default())
        .unwrap()
}

#[test]
fn every_detector_finds_keypoints_inside_the_image() {
    let frames = common::os0_frames();
    let image = common::signal_image(&frames[0]);
    assert_eq!((image.width, image.height), (1024, 64));
    let r = registry();
    for kind in [
        "shi-tomasi",
        "harris",
        "fast",
        "brisk",
        "sift",
        "akaze",
        "kaze",
        "orb",
    ] {
        let mut d = detector(&r, kind, "");
        let kps = d.detect(&image).unwrap();
        assert!(!kps.is_empty(), "{kind} found no keypoint");
        for k in &kps {
            assert!(
                k.x >= 0.0 && k.y >= 0.0 && k.x < 1024.0 && k.y < 64.0,
                "{kind}: keypoint outside the image: {k:?}"
            );
        }
        // Same input, same output.
        assert_eq!(
            d.detect(&image).unwrap(),
            kps,
            "{kind} is not deterministic"
        );
    }
}

#[test]
fn describing_detectors_return_aligned_descriptors() {
    let frames = common::os0_frames();
    let image = common::signal_image(&frames[0]);
    let r = registry();
    for (kind, binary) in [
        ("akaze", true),
        ("orb", true),
        ("brisk", true),
        ("sift", false),
    ] {
        let mut d = detector(&r, kind, "describe = true");
        let (kps, desc) = d.detect_and_describe(&image).unwrap();
        let desc = desc.expect("descriptors");
        assert_eq!(desc.rows, kps.len(), "{kind}");
        assert_eq!(
            matches!(desc.data, DescriptorData::Binary(_)),
            binary,
            "{kind}"
        );
        // The same algorithm as a separate descriptor stage gives the same rows.
        let table = toml::Table::new();
        let f = r.descriptors.get(kind).unwrap();
        let mut describer = f
            .build(
                &f.resolve(&table).unwrap(),
                &keylo_core::BuildContext::default(),
            )
            .unwrap();
        let mut again = kps.clone();
        let d2 = describer.describe(&image, &mut again).unwrap();
        assert_eq!(d2.rows, again.len(), "{kind}");
        if kind != "sift" {
            assert_eq!(again, kps, "{kind} dropped or moved keypoints");
            assert_eq!(d2, desc, "{kind}: describe differs from detectAndCompute");
        }
    }
}

#[test]
fn paper_fast_threshold_finds_fewer_corners_than_default() {
    let frames = common::os0_frames();
    let image = common::signal_image(&frames[0]);
    let r = registry();
    let n10 = detector(&r, "fast", "").detect(&image).unwrap().len();
    let n30 = detector(&r, "fast", "threshold = 30")
        .detect(&image)
        .unwrap()
        .len();
    assert!(n30 < n10, "threshold 30: {n30}, 10: {n10}");
}

#[test]
fn two_plane_image_is_a_clear_error() {
    let mut image = Image::new_gray(16, 16, Channel::Signal);
    image.channels = 2;
    image.stride = 32;
    image.data = vec![0; 512];
    image.sources.push(Channel::Range);
    let mut d = detector(&registry(), "orb", "");
    let e = d.detect(&image).unwrap_err().to_string();
    assert!(e.contains("one-plane") && e.contains("signal+range"), "{e}");
}

#[test]
fn black_image_gives_no_keypoints_and_no_error() {
    let image = Image::new_gray(1024, 64, Channel::Signal);
    let r = registry();
    for kind in ["shi-tomasi", "fast", "akaze", "orb", "sift", "brisk"] {
        let kps = detector(&r, kind, "").detect(&image).unwrap();
        assert!(kps.is_empty(), "{kind}");
    }
}

/// Without the cargo feature `nonfree`, SURF is a clear error naming the feature.
#[cfg(not(feature = "nonfree"))]
#[test]
fn surf_says_why_it_is_missing() {
    let r = registry();
    let f = r.detectors.get("surf").unwrap();
    let params = f.resolve(&toml::Table::new()).unwrap();
    let e = match f.build(&params, &keylo_core::BuildContext::default()) {
        Ok(_) => panic!("SURF built without the feature `nonfree`"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("nonfree") && e.contains("--features nonfree"),
        "{e}"
    );
}

#[test]
fn bad_parameters_name_the_field() {
    let r = registry();
    let f = r.detectors.get("orb").unwrap();
    let params = f.resolve(&"scale_factor = 0.5".parse().unwrap()).unwrap();
    let e = match f.build(&params, &keylo_core::BuildContext::default()) {
        Ok(_) => panic!("accepted scale_factor 0.5"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("scale_factor"), "{e}");
}

#[test]
fn orb_refuses_sift_keypoints_instead_of_allocating_a_huge_pyramid() {
    let frames = common::os0_frames();
    let image = common::signal_image(&frames[0]);
    let r = registry();
    let mut sift = detector(&r, "sift", "");
    let mut kps = sift.detect(&image).unwrap();
    assert!(kps.iter().any(|k| k.octave > 7), "SIFT packs octaves");
    let f = r.descriptors.get("orb").unwrap();
    let resolved = f.resolve(&toml::Table::new()).unwrap();
    let mut orb = f
        .build(&resolved, &keylo_core::BuildContext::default())
        .unwrap();
    let e = orb.describe(&image, &mut kps).unwrap_err().to_string();
    assert!(e.contains("octave") && e.contains("SIFT"), "{e}");
    // FAST keypoints (octave 0) are described.
    let mut fast = detector(&r, "fast", "");
    let mut kps = fast.detect(&image).unwrap();
    let d = orb.describe(&image, &mut kps).unwrap();
    assert_eq!(d.rows, kps.len());
}
