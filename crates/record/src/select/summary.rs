//! A recording's summary section and the records it points at (the session metadata, a
//! channel's message index in a chunk), read with mcap's linear reader and record parser
//! within the walk's limits: every record at most [`MAX_RECORD_BYTES`], every length inside
//! one checked before mcap parses it (mcap reserves a string's claimed length first).

use crate::error::ReadError;
use crate::stream::SchemaTable;
use crate::walk::{MAX_RECORD_BYTES, check_lengths, head, within_limit};
use mcap::records::{Channel, ChunkIndex, MetadataIndex, Record, Statistics, op};
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use std::collections::BTreeMap;
use std::io::{Read, Seek, SeekFrom};

/// The footer record (opcode, length, its 20 bytes) and the closing magic (MCAP
/// specification, "Footer").
const FOOTER_AND_MAGIC: usize = 9 + 20 + 8;

/// The closing magic of an MCAP file.
const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// What a recording's summary section says.
#[derive(Debug, Default)]
pub(crate) struct Index {
    /// The schemas, by id.
    pub(crate) schemas: SchemaTable,
    /// The channels, by id.
    pub(crate) channels: BTreeMap<u16, Channel>,
    /// One index per chunk, in file order.
    pub(crate) chunks: Vec<ChunkIndex>,
    /// Where each metadata record is.
    pub(crate) metadata: Vec<MetadataIndex>,
    /// The message counts and times, when written.
    pub(crate) stats: Option<Statistics>,
}

impl Index {
    /// Whether the chunk indexes say where each channel's messages are: a file written
    /// without message indexes (or without chunk indexes) is read front to back instead.
    pub(crate) fn indexes_messages(&self) -> bool {
        self.chunks
            .iter()
            .any(|c| !c.message_index_offsets.is_empty())
    }

    /// The earliest message stamp of the file, ns (log time), from its chunk indexes.
    pub(crate) fn first_stamp_ns(&self) -> Option<u64> {
        self.chunks
            .iter()
            .filter(|c| !c.message_index_offsets.is_empty())
            .map(|c| c.message_start_time)
            .min()
    }
}

/// An I/O error of the recording being read.
pub(crate) fn io(source: std::io::Error) -> ReadError {
    ReadError::Io {
        path: String::new(),
        source,
    }
}

/// The summary section of the recording read by `input`, or `None` when it has none (a
/// file cut short before its footer; one written without a summary).
pub(crate) fn read_index<R: Read + Seek>(input: &mut R) -> Result<Option<Index>, ReadError> {
    let file_bytes = input.seek(SeekFrom::End(0)).map_err(io)?;
    let Some(footer_at) = file_bytes.checked_sub(FOOTER_AND_MAGIC as u64) else {
        return Ok(None);
    };
    input.seek(SeekFrom::Start(footer_at)).map_err(io)?;
    let mut tail = [0u8; FOOTER_AND_MAGIC];
    input.read_exact(&mut tail).map_err(io)?;
    let (opcode, len) = head(tail[..9].try_into().expect("9 bytes"));
    if opcode != op::FOOTER || len != 20 || &tail[29..] != MAGIC {
        return Ok(None);
    }
    let Record::Footer(footer) = mcap::parse_record(op::FOOTER, &tail[9..29])? else {
        return Ok(None);
    };
    if footer.summary_start == 0 || footer.summary_start >= footer_at {
        return Ok(None);
    }
    input
        .seek(SeekFrom::Start(footer.summary_start))
        .map_err(io)?;
    let options = LinearReaderOptions::default()
        .with_skip_start_magic(true)
        .with_record_length_limit(MAX_RECORD_BYTES);
    let mut reader = LinearReader::new_with_options(options);
    let mut index = Index::default();
    while let Some(event) = reader.next_event() {
        match event? {
            LinearReadEvent::ReadRequest(need) => {
                let n = read_some(input, reader.insert(need))?;
                reader.notify_read(n);
            }
            LinearReadEvent::Record { opcode, data } => {
                if !matches!(
                    opcode,
                    op::SCHEMA
                        | op::CHANNEL
                        | op::CHUNK_INDEX
                        | op::METADATA_INDEX
                        | op::STATISTICS
                ) {
                    continue;
                }
                check_lengths(opcode, data).map_err(|reason| summary_damaged(&reason))?;
                match mcap::parse_record(opcode, data)? {
                    Record::Schema { header, data } => {
                        index.schemas.keep(header, data.into_owned(), 0)?;
                    }
                    Record::Channel(c) => {
                        index.channels.insert(c.id, c);
                    }
                    Record::ChunkIndex(c) => index.chunks.push(c),
                    Record::MetadataIndex(m) => index.metadata.push(m),
                    Record::Statistics(s) => index.stats = Some(s),
                    _ => {}
                }
            }
        }
    }
    index.chunks.sort_by_key(|c| c.chunk_start_offset);
    Ok(Some(index))
}

