//! One `.ply` file to a [`RawCloud`], with `ply-rs-bw` doing the parsing (ascii, binary
//! little and big endian). Elements are read one at a time straight into columns, so no
//! per-vertex map or intermediate vertex vector is built.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyAccess, PropertyAccessResult};
use ply_rs_bw::ply::{PropertyType, ScalarType};

use crate::cloud::RawCloud;
use crate::folder::fields::{alias_index, FieldInfo, FieldMap, FieldOptions, FIELD_NAMES};
use crate::folder::Columns;
use crate::IoError;

/// The element holding the points.
const VERTEX: &str = "vertex";

type PlyReader = Reader<BufReader<File>>;

/// The fields of the `vertex` element of `path` (reads the header only).
pub fn ply_fields(path: &Path) -> Result<Vec<FieldInfo>, IoError> {
    let (_, header) = open(path)?;
    Ok(vertex_fields(vertex_def(path, &header)?))
}

/// Reads `path`: the `vertex` element's mapped fields (x, y, z required), other elements
/// skipped. `stamp` is the cloud time unless the points carry an absolute clock.
pub fn read_ply(path: &Path, stamp: f64, options: &FieldOptions) -> Result<RawCloud, IoError> {
    let (mut reader, header) = open(path)?;
    let def = vertex_def(path, &header)?;
    let fields = vertex_fields(def);
    let map = FieldMap::new(&fields).map_err(|m| IoError::format(path, m))?;
    // Where each field's value lands in a parsed vertex (its name's alias slot).
    let alias: Vec<Option<usize>> = fields.iter().map(|f| alias_index(&f.name)).collect();
    let mut columns = Columns::new(&map, def.count.min(1 << 20));
    for (name, element) in &header.elements {
        if name == VERTEX {
            read_elements::<Vertex>(&mut reader, &header, element, |v| {
                columns.push(|p| alias[p].map_or(f64::NAN, |a| v.values[a]));
            })
            .map_err(|m| IoError::format(path, m))?;
            break;
        }
        read_elements::<Skip>(&mut reader, &header, element, |_| {})
            .map_err(|m| IoError::format(path, m))?;
    }
    columns
        .finish(stamp, None, options)
        .map_err(|m| IoError::format(path, m))
}

fn open(path: &Path) -> Result<(PlyReader, Header), IoError> {
    let file = File::open(path).map_err(|e| IoError::io(path, e))?;
    let mut reader = Reader::new(BufReader::new(file));
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| IoError::format(path, format!("PLY header: {}", one_line(&e))))?;
    Ok((reader, header))
}

fn vertex_def<'a>(path: &Path, header: &'a Header) -> Result<&'a ElementDef, IoError> {
    header.elements.get(VERTEX).ok_or_else(|| {
        let names: Vec<&str> = header.elements.keys().map(String::as_str).collect();
        IoError::format(
            path,
            format!(
                "no `vertex` element (expected the points there; elements: {})",
                names.join(", ")
            ),
        )
    })
}

fn vertex_fields(def: &ElementDef) -> Vec<FieldInfo> {
    def.properties
        .values()
        .map(|p| {
            let (integer, count) = match &p.data_type {
                PropertyType::Scalar(s) => {
                    (!matches!(s, ScalarType::Float | ScalarType::Double), 1)
                }
                PropertyType::List(_, _) => (false, 0),
            };
            FieldInfo {
                name: p.name.clone(),
                integer,
                count,
            }
        })
        .collect()
}

/// Reads the `element.count` elements of one element type, handing each to `each`; the
/// error says which element ran short or is malformed.
fn read_elements<E: PropertyAccess>(
    reader: &mut PlyReader,
    header: &Header,
    element: &ElementDef,
    mut each: impl FnMut(&E),
) -> Result<(), String> {
    let parser = Parser::<E>::new();
    let mut line = String::new();
    for i in 0..element.count {
        let result = match header.encoding {
            Encoding::Ascii => {
                line.clear();
                match reader.get_mut().read_line(&mut line) {
                    Ok(0) => Err("the file ends here".to_string()),
                    Ok(_) => parser
                        .read_ascii_element(&line, element)
                        .map_err(|e| one_line(&e)),
                    Err(e) => Err(e.to_string()),
                }
            }
            Encoding::BinaryLittleEndian => parser
                .read_little_endian_element(reader.get_mut(), element)
                .map_err(|e| binary_error(&e)),
            Encoding::BinaryBigEndian => parser
                .read_big_endian_element(reader.get_mut(), element)
                .map_err(|e| binary_error(&e)),
        };
        match result {
            Ok(e) => each(&e),
            Err(m) => {
                return Err(format!(
                    "{} element {i} of the {} the header declares ({}): {m}",
                    element.name, element.count, header.encoding
                ))
            }
        }
    }
    Ok(())
}

fn binary_error(e: &ply_rs_bw::parser::ParseError) -> String {
    if e.kind() == std::io::ErrorKind::UnexpectedEof {
        "the file ends here".to_string()
    } else {
        one_line(e)
    }
}

/// A library message on one line (ply-rs puts details on indented extra lines).
fn one_line(e: &impl std::fmt::Display) -> String {
    e.to_string()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// One parsed vertex: the value of every known field name, by [`FIELD_NAMES`] position.
struct Vertex {
    values: [f64; FIELD_NAMES.len()],
}

impl Vertex {
    fn set(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        match alias_index(name) {
            Some(a) => {
                self.values[a] = value;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::Ignored,
        }
    }
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Self {
            values: [f64::NAN; FIELD_NAMES.len()],
        }
    }
    fn set_char(&mut self, name: &str, v: i8) -> PropertyAccessResult {
        self.set(name, f64::from(v))
    }
    fn set_uchar(&mut self, name: &str, v: u8) -> PropertyAccessResult {
        self.set(name, f64::from(v))
    }
    fn set_short(&mut self, name: &str, v: i16) -> PropertyAccessResult {
        self.set(name, f64::from(v))
    }
    fn set_ushort(&mut self, name: &str, v: u16) -> PropertyAccessResult {
        self.set(name, f64::from(v))
    }
    fn set_int(&mut self, name: &str, v: i32) -> PropertyAccessResult {
        self.set(name, f64::from(v))
    }
    fn set_uint(&mut self, name: &str, v: u32) -> PropertyAccessResult {
        self.set(name, f64::from(v))
    }
    fn set_float(&mut self, name: &str, v: f32) -> PropertyAccessResult {
        self.set(name, f64::from(v))
    }
    fn set_double(&mut self, name: &str, v: f64) -> PropertyAccessResult {
        self.set(name, v)
    }
}

/// An element that is read past (every property ignored).
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}
