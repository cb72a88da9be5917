//! The streaming pieces of MCAP reading: the summary through the sans-io reader, and
//! messages in file order for files without a usable summary.

use std::fs::File;
use std::io::{BufReader, Read, Seek};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use mcap::sans_io::{LinearReaderOptions, SummaryReadEvent, SummaryReader, SummaryReaderOptions};
use mcap::{Message, Summary};

use crate::IoError;

/// Largest record or chunk read (compressed or not); a corrupt length beyond it is an error
/// instead of an allocation.
pub(crate) const RECORD_LIMIT: usize = 512 << 20;

/// The summary section through the sans-io reader (reads clamped to the file size).
pub(crate) fn read_summary(
    file: &mut BufReader<File>,
    len: u64,
) -> Result<Option<Summary>, String> {
    let options = SummaryReaderOptions::default()
        .with_file_size(len)
        .with_record_length_limit(RECORD_LIMIT);
    let mut reader = SummaryReader::new_with_options(options);
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| e.to_string())? {
            SummaryReadEvent::ReadRequest(need) => {
                let n = file.read(reader.insert(need)).map_err(|e| e.to_string())?;
                reader.notify_read(n);
            }
            SummaryReadEvent::SeekRequest(to) => {
                let at = file.seek(to).map_err(|e| e.to_string())?;
                reader.notify_seeked(at);
            }
        }
    }
    Ok(reader.finish())
}

/// Counts the bytes a reader has delivered (for error positions).
struct Counted<R> {
    inner: R,
    read: Arc<AtomicU64>,
}

impl<R: Read> Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.read.fetch_add(n as u64, Ordering::Relaxed);
        Ok(n)
    }
}

/// Messages in file order, chunk CRCs checked before a chunk's messages come out.
pub(crate) struct Linear {
    reader: mcap::io::MessageReader<Counted<BufReader<File>>>,
    read: Arc<AtomicU64>,
    index: u64,
}

impl Linear {
    pub fn open(path: &Path) -> Result<Self, IoError> {
        let file = File::open(path).map_err(|e| IoError::io(path, e))?;
        let options = LinearReaderOptions::default()
            .with_prevalidate_chunk_crcs(true)
            .with_validate_data_section_crc(true)
            .with_record_length_limit(RECORD_LIMIT);
        let read = Arc::new(AtomicU64::new(0));
        let source = Counted {
            inner: BufReader::new(file),
            read: Arc::clone(&read),
        };
        Ok(Self {
            reader: mcap::io::MessageReader::new_with_options(source, options),
            read,
            index: 0,
        })
    }

    /// The next message; the error says after which message and near which byte.
    pub fn next(&mut self) -> Option<Result<Message<'static>, String>> {
        Some(match self.reader.next()? {
            Ok(m) => {
                self.index += 1;
                Ok(m)
            }
            Err(e) => Err(format!(
                "{e} (reading near byte {}, after message {} of the file; \
                 the messages before it were read)",
                self.read.load(Ordering::Relaxed),
                self.index,
            )),
        })
    }
}
