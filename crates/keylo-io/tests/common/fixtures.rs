//! A small writer of PLY and PCD test files, independent of the crates keylo reads them
//! with: the header text is written by hand, binary values with `to_le_bytes` /
//! `to_be_bytes`, and binary_compressed data as LZF literal runs (valid LZF that does not
//! compress).

use std::fmt::Write as _;
use std::path::Path;

/// One point with every field keylo maps (Ouster's types) plus one it does not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pt {
    pub x: f32,
    pub y: f32,
    pub z: f32,
    pub intensity: f32,
    /// Nanoseconds since the frame start.
    pub t: u32,
    pub ring: u16,
    pub reflectivity: u16,
    pub ambient: u16,
    /// Millimetres.
    pub range: u32,
    /// A field keylo does not read.
    pub curvature: f32,
}

/// `n` points spread in azimuth and over four rings, times over 99 ms.
pub fn sample(n: usize) -> Vec<Pt> {
    (0..n)
        .map(|i| {
            let az = i as f32 * 0.37;
            let el = [0.04f32, 0.0, -0.04, -0.08][i % 4];
            let r = 2.0 + i as f32 * 0.25;
            Pt {
                x: r * el.cos() * az.cos(),
                y: r * el.cos() * az.sin(),
                z: r * el.sin(),
                intensity: 10.5 + i as f32,
                t: (i as u64 * 99_000_000 / (n as u64 - 1).max(1)) as u32,
                ring: (i % 4) as u16,
                reflectivity: (100 + i % 1000) as u16,
                ambient: (7 * (i % 1000)) as u16,
                range: (r * 1000.0).round() as u32,
                curvature: 0.5,
            }
        })
        .collect()
}

/// Field names, PLY types, PCD TYPE and SIZE, in file order.
const FIELDS: [(&str, &str, char, usize); 10] = [
    ("x", "float", 'F', 4),
    ("y", "float", 'F', 4),
    ("z", "float", 'F', 4),
    ("intensity", "float", 'F', 4),
    ("t", "uint", 'U', 4),
    ("ring", "ushort", 'U', 2),
    ("reflectivity", "ushort", 'U', 2),
    ("ambient", "ushort", 'U', 2),
    ("range", "uint", 'U', 4),
    ("curvature", "float", 'F', 4),
];

fn text_values(p: &Pt) -> String {
    format!(
        "{} {} {} {} {} {} {} {} {} {}",
        p.x, p.y, p.z, p.intensity, p.t, p.ring, p.reflectivity, p.ambient, p.range, p.curvature
    )
}

fn binary_values(p: &Pt, big_endian: bool) -> Vec<u8> {
    let mut out = Vec::new();
    macro_rules! put {
        ($($v:expr),*) => {$(
            if big_endian { out.extend_from_slice(&$v.to_be_bytes()) }
            else { out.extend_from_slice(&$v.to_le_bytes()) }
        )*};
    }
    put!(
        p.x,
        p.y,
        p.z,
        p.intensity,
        p.t,
        p.ring,
        p.reflectivity,
        p.ambient,
        p.range,
        p.curvature
    );
    out
}

/// PLY encodings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ply {
    Ascii,
    LittleEndian,
    BigEndian,
}

