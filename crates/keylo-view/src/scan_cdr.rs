//! The input scan as a ROS 2 `sensor_msgs/msg/PointCloud2` (XCDR1, little endian): what a ROS 2
//! user expects in a recording, what Foxglove and Lichtblick draw, and what `keylo run --data`
//! reads back (docs/formats.md, "ROS recordings").

use keylo_core::LidarFrame;

/// The `ros2msg` schema of `sensor_msgs/msg/PointCloud2`, with its dependencies as ROS 2's
/// recorder writes them.
pub const POINTCLOUD2_SCHEMA: &str = "std_msgs/Header header
uint32 height
uint32 width
PointField[] fields
bool is_bigendian
uint32 point_step
uint32 row_step
uint8[] data
bool is_dense
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: sensor_msgs/PointField
uint8 INT8=1
uint8 UINT8=2
uint8 INT16=3
uint8 UINT16=4
uint8 INT32=5
uint8 UINT32=6
uint8 FLOAT32=7
uint8 FLOAT64=8
string name
uint32 offset
uint8 datatype
uint32 count
";

const FLOAT32: u8 = 7;
const UINT16: u8 = 4;
const UINT32: u8 = 6;

/// A little-endian CDR writer (alignment counted after the 4-byte encapsulation header).
struct Cdr(Vec<u8>);

impl Cdr {
    fn new(capacity: usize) -> Self {
        let mut buf = Vec::with_capacity(capacity + 256);
        buf.extend_from_slice(&[0, 1, 0, 0]);
        Self(buf)
    }
    fn align(&mut self, n: usize) {
        while !(self.0.len() - 4).is_multiple_of(n) {
            self.0.push(0);
        }
    }
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.align(4);
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn string(&mut self, s: &str) {
        self.u32(s.len() as u32 + 1);
        self.0.extend_from_slice(s.as_bytes());
        self.0.push(0);
    }
}

