use super::*;
use crate::ros::msgs::tests::cloud_msg;
use crate::ros::wire::Encoding;

fn decode_with(buf: &[u8], enc: Encoding) -> Result<RawCloud, crate::ros::DecodeError> {
    to_raw_cloud(&PointCloud2::decode(buf, enc)?)
}

/// Serialises a value of datatype `code` in the given byte order.
pub(crate) fn bytes_of(code: u8, v: f64, big: bool) -> Vec<u8> {
    let mut b = match code {
        1 => vec![(v as i8) as u8],
        2 => vec![v as u8],
        3 => (v as i16).to_le_bytes().to_vec(),
        4 => (v as u16).to_le_bytes().to_vec(),
        5 => (v as i32).to_le_bytes().to_vec(),
        6 => (v as u32).to_le_bytes().to_vec(),
        7 => (v as f32).to_le_bytes().to_vec(),
        _ => v.to_le_bytes().to_vec(),
    };
    if big {
        b.reverse();
    }
    b
}

#[test]
fn every_datatype_in_both_byte_orders() {
    for big in [false, true] {
        for code in 1..=8u8 {
            // x y z of datatype `code` at offsets 0, 8, 16 (point_step 24), two points.
            let fields = [("x", 0, code), ("y", 8, code), ("Z", 16, code)];
            let mut data = vec![0u8; 48];
            for (p, base) in [(0usize, 0.0), (1, 10.0)] {
                for (k, off) in [0usize, 8, 16].into_iter().enumerate() {
                    let v = bytes_of(code, base + k as f64 - 1.0 + 2.0, big);
                    data[p * 24 + off..p * 24 + off + v.len()].copy_from_slice(&v);
                }
            }
            let buf = cloud_msg(Encoding::Ros1, 0, (1, 2, 24), &fields, big, &data);
            let c = decode_with(&buf, Encoding::Ros1).unwrap();
            assert_eq!(
                c.points,
                vec![[1.0, 2.0, 3.0], [11.0, 12.0, 13.0]],
                "datatype {code}, big {big}"
            );
            assert_eq!(c.grid, None);
        }
    }
}

#[test]
fn negative_values_of_signed_types() {
    for code in [1u8, 3, 5] {
        let mut data = Vec::new();
        for v in [-3.0, -2.0, -1.0] {
            data.extend(bytes_of(code, v, false));
            data.resize(data.len() + 8 - data.len() % 8, 0);
        }
        let fields = [("x", 0, code), ("y", 8, code), ("z", 16, code)];
        let buf = cloud_msg(Encoding::Cdr, 0, (1, 1, 24), &fields, false, &data);
        let c = decode_with(&buf, Encoding::Cdr).unwrap();
        assert_eq!(c.points, vec![[-3.0, -2.0, -1.0]], "datatype {code}");
    }
}

/// ouster-ros' layout: organised, point_step 48, u32 `t` (ns) and `range` (mm).
#[test]
fn ouster_ros_fields_and_units() {
    let fields = [
        ("x", 0, 7),
        ("y", 4, 7),
        ("z", 8, 7),
        ("intensity", 16, 7),
        ("t", 20, 6),
        ("reflectivity", 24, 4),
        ("ring", 26, 4),
        ("ambient", 28, 4),
        ("range", 32, 6),
    ];
    let mut data = vec![0u8; 48 * 4];
    for i in 0..4usize {
        let p = &mut data[i * 48..(i + 1) * 48];
        p[0..4].copy_from_slice(&(i as f32 + 1.0).to_le_bytes());
        p[16..20].copy_from_slice(&(100.0f32 + i as f32).to_le_bytes());
        p[20..24].copy_from_slice(&(i as u32 * 25_000_000).to_le_bytes());
        p[24..26].copy_from_slice(&7u16.to_le_bytes());
        p[26..28].copy_from_slice(&((i / 2) as u16).to_le_bytes());
        p[28..30].copy_from_slice(&9u16.to_le_bytes());
        p[32..36].copy_from_slice(&(1500u32 * (i as u32 + 1)).to_le_bytes());
    }
    let buf = cloud_msg(
        Encoding::Cdr,
        2_500_000_000,
        (2, 2, 48),
        &fields,
        false,
        &data,
    );
    let c = decode_with(&buf, Encoding::Cdr).unwrap();
    assert_eq!(c.grid, Some((2, 2)));
    assert!((c.timestamp - 2.5).abs() < 1e-12);
    assert_eq!(c.intensity, Some(vec![100.0, 101.0, 102.0, 103.0]));
    assert_eq!(c.reflectivity, Some(vec![7.0; 4]));
    assert_eq!(c.near_ir, Some(vec![9.0; 4]));
    assert_eq!(c.ring, Some(vec![0, 0, 1, 1]));
    assert_eq!(c.range, Some(vec![1.5, 3.0, 4.5, 6.0]));
    let t = c.time.unwrap();
    assert!((t[3] - 0.075).abs() < 1e-12, "{t:?}");
    assert!(c.points[3][0] == 4.0);
}