/// A PLY file: an element `sensor` before `vertex` and a `face` element after it (both to be
/// skipped); `declared` is the vertex count written in the header.
pub fn write_ply(path: &Path, points: &[Pt], encoding: Ply, declared: usize) {
    let format = match encoding {
        Ply::Ascii => "ascii",
        Ply::LittleEndian => "binary_little_endian",
        Ply::BigEndian => "binary_big_endian",
    };
    let mut h = format!("ply\nformat {format} 1.0\ncomment keylo test fixture\n");
    h.push_str("element sensor 1\nproperty float rate\n");
    let _ = writeln!(h, "element vertex {declared}");
    for (name, ty, _, _) in FIELDS {
        let _ = writeln!(h, "property {ty} {name}");
    }
    h.push_str("element face 1\nproperty list uchar int vertex_indices\nend_header\n");
    let mut bytes = h.into_bytes();
    let be = encoding == Ply::BigEndian;
    match encoding {
        Ply::Ascii => {
            bytes.extend_from_slice(b"10\n");
            for p in points {
                bytes.extend_from_slice(text_values(p).as_bytes());
                bytes.push(b'\n');
            }
            bytes.extend_from_slice(b"3 0 1 2\n");
        }
        _ => {
            let rate = 10.0f32;
            bytes.extend_from_slice(&if be {
                rate.to_be_bytes()
            } else {
                rate.to_le_bytes()
            });
            for p in points {
                bytes.extend(binary_values(p, be));
            }
            bytes.push(3);
            for i in 0..3i32 {
                bytes.extend_from_slice(&if be { i.to_be_bytes() } else { i.to_le_bytes() });
            }
        }
    }
    std::fs::write(path, bytes).expect("write PLY");
}

/// PCD data kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pcd {
    Ascii,
    Binary,
    Compressed,
}

/// A PCD file, organised `height` rows high when `height > 1`. Binary kinds carry a
/// 2-byte padding field `_` as PCL writes for alignment.
pub fn write_pcd(path: &Path, points: &[Pt], data: Pcd, height: usize) {
    let pad = data != Pcd::Ascii;
    let (mut names, mut sizes, mut types, mut counts) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (name, _, ty, size) in FIELDS {
        names.push(name.to_string());
        sizes.push(size.to_string());
        types.push(ty.to_string());
        counts.push("1".to_string());
    }
    if pad {
        names.push("_".into());
        sizes.push("1".into());
        types.push("U".into());
        counts.push("2".into());
    }
    let kind = match data {
        Pcd::Ascii => "ascii",
        Pcd::Binary => "binary",
        Pcd::Compressed => "binary_compressed",
    };
    let n = points.len();
    let header = format!(
        "# .PCD v0.7 - keylo test fixture\nVERSION 0.7\nFIELDS {}\nSIZE {}\nTYPE {}\nCOUNT {}\n\
         WIDTH {}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {kind}\n",
        names.join(" "),
        sizes.join(" "),
        types.join(" "),
        counts.join(" "),
        n / height.max(1),
    );
    let mut bytes = header.into_bytes();
    match data {
        Pcd::Ascii => {
            for p in points {
                bytes.extend_from_slice(text_values(p).as_bytes());
                bytes.push(b'\n');
            }
        }
        Pcd::Binary => {
            for p in points {
                bytes.extend(binary_values(p, false));
                bytes.extend_from_slice(&[0, 0]);
            }
        }
        Pcd::Compressed => {
            let soa = columns(points);
            let packed = lzf_literals(&soa);
            bytes.extend_from_slice(&(packed.len() as u32).to_le_bytes());
            bytes.extend_from_slice(&(soa.len() as u32).to_le_bytes());
            bytes.extend(packed);
        }
    }
    std::fs::write(path, bytes).expect("write PCD");
}

/// binary_compressed's layout before compression: each field's values for all points in
/// turn (structure of arrays), the padding field last.
fn columns(points: &[Pt]) -> Vec<u8> {
    let rows: Vec<Vec<u8>> = points.iter().map(|p| binary_values(p, false)).collect();
    let mut out = Vec::new();
    let mut offset = 0;
    for (_, _, _, size) in FIELDS {
        for r in &rows {
            out.extend_from_slice(&r[offset..offset + size]);
        }
        offset += size;
    }
    out.extend(std::iter::repeat_n(0u8, 2 * points.len()));
    out
}

/// LZF with literal runs only: a control byte `len - 1` (< 32) before each run of up to 32
/// bytes.
fn lzf_literals(data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    for chunk in data.chunks(32) {
        out.push((chunk.len() - 1) as u8);
        out.extend_from_slice(chunk);
    }
    out
}