/// One field of the cloud: name, datatype, size in bytes.
type Field = (&'static str, u8, u32);

/// The message's bytes; `fill` writes the `data` field's `len` bytes in place (no copy of a
/// multi-megabyte cloud).
fn message(
    stamp_ns: u64,
    frame_id: &str,
    (height, width): (u32, u32),
    fields: &[Field],
    dense: bool,
    (len, fill): (usize, impl FnOnce(&mut [u8])),
) -> Vec<u8> {
    let point_step: u32 = fields.iter().map(|f| f.2).sum();
    let mut w = Cdr::new(len);
    w.u32((stamp_ns / 1_000_000_000).min(i32::MAX as u64) as u32);
    w.u32((stamp_ns % 1_000_000_000) as u32);
    w.string(frame_id);
    w.u32(height);
    w.u32(width);
    w.u32(fields.len() as u32);
    let mut offset = 0;
    for (name, datatype, size) in fields {
        w.string(name);
        w.u32(offset);
        w.u8(*datatype);
        w.u32(1);
        offset += size;
    }
    w.u8(0);
    w.u32(point_step);
    w.u32(point_step * width);
    w.u32(len as u32);
    let start = w.0.len();
    w.0.resize(start + len, 0);
    fill(&mut w.0[start..]);
    w.u8(u8::from(dense));
    w.0
}

fn push_f32(data: &mut Vec<u8>, v: f32) {
    data.extend_from_slice(&v.to_le_bytes());
}

/// Nanoseconds from `t0` to `t` as the `t` field (0 when before `t0` or not finite).
fn offset_ns(t: f64, t0: f64) -> u32 {
    let d = (t - t0) * 1e9;
    if d.is_finite() && d > 0.0 {
        d.round().min(u32::MAX as f64) as u32
    } else {
        0
    }
}

/// The frame's scan: for a sensor's grid, the organised `rows × cols` cloud (`x y z` 0 where
/// there is no return, as ouster-ros writes it; `intensity` = signal, `reflectivity`, `near_ir`,
/// `range` in metres, `t` ns after the stamp); for an unorganised source every point of the
/// scan (`x y z`, `intensity` and `ring` when the file had them, `t`). The stamp is the frame's
/// timestamp.
pub fn scan(frame: &LidarFrame, frame_id: &str) -> Vec<u8> {
    let stamp = crate::convert::nanos(frame.timestamp);
    match &frame.scan {
        Some(s) => {
            let mut fields: Vec<Field> =
                vec![("x", FLOAT32, 4), ("y", FLOAT32, 4), ("z", FLOAT32, 4)];
            if s.intensity.is_some() {
                fields.push(("intensity", FLOAT32, 4));
            }
            if s.times.is_some() {
                fields.push(("t", UINT32, 4));
            }
            if s.ring.is_some() {
                fields.push(("ring", UINT16, 2));
            }
            let step: u32 = fields.iter().map(|f| f.2).sum();
            let mut data = Vec::with_capacity(s.points.len() * step as usize);
            for (i, p) in s.points.iter().enumerate() {
                for v in [p.x, p.y, p.z] {
                    push_f32(&mut data, v as f32);
                }
                if let Some(v) = &s.intensity {
                    push_f32(&mut data, v.get(i).copied().unwrap_or(0.0));
                }
                if let Some(t) = &s.times {
                    let t = t.get(i).copied().unwrap_or(0.0);
                    data.extend_from_slice(&offset_ns(t, 0.0).to_le_bytes());
                }
                if let Some(r) = &s.ring {
                    data.extend_from_slice(&r.get(i).copied().unwrap_or(0).to_le_bytes());
                }
            }
            let n = s.points.len() as u32;
            let copy = |out: &mut [u8]| out.copy_from_slice(&data);
            message(stamp, frame_id, (1, n), &fields, true, (data.len(), copy))
        }
        None => organised(frame, frame_id, stamp),
    }
}

/// The frame's points for watching: every valid pixel (or scan point) as `x y z intensity`
/// (float32), unorganised, stamped at the frame's start: half the bytes of [`scan`] or less, and
/// what a viewer draws.
pub fn points(frame: &LidarFrame, frame_id: &str) -> Vec<u8> {
    let stamp = crate::convert::nanos(frame.timestamp);
    let fields: [Field; 4] = [
        ("x", FLOAT32, 4),
        ("y", FLOAT32, 4),
        ("z", FLOAT32, 4),
        ("intensity", FLOAT32, 4),
    ];
    let put = |data: &mut Vec<u8>, point: [f32; 4]| {
        for c in point {
            data.extend_from_slice(&c.to_le_bytes());
        }
    };
    let mut data: Vec<u8> = Vec::new();
    match &frame.scan {
        Some(s) => {
            data.reserve(s.points.len() * 16);
            for (i, p) in s.points.iter().enumerate() {
                let v = s.intensity.as_ref().and_then(|t| t.get(i)).copied();
                put(
                    &mut data,
                    [p.x as f32, p.y as f32, p.z as f32, v.unwrap_or(0.0)],
                );
            }
        }
        None => {
            data.reserve(frame.valid_count() * 16);
            for (i, _) in frame.valid.iter().enumerate().filter(|(_, v)| **v) {
                let p = frame.points.get(i).copied().unwrap_or_default();
                let v = frame.signal.get(i).copied().unwrap_or(0.0);
                put(&mut data, [p.x, p.y, p.z, v]);
            }
        }
    }
    let n = (data.len() / 16) as u32;
    let copy = |out: &mut [u8]| out.copy_from_slice(&data);
    message(stamp, frame_id, (1, n), &fields, true, (data.len(), copy))
}

fn organised(frame: &LidarFrame, frame_id: &str, stamp: u64) -> Vec<u8> {
    let fields: [Field; 8] = [
        ("x", FLOAT32, 4),
        ("y", FLOAT32, 4),
        ("z", FLOAT32, 4),
        ("intensity", FLOAT32, 4),
        ("reflectivity", FLOAT32, 4),
        ("near_ir", FLOAT32, 4),
        ("range", FLOAT32, 4),
        ("t", UINT32, 4),
    ];
    let n = frame.rows * frame.cols;
    let channels = [&frame.signal, &frame.reflectivity, &frame.near_ir];
    let fill = |data: &mut [u8]| {
        for (i, out) in data.chunks_exact_mut(32).enumerate() {
            // One 32-byte point: x y z intensity reflectivity near_ir range (f32), t (u32).
            let mut point = [0f32; 7];
            if frame.valid.get(i).copied().unwrap_or(false) {
                let p = frame.points.get(i).copied().unwrap_or_default();
                point[..3].copy_from_slice(&[p.x, p.y, p.z]);
                point[6] = frame.range.get(i).copied().unwrap_or(0.0);
            }
            for (k, ch) in channels.iter().enumerate() {
                point[3 + k] = ch.get(i).copied().unwrap_or(0.0);
            }
            for (k, v) in point.iter().enumerate() {
                out[4 * k..4 * k + 4].copy_from_slice(&v.to_le_bytes());
            }
            let t = offset_ns(frame.pixel_time(i), frame.timestamp);
            out[28..32].copy_from_slice(&t.to_le_bytes());
        }
    };
    let shape = (frame.rows as u32, frame.cols as u32);
    message(stamp, frame_id, shape, &fields, false, (n * 32, fill))
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use keylo_core::BeamGeometry;
    use nalgebra::Point3;

    use super::*;

    /// Reads what [`message`] wrote (XCDR1 little endian, alignment after the 4-byte header).
    struct Reader<'a>(&'a [u8], usize);

    impl Reader<'_> {
        fn u8(&mut self) -> u8 {
            self.1 += 1;
            self.0[self.1 - 1]
        }
        fn u32(&mut self) -> u32 {
            while !(self.1 - 4).is_multiple_of(4) {
                assert_eq!(self.0[self.1], 0, "padding at {}", self.1);
                self.1 += 1;
            }
            self.1 += 4;
            u32::from_le_bytes(self.0[self.1 - 4..self.1].try_into().unwrap())
        }
        fn string(&mut self) -> String {
            let n = self.u32() as usize;
            self.1 += n;
            assert_eq!(self.0[self.1 - 1], 0, "NUL-terminated");
            String::from_utf8(self.0[self.1 - n..self.1 - 1].to_vec()).unwrap()
        }
    }

    fn frame() -> LidarFrame {
        let beams = Arc::new(BeamGeometry {
            model: "test".into(),
            altitude_deg: vec![1.0, -1.0],
            azimuth_deg: vec![0.0, 0.0],
            origin_to_beam_mm: 0.0,
            columns_per_frame: 3,
            frame_rate_hz: 10.0,
            column_lag_by_row: Vec::new(),
        });
        let mut f = LidarFrame::empty(0, 12.5, 2, 3, beams);
        f.column_times = vec![12.5, 12.53, 12.56];
        f.valid[4] = true;
        f.points[4] = Point3::new(1.0, -2.0, 0.5);
        f.range[4] = 2.3;
        f.signal[4] = 40.0;
        f
    }

    #[test]
    fn an_organised_scan_is_a_pointcloud2_in_xcdr1() {
        let bytes = scan(&frame(), "lidar");
        assert_eq!(&bytes[..4], &[0, 1, 0, 0]);
        let mut r = Reader(&bytes, 4);
        assert_eq!((r.u32(), r.u32()), (12, 500_000_000));
        assert_eq!(r.string(), "lidar");
        assert_eq!((r.u32(), r.u32()), (2, 3));
        let fields: Vec<(String, u32, u8, u32)> = (0..r.u32())
            .map(|_| (r.string(), r.u32(), r.u8(), r.u32()))
            .collect();
        let names: Vec<&str> = fields.iter().map(|f| f.0.as_str()).collect();
        assert_eq!(
            names,
            [
                "x",
                "y",
                "z",
                "intensity",
                "reflectivity",
                "near_ir",
                "range",
                "t"
            ]
        );
        assert!(fields
            .iter()
            .enumerate()
            .all(|(k, f)| f.1 == 4 * k as u32 && f.3 == 1));
        assert_eq!((fields[0].2, fields[7].2), (FLOAT32, UINT32));
        assert_eq!(r.u8(), 0, "little endian");
        assert_eq!((r.u32(), r.u32()), (32, 96), "point_step, row_step");
        let len = r.u32() as usize;
        assert_eq!(len, 6 * 32);
        let data = &bytes[r.1..r.1 + len];
        let f32_at = |o: usize| f32::from_le_bytes(data[o..o + 4].try_into().unwrap());
        // Pixel 4 (row 1, column 1): its point, signal and range; its column's time.
        let p = 4 * 32;
        assert_eq!([f32_at(p), f32_at(p + 4), f32_at(p + 8)], [1.0, -2.0, 0.5]);
        assert_eq!((f32_at(p + 12), f32_at(p + 24)), (40.0, 2.3));
        let t = u32::from_le_bytes(data[p + 28..p + 32].try_into().unwrap());
        assert_eq!(t, 30_000_000);
        // No return: the origin, as ouster-ros writes it.
        assert_eq!([f32_at(0), f32_at(4), f32_at(8), f32_at(24)], [0.0; 4]);
        r.1 += len;
        assert_eq!(r.u8(), 0, "is_dense");
        assert_eq!(r.1, bytes.len());
    }

    #[test]
    fn watched_points_are_the_valid_ones() {
        let bytes = points(&frame(), "lidar");
        let mut r = Reader(&bytes, 4);
        r.u32();
        r.u32();
        r.string();
        assert_eq!((r.u32(), r.u32()), (1, 1), "one valid pixel");
        let n = r.u32();
        let names: Vec<String> = (0..n)
            .map(|_| (r.string(), r.u32(), r.u8(), r.u32()).0)
            .collect();
        assert_eq!(names, ["x", "y", "z", "intensity"]);
        r.u8();
        assert_eq!((r.u32(), r.u32(), r.u32()), (16, 16, 16));
    }
}
