//! `CloudFramer::frame_message` (straight from the bytes when no grid is needed) makes the
//! frame `frame` makes of `to_raw_cloud`'s cloud, and refuses what it refuses.

use super::*;
use crate::cloud::{ProjectionConfig, RowSource, Sensor, VerticalAngleCorrection};
use crate::ros::msgs::tests::cloud_msg;
use crate::ros::pointcloud2::tests::bytes_of;
use crate::ros::wire::Encoding;

/// A deterministic spread of values in `[-span, span)`.
fn values(n: usize, seed: u64, span: f64) -> Vec<f64> {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * span
        })
        .collect()
}

/// A time field: its datatype and the value of point `i`.
type TimeOf<'a> = (u8, &'a dyn Fn(usize) -> f64);

struct Layout<'a> {
    n: usize,
    xyz: u8,
    intensity: Option<u8>,
    time: Option<TimeOf<'a>>,
    big: bool,
    stamp_ns: i64,
}

fn message(l: &Layout) -> Vec<u8> {
    let mut fields = vec![("x", 0, l.xyz), ("y", 8, l.xyz), ("z", 16, l.xyz)];
    if let Some(code) = l.intensity {
        fields.push(("intensity", 24, code));
    }
    if let Some((code, _)) = l.time {
        fields.push(("time", 32, code));
    }
    let [x, y, z, v] = [1u64, 2, 3, 4].map(|seed| values(l.n, seed, 40.0));
    let mut data = vec![0u8; 40 * l.n];
    for i in 0..l.n {
        let mut put = |off: usize, code: u8, value: f64| {
            let b = bytes_of(code, value, l.big);
            data[40 * i + off..40 * i + off + b.len()].copy_from_slice(&b);
        };
        // Every 17th point is not finite where the type can say so.
        let x = if i % 17 == 5 { f64::NAN } else { x[i] };
        put(0, l.xyz, x);
        put(8, l.xyz, y[i]);
        put(16, l.xyz, z[i] / 4.0);
        if let Some(code) = l.intensity {
            put(24, code, v[i].abs());
        }
        if let Some((code, t)) = l.time {
            put(32, code, t(i));
        }
    }
    cloud_msg(
        Encoding::Cdr,
        l.stamp_ns,
        (1, l.n as u32, 40),
        &fields,
        l.big,
        &data,
    )
}

fn framer(config: &ProjectionConfig, correction: Option<VerticalAngleCorrection>) -> CloudFramer {
    let projector = Projector::from_config(config, Sensor::Generic)
        .unwrap()
        .with_correction(correction);
    let mut f = CloudFramer::new(projector, None, "test");
    f.set_grid_needed(false);
    f
}

/// [`assert_same`] for a message read straight from its bytes, whose frame has points.
fn assert_same_from_bytes(buf: &[u8], config: &ProjectionConfig, what: &str) {
    let msg = PointCloud2::decode(buf, Encoding::Cdr).unwrap();
    assert!(
        matches!(DirectPoints::of(&msg), Ok(Some(_))),
        "{what}: not read from the bytes"
    );
    let frame = framer(config, None).frame_message(&msg, 0).unwrap();
    assert!(
        frame.scan.is_some_and(|s| s.len() > msg.width as usize / 2),
        "{what}"
    );
    assert_same(buf, config, what);
}

/// Both ways on `buf`: the same frame, or the same error.
fn assert_same(buf: &[u8], config: &ProjectionConfig, what: &str) {
    let correction = VerticalAngleCorrection::new(0.205);
    for c in [None, correction] {
        let msg = PointCloud2::decode(buf, Encoding::Cdr).unwrap();
        let two_step = to_raw_cloud(&msg)
            .map_err(|e| e.to_string())
            .and_then(|cloud| framer(config, c).frame(&cloud, 3));
        let direct = framer(config, c).frame_message(&msg, 3);
        assert_eq!(direct, two_step, "{what}, correction {}", c.is_some());
    }
}

#[test]
fn every_datatype_and_byte_order_gives_the_same_frame() {
    let ns = |i: usize| 1e3 * i as f64;
    let s = |i: usize| 1e-6 * i as f64 - if i.is_multiple_of(23) { f64::NAN } else { 0.0 };
    for big in [false, true] {
        for code in 1..=8u8 {
            let time: TimeOf = if code >= 7 { (code, &s) } else { (6, &ns) };
            let layout = Layout {
                n: 300,
                xyz: code,
                intensity: Some(9 - code),
                time: Some(time),
                big,
                stamp_ns: 1_500_000_000,
            };
            let what = format!("datatype {code}, big endian {big}");
            assert_same_from_bytes(&message(&layout), &ProjectionConfig::default(), &what);
        }
    }
}

#[test]
fn times_by_azimuth_and_absolute_times_give_the_same_frame() {
    let config = ProjectionConfig {
        frame_rate_hz: 10.0,
        ..ProjectionConfig::default()
    };
    let stamp_ns = 1_700_000_000_123_456_789;
    let stamp_s = 1_700_000_000.123_456_8;
    let epoch_s = |i: usize| stamp_s + 1e-5 * i as f64;
    let epoch_ns = |i: usize| 1e9 * (stamp_s + 1e-5 * i as f64);
    let cases: [(&str, Option<TimeOf>); 3] = [
        ("no time field", None),
        ("f64 seconds since the epoch", Some((8, &epoch_s))),
        ("f64 nanoseconds since the epoch", Some((8, &epoch_ns))),
    ];
    for (what, time) in cases {
        let layout = Layout {
            n: 500,
            xyz: 7,
            intensity: None,
            time,
            big: false,
            stamp_ns,
        };
        assert_same_from_bytes(&message(&layout), &config, what);
    }
}

#[test]
fn refusals_and_clouds_left_to_the_two_steps_agree() {
    let xyz = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7)];
    let data: Vec<u8> = (0..24).map(|b| (b * 7) as u8).collect();
    let msg = |fields: &[(&str, u32, u8)], shape| {
        cloud_msg(Encoding::Cdr, 0, shape, fields, false, &data)
    };
    let config = ProjectionConfig::default();
    assert_same(&msg(&xyz[..2], (1, 2, 12)), &config, "no z");
    assert_same(&msg(&xyz, (1, 3, 12)), &config, "data too short");
    let bad_reflectivity = [xyz[0], xyz[1], xyz[2], ("reflectivity", 8, 9)];
    assert_same(&msg(&bad_reflectivity, (1, 2, 12)), &config, "bad datatype");
    let ring = [xyz[0], xyz[1], xyz[2], ("ring", 8, 2)];
    assert_same(&msg(&ring, (1, 2, 12)), &config, "rings");
    let by_ring = ProjectionConfig {
        row_from: RowSource::Ring,
        ..ProjectionConfig::default()
    };
    assert_same(
        &msg(&xyz, (1, 2, 12)),
        &by_ring,
        "rows from rings, none given",
    );
    assert_same(&msg(&xyz, (2, 1, 12)), &config, "organised");
    assert_same(&msg(&xyz, (0, 0, 12))[..], &config, "no point");
}
