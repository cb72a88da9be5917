//! PLY and PCD folders: files written by the fixture writer in `common/fixtures.rs` are read
//! back field by field, in every encoding; bad files are errors naming the file.

mod common;

use std::path::Path;

use common::fixtures::{sample, write_pcd, write_ply, Pcd, Ply, Pt};
use common::{build, frames, lit};
use keylo_io::cloud::RawCloud;
use keylo_io::folder::fields::FieldOptions;
use keylo_io::{pcd::read_pcd, ply::read_ply};

fn assert_matches(cloud: &RawCloud, points: &[Pt], what: &str) {
    assert_eq!(cloud.len(), points.len(), "{what}: point count");
    let intensity = cloud.intensity.as_ref().expect("intensity");
    let time = cloud.time.as_ref().expect("time");
    let ring = cloud.ring.as_ref().expect("ring");
    let refl = cloud.reflectivity.as_ref().expect("reflectivity");
    let nir = cloud.near_ir.as_ref().expect("near_ir");
    let range = cloud.range.as_ref().expect("range");
    for (i, p) in points.iter().enumerate() {
        let at = format!("{what}, point {i}");
        assert_eq!(cloud.points[i], [p.x, p.y, p.z], "{at}: xyz");
        assert_eq!(intensity[i], p.intensity, "{at}: intensity");
        assert!((time[i] - f64::from(p.t) * 1e-9).abs() < 1e-15, "{at}: t");
        assert_eq!(ring[i], p.ring, "{at}: ring");
        assert_eq!(refl[i], f32::from(p.reflectivity), "{at}: reflectivity");
        assert_eq!(nir[i], f32::from(p.ambient), "{at}: ambient");
        assert!(
            (range[i] - p.range as f32 / 1000.0).abs() < 1e-6,
            "{at}: range"
        );
    }
}

#[test]
fn ply_ascii_and_both_binary_orders_read_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let pts = sample(12);
    for enc in [Ply::Ascii, Ply::LittleEndian, Ply::BigEndian] {
        let path = dir.path().join(format!("{enc:?}.ply"));
        write_ply(&path, &pts, enc, pts.len());
        let cloud = read_ply(&path, 3.5, &FieldOptions::default()).unwrap();
        assert_eq!(cloud.timestamp, 3.5);
        assert_eq!(cloud.grid, None);
        assert_matches(&cloud, &pts, &format!("PLY {enc:?}"));
    }
}

#[test]
fn pcd_ascii_binary_and_compressed_read_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let pts = sample(12);
    for data in [Pcd::Ascii, Pcd::Binary, Pcd::Compressed] {
        let path = dir.path().join(format!("{data:?}.pcd"));
        write_pcd(&path, &pts, data, 1);
        let cloud = read_pcd(&path, 1.0, &FieldOptions::default()).unwrap();
        assert_eq!(cloud.grid, None);
        assert_matches(&cloud, &pts, &format!("PCD {data:?}"));
        let organised = dir.path().join(format!("{data:?}-grid.pcd"));
        write_pcd(&organised, &pts, data, 4);
        let cloud = read_pcd(&organised, 1.0, &FieldOptions::default()).unwrap();
        assert_eq!(cloud.grid, Some((4, 3)));
        assert_matches(&cloud, &pts, &format!("organised PCD {data:?}"));
    }
}

#[test]
fn folders_stream_in_natural_order_with_name_stamps_and_projection() {
    let dir = tempfile::tempdir().unwrap();
    let pts = sample(40);
    for (i, name) in ["1700000000.5.ply", "1700000000.25.ply", "1700000000.75.ply"]
        .iter()
        .enumerate()
    {
        write_ply(
            &dir.path().join(name),
            &pts[..10 + i],
            Ply::LittleEndian,
            10 + i,
        );
    }
    let params = format!(
        "path = {}\nstride = 2\n[projection]\nrows = 4\ncols = 64\nfov_up_deg = 5\nfov_down_deg = -10",
        lit(dir.path())
    );
    let mut src = build("ply", &params).unwrap();
    let info = src.info();
    assert_eq!(info.frames, Some(2));
    assert!(
        info.description.contains("times from the file names"),
        "{}",
        info.description
    );
    assert!(
        info.description.contains("fields not read: curvature"),
        "{}",
        info.description
    );
    let f = frames(src.as_mut()).unwrap();
    assert_eq!(
        f.iter().map(|f| f.timestamp).collect::<Vec<_>>(),
        vec![1700000000.25, 1700000000.75]
    );
    assert_eq!(f[1].index, 2);
    assert_eq!((f[0].rows, f[0].cols), (4, 64));
    // Ring rows: every point lands in the image, and the maps agree.
    let map = f[0].scan.as_ref().unwrap();
    assert!(map.pixel.iter().all(|&p| p != u32::MAX));
    for (pixel, &point) in map.pixel_to_point.iter().enumerate() {
        if point != u32::MAX {
            assert_eq!(map.pixel[point as usize] as usize, pixel);
        }
    }
}

#[test]
fn organised_pcd_folders_keep_the_grid_and_single_files_work() {
    let dir = tempfile::tempdir().unwrap();
    let pts = sample(12);
    let names = ["scan_2.pcd", "scan_10.pcd", "scan_1.pcd"];
    for n in names {
        write_pcd(&dir.path().join(n), &pts, Pcd::Binary, 4);
    }
    let mut src = build(
        "pcd",
        &format!("path = {}\nframe_rate_hz = 20", lit(dir.path())),
    )
    .unwrap();
    let info = src.info().description;
    assert!(
        info.contains("index / 20 Hz") && info.contains("fields not read: curvature"),
        "{info}"
    );
    let f = frames(src.as_mut()).unwrap();
    assert_eq!(f.len(), 3);
    assert_eq!(f[2].timestamp, 0.1);
    assert_eq!((f[0].rows, f[0].cols), (4, 3));
    assert!(f[0].scan.is_none());
    assert_eq!(f[0].valid_count(), 12);
    let one = dir.path().join("scan_10.pcd");
    let mut src = build("pcd", &format!("path = {}", lit(&one))).unwrap();
    assert_eq!(frames(src.as_mut()).unwrap().len(), 1);
}

