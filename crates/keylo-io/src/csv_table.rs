//! CSV tables as keylo writes them (`frames.csv`, `degeneracy.csv`, `compare.csv`,
//! `per_image.csv`, `summary.csv`, `sweep.csv`) and reads them back: through the `csv` crate,
//! so a field holding a comma, a quote or a line break is quoted and round-trips.
//!
//! ```
//! use keylo_io::csv_table::{line, parse};
//! let text = format!("{}{}", line(["name", "value"]), line(["a,b \"c\"", "1"]));
//! assert_eq!(text, "name,value\n\"a,b \"\"c\"\"\",1\n");
//! let (header, rows) = parse(text.as_bytes()).unwrap();
//! assert_eq!((header[0].as_str(), rows[0][0].as_str()), ("name", "a,b \"c\""));
//! ```

use std::path::Path;

use crate::IoError;

/// CSV text that cannot be read: the record (1 = the first after the header) and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    #[error("header: {0}")]
    Header(String),
    #[error("record {record}: {message}")]
    Record { record: usize, message: String },
}

/// One CSV record with its line break, fields quoted where needed.
pub fn line<I, F>(fields: I) -> String
where
    I: IntoIterator<Item = F>,
    F: AsRef<[u8]>,
{
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    // Writing to memory cannot fail; the record of an empty iterator is an empty line.
    let _ = w.write_record(fields);
    let bytes = w.into_inner().unwrap_or_default();
    String::from_utf8(bytes).unwrap_or_default()
}

/// A whole table: the header line, then one line per record.
pub fn table<H, R, F>(header: &[H], records: impl IntoIterator<Item = R>) -> String
where
    H: AsRef<[u8]>,
    R: IntoIterator<Item = F>,
    F: AsRef<[u8]>,
{
    let mut out = line(header);
    for r in records {
        out.push_str(&line(r));
    }
    out
}

/// The header and records of CSV text. Records may differ in length (a line cut short by a
/// killed writer is the caller's to skip); an error names the record.
pub fn parse(text: &[u8]) -> Result<(Vec<String>, Vec<Vec<String>>), TableError> {
    let mut r = csv::ReaderBuilder::new().flexible(true).from_reader(text);
    let header = r
        .headers()
        .map_err(|e| TableError::Header(e.to_string()))?
        .iter()
        .map(str::to_string)
        .collect();
    let mut records = Vec::new();
    for (i, rec) in r.records().enumerate() {
        let rec = rec.map_err(|e| TableError::Record {
            record: i + 1,
            message: e.to_string(),
        })?;
        records.push(rec.iter().map(str::to_string).collect());
    }
    Ok((header, records))
}

/// [`parse`] of the file at `path`.
pub fn read(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>), IoError> {
    let text = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    parse(&text).map_err(|m| IoError::format(path, m))
}
