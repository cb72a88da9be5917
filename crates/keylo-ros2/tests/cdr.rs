//! keylo-ros2's messages on the wire: the bytes RustDDS writes for them equal the bytes of an
//! independent encoder (PyPI `rosbags`' CDR serialiser for ROS 2 Humble types,
//! `fixtures/make_cdr_fixtures.py`), and those bytes decode back to the same values.

use keylo_ros2::msgs::*;
use ros2_client::dds::rustdds::no_key::SerializerAdapter;
use ros2_client::dds::rustdds::serialization::CDRSerializerAdapter;
use serde::de::DeserializeOwned;
use serde::Serialize;

fn fixture(name: &str) -> Vec<u8> {
    let text = include_str!("fixtures/cdr.json");
    let json: serde_json::Value = serde_json::from_str(text).expect("cdr.json parses");
    let hex = json["messages"][name]["cdr_hex"]
        .as_str()
        .unwrap_or_else(|| panic!("no fixture {name}"));
    (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).expect("hex"))
        .collect()
}

/// What RustDDS puts in a DATA submessage for `value`: the encapsulation header (CDR, little
/// endian) and the body.
fn wire<T: Serialize>(value: &T) -> Vec<u8> {
    assert_eq!(
        <CDRSerializerAdapter<T> as SerializerAdapter<T>>::output_encoding().to_bytes(),
        [0, 1],
        "CDR_LE"
    );
    let body =
        <CDRSerializerAdapter<T> as SerializerAdapter<T>>::to_bytes(value).expect("serialises");
    let mut out = vec![0, 1, 0, 0];
    out.extend_from_slice(&body);
    out
}

fn same_both_ways<T: Serialize + DeserializeOwned + PartialEq + std::fmt::Debug>(
    name: &str,
    value: &T,
) {
    let theirs = fixture(name);
    let ours = wire(value);
    assert_eq!(
        hex(&ours),
        hex(&theirs),
        "{name}: keylo-ros2's bytes (left) against rosbags' (right)"
    );
    let (back, used): (T, usize) =
        cdr_encoding::from_bytes::<T, byteorder::LittleEndian>(&theirs[4..]).expect("decodes");
    assert_eq!(&back, value, "{name}: rosbags' bytes decode to the value");
    assert_eq!(used, theirs.len() - 4, "{name}: every byte read");
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

fn header(sec: i32, nanosec: u32, frame: &str) -> Header {
    Header {
        stamp: Time { sec, nanosec },
        frame_id: frame.into(),
    }
}

fn pose(k: f64) -> Pose {
    Pose {
        position: Point {
            x: 1.5 + k,
            y: -2.25,
            z: 0.125,
        },
        orientation: Quaternion {
            x: 0.1,
            y: -0.2,
            z: 0.3,
            w: 0.9273618495495704,
        },
    }
}

fn cov(base: f64) -> [f64; 36] {
    std::array::from_fn(|i| base + 0.5 * i as f64)
}

fn v3(x: f64, y: f64, z: f64) -> Vector3 {
    Vector3 { x, y, z }
}

#[test]
fn odometry() {
    same_both_ways(
        "odometry",
        &Odometry {
            header: header(1_700_000_000, 123_456_789, "odom_lidar"),
            child_frame_id: "os_sensor".into(),
            pose: PoseWithCovariance {
                pose: pose(0.0),
                covariance: cov(1.0),
            },
            twist: TwistWithCovariance {
                twist: Twist {
                    linear: v3(0.5, 0.25, -0.125),
                    angular: v3(-0.01, 0.02, 0.3),
                },
                covariance: cov(-3.0),
            },
        },
    );
}

#[test]
fn tf_message() {
    let ts = |h: Header, child: &str, t: Vector3, k: f64| TransformStamped {
        header: h,
        child_frame_id: child.into(),
        transform: Transform {
            translation: t,
            rotation: pose(k).orientation,
        },
    };
    same_both_ways(
        "tf",
        &TfMessage {
            transforms: vec![
                ts(
                    header(17, 5, "odom_lidar"),
                    "base_link",
                    v3(3.0, -4.0, 5.5),
                    0.0,
                ),
                ts(header(18, 6, "a"), "bc", v3(-1.0, 0.0, 2.0), 1.0),
            ],
        },
    );
}

#[test]
fn path() {
    same_both_ways(
        "path",
        &Path {
            header: header(20, 7, "odom_lidar"),
            poses: vec![
                PoseStamped {
                    header: header(19, 1, "odom_lidar"),
                    pose: pose(0.0),
                },
                PoseStamped {
                    header: header(20, 7, "odom_lidar"),
                    pose: pose(1.0),
                },
            ],
        },
    );
}

#[test]
fn pointcloud2() {
    let field = |name: &str, offset, datatype| PointField {
        name: name.into(),
        offset,
        datatype,
        count: 1,
    };
    same_both_ways(
        "pointcloud2",
        &PointCloud2 {
            header: header(1_700_000_001, 999, "os_sensor"),
            height: 1,
            width: 2,
            fields: vec![field("x", 0, 7), field("t", 4, 6), field("ring", 8, 4)],
            is_bigendian: false,
            point_step: 10,
            row_step: 20,
            data: (0..20u8).map(|i| i * 7).collect(),
            is_dense: true,
        },
    );
}

#[test]
fn image() {
    same_both_ways(
        "image",
        &Image {
            header: header(3, 4, "cam"),
            height: 2,
            width: 3,
            encoding: "rgb8".into(),
            is_bigendian: 0,
            step: 9,
            data: (0..18u8).map(|i| i + 100).collect(),
        },
    );
}

#[test]
fn pose_with_covariance_stamped() {
    same_both_ways(
        "pose_with_covariance_stamped",
        &PoseWithCovarianceStamped {
            header: header(-5, 6, "odom_lidar"),
            pose: PoseWithCovariance {
                pose: pose(2.0),
                covariance: cov(7.0),
            },
        },
    );
}

#[test]
fn empty() {
    same_both_ways("empty", &Empty::default());
}