#[test]
fn probes_recognise_folders_and_files() {
    let r = common::registry();
    let dir = tempfile::tempdir().unwrap();
    let (ply, pcd) = (dir.path().join("ply"), dir.path().join("pcd"));
    std::fs::create_dir_all(&ply).unwrap();
    std::fs::create_dir_all(&pcd).unwrap();
    write_ply(&ply.join("0.ply"), &sample(3), Ply::Ascii, 3);
    write_pcd(&pcd.join("0.pcd"), &sample(3), Pcd::Ascii, 1);
    assert_eq!(r.detect_source(&ply), Some("ply"));
    assert_eq!(r.detect_source(&ply.join("0.ply")), Some("ply"));
    assert_eq!(r.detect_source(&pcd), Some("pcd"));
    assert_eq!(r.detect_source(&pcd.join("0.pcd")), Some("pcd"));
    assert_eq!(r.detect_source(dir.path()), None);
}

fn err_of(kind: &str, dir: &Path) -> String {
    match build(kind, &format!("path = {}", lit(dir))) {
        Err(e) => e.to_string(),
        Ok(mut s) => match frames(s.as_mut()) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{kind} {}: expected an error", dir.display()),
        },
    }
}

#[test]
fn empty_folders_and_files_without_coordinates_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let e = err_of("ply", dir.path());
    assert!(e.contains("holds no .ply file"), "{e}");
    let e = err_of("pcd", dir.path());
    assert!(e.contains("holds no .pcd file"), "{e}");
    let p = dir.path().join("a.ply");
    std::fs::write(&p, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float intensity\nend_header\n1 2\n").unwrap();
    let e = err_of("ply", dir.path());
    assert!(
        e.contains("a.ply") && e.contains("no field `y`, `z`"),
        "{e}"
    );
}

#[test]
fn a_truncated_ply_fails_on_its_own_frame() {
    let dir = tempfile::tempdir().unwrap();
    let pts = sample(8);
    for enc in [Ply::Ascii, Ply::LittleEndian, Ply::BigEndian] {
        let sub = dir.path().join(format!("{enc:?}"));
        std::fs::create_dir_all(&sub).unwrap();
        write_ply(&sub.join("0.ply"), &pts, enc, 8);
        write_ply(&sub.join("1.ply"), &pts[..5], enc, 8);
        write_ply(&sub.join("2.ply"), &pts, enc, 8);
        let mut src = build("ply", &format!("path = {}", lit(&sub))).unwrap();
        assert!(src.next_frame().unwrap().is_ok(), "{enc:?}: frame 0");
        let e = src.next_frame().unwrap().unwrap_err().to_string();
        assert!(
            e.contains("1.ply") && e.contains("vertex element 5 of the 8"),
            "{enc:?}: {e}"
        );
    }
}

#[test]
fn bad_pcd_files_name_the_file_and_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &[u8]| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let opts = FieldOptions::default();
    let head = |fields: &str, size: &str, ty: &str, n: usize, data: &str| {
        format!("VERSION 0.7\nFIELDS {fields}\nSIZE {size}\nTYPE {ty}\nWIDTH {n}\nHEIGHT 1\nPOINTS {n}\nDATA {data}\n")
    };
    let half = write(
        "half.pcd",
        head("x y z h", "4 4 4 2", "F F F F", 1, "ascii").as_bytes(),
    );
    let e = read_pcd(&half, 0.0, &opts).unwrap_err().to_string();
    assert!(
        e.contains("half.pcd") && e.contains("field `h` has TYPE F SIZE 2"),
        "{e}"
    );
    let vec3 = write("vec.pcd", b"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 3\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 4 5\n");
    let e = read_pcd(&vec3, 0.0, &opts).unwrap_err().to_string();
    assert!(e.contains("field `z` holds 3 values"), "{e}");
    let mut short = head("x y z", "4 4 4", "F F F", 3, "binary").into_bytes();
    short.extend([0u8; 20]);
    let p = write("short.pcd", &short);
    let e = read_pcd(&p, 0.0, &opts).unwrap_err().to_string();
    assert!(
        e.contains("short.pcd")
            && e.contains("3 points of 12 bytes (36 bytes) but the data holds 20"),
        "{e}"
    );
    let mut packed = head("x y z", "4 4 4", "F F F", 3, "binary_compressed").into_bytes();
    packed.extend(1u32.to_le_bytes());
    packed.extend(12u32.to_le_bytes());
    packed.extend([0u8; 4]);
    let p = write("packed.pcd", &packed);
    let e = read_pcd(&p, 0.0, &opts).unwrap_err().to_string();
    assert!(
        e.contains("unpacks to 12 bytes") && e.contains("(36 bytes)"),
        "{e}"
    );
    let ascii = write(
        "few.pcd",
        format!("{}1 2 3\n", head("x y z", "4 4 4", "F F F", 2, "ascii")).as_bytes(),
    );
    let e = read_pcd(&ascii, 0.0, &opts).unwrap_err().to_string();
    assert!(
        e.contains("few.pcd") && e.contains("point 1 of the 2"),
        "{e}"
    );
    let none = write("none.pcd", b"hello\n");
    assert!(read_pcd(&none, 0.0, &opts)
        .unwrap_err()
        .to_string()
        .contains("no `DATA` line"));
}