#[test]
fn velodyne_float_time_and_absolute_times() {
    let fields = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("time", 12, 7)];
    let mut data = vec![0u8; 16];
    data[12..16].copy_from_slice(&(-0.05f32).to_le_bytes());
    let buf = cloud_msg(
        Encoding::Ros1,
        10_000_000_000,
        (1, 1, 16),
        &fields,
        false,
        &data,
    );
    let t = decode_with(&buf, Encoding::Ros1).unwrap().time.unwrap();
    assert!((t[0] + 0.05).abs() < 1e-7);

    // Hesai-style absolute f64 seconds, and Livox-style absolute f64 nanoseconds.
    for (value, want) in [(1_700_000_000.25f64, 0.25), (1.70000000025e18, 0.25)] {
        let fields = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("timestamp", 16, 8)];
        let mut data = vec![0u8; 24];
        data[16..24].copy_from_slice(&value.to_le_bytes());
        let stamp = 1_700_000_000_000_000_000i64;
        let buf = cloud_msg(Encoding::Ros1, stamp, (1, 1, 24), &fields, false, &data);
        let t = decode_with(&buf, Encoding::Ros1).unwrap().time.unwrap();
        assert!((t[0] - want).abs() < 1e-6, "{value}: {t:?}");
    }
}

#[test]
fn row_padding_is_skipped() {
    // 2 rows of 1 point (point_step 12), row_step 16: 4 padding bytes per row.
    let fields = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7)];
    let mut data = vec![0u8; 32];
    data[16..20].copy_from_slice(&5.0f32.to_le_bytes());
    let mut buf = cloud_msg(Encoding::Ros1, 0, (2, 1, 12), &fields, false, &data);
    // cloud_msg writes row_step = point_step × width = 12; patch it to 16.
    let at = buf.len() - 1 - 4 - 32 - 4;
    buf[at..at + 4].copy_from_slice(&16u32.to_le_bytes());
    let c = decode_with(&buf, Encoding::Ros1).unwrap();
    assert_eq!(c.points[1], [5.0, 0.0, 0.0]);
}

#[test]
fn inconsistent_messages_are_errors() {
    let xyz = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7)];
    let short = cloud_msg(Encoding::Ros1, 0, (2, 3, 12), &xyz, false, &[0u8; 60]);
    let e = decode_with(&short, Encoding::Ros1).unwrap_err().to_string();
    assert!(
        e.contains("data holds 60 bytes") && e.contains("72") && e.contains("point_step 12"),
        "{e}"
    );

    let no_z = cloud_msg(Encoding::Ros1, 0, (1, 1, 12), &xyz[..2], false, &[0u8; 12]);
    let e = decode_with(&no_z, Encoding::Ros1).unwrap_err().to_string();
    assert!(e.contains("no `z` field") && e.contains("x, y"), "{e}");

    let outside = [("x", 0, 7), ("y", 4, 7), ("z", 10, 7)];
    let buf = cloud_msg(Encoding::Ros1, 0, (1, 1, 12), &outside, false, &[0u8; 12]);
    let e = decode_with(&buf, Encoding::Ros1).unwrap_err().to_string();
    assert!(e.contains("outside point_step 12"), "{e}");

    let bad_type = [("x", 0, 9), ("y", 4, 7), ("z", 8, 7)];
    let buf = cloud_msg(Encoding::Ros1, 0, (1, 1, 12), &bad_type, false, &[0u8; 12]);
    assert!(decode_with(&buf, Encoding::Ros1)
        .unwrap_err()
        .message()
        .contains("datatype 9"));

    let ring = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("ring", 12, 5)];
    let mut data = vec![0u8; 16];
    data[12..16].copy_from_slice(&(-1i32).to_le_bytes());
    let buf = cloud_msg(Encoding::Ros1, 0, (1, 1, 16), &ring, false, &data);
    assert!(decode_with(&buf, Encoding::Ros1)
        .unwrap_err()
        .message()
        .contains("beam index"));
}