/// Reads what `input` has, up to `buf`'s length; 0 at its end.
fn read_some<R: Read>(input: &mut R, buf: &mut [u8]) -> Result<usize, ReadError> {
    loop {
        match input.read(buf) {
            Ok(n) => return Ok(n),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(io(e)),
        }
    }
}

/// A summary whose records or pointers are not what they claim.
fn summary_damaged(reason: &str) -> ReadError {
    ReadError::Damaged {
        chunk: 0,
        reason: format!("in its summary: {reason}"),
    }
}

/// Reads `len` bytes at `offset` into `buf`.
pub(crate) fn read_at<R: Read + Seek>(
    input: &mut R,
    offset: u64,
    len: usize,
    buf: &mut Vec<u8>,
) -> Result<(), ReadError> {
    input.seek(SeekFrom::Start(offset)).map_err(io)?;
    buf.clear();
    buf.resize(len, 0);
    input.read_exact(buf).map_err(io)
}

/// The record at `offset`, which the summary says is a `what` (of `opcode`): its length held
/// to [`MAX_RECORD_BYTES`] and its fields checked before it is parsed.
fn record_at<'b, R: Read + Seek>(
    input: &mut R,
    offset: u64,
    opcode: u8,
    what: &str,
    buf: &'b mut Vec<u8>,
) -> Result<Record<'b>, ReadError> {
    read_at(input, offset, 9, buf)?;
    let (found, len) = head(buf[..9].try_into().expect("9 bytes"));
    if found != opcode {
        return Err(summary_damaged(&format!(
            "it points at a {what} at byte {offset}, and finds a record of opcode 0x{found:02x}"
        )));
    }
    let len = within_limit(opcode, len, &format!(" (a {what})"))?;
    read_at(input, offset + 9, len, buf)?;
    check_lengths(opcode, buf).map_err(|reason| summary_damaged(&reason))?;
    Ok(mcap::parse_record(opcode, buf)?)
}

/// The metadata record named `name` ([`Index::metadata`]): name → value, or `None` when the
/// summary lists none of that name.
pub(crate) fn metadata<R: Read + Seek>(
    input: &mut R,
    index: &Index,
    name: &str,
) -> Result<Option<BTreeMap<String, String>>, ReadError> {
    let Some(at) = index.metadata.iter().find(|m| m.name == name) else {
        return Ok(None);
    };
    let mut buf = Vec::new();
    match record_at(input, at.offset, op::METADATA, "metadata record", &mut buf)? {
        Record::Metadata(m) if m.name == name => Ok(Some(m.metadata)),
        _ => Err(summary_damaged(&format!(
            "its metadata index names {name:?} at byte {}, where another record is",
            at.offset
        ))),
    }
}

/// The log times of channel `id`'s messages in `chunk` (its message index), ns; none when the
/// chunk holds none of them.
pub(crate) fn stamps<R: Read + Seek>(
    input: &mut R,
    chunk: &ChunkIndex,
    id: u16,
) -> Result<Vec<u64>, ReadError> {
    let Some(&offset) = chunk.message_index_offsets.get(&id) else {
        return Ok(Vec::new());
    };
    let mut buf = Vec::new();
    match record_at(input, offset, op::MESSAGE_INDEX, "message index", &mut buf)? {
        Record::MessageIndex(m) if m.channel_id == id => {
            Ok(m.records.iter().map(|e| e.log_time).collect())
        }
        _ => Err(summary_damaged(&format!(
            "it points at the message index of channel {id} at byte {offset}, where another \
             channel's is"
        ))),
    }
}
