//! The one walk over the records of a recording that every reader in this crate stands on
//! (the streaming reader, the column reader, the comparison, the whole-file reader and
//! `recover`), and the one record limit they share: a recording may come from anyone (the hub
//! replays what stations upload; `recover` reads what a killed process left), so every length
//! is checked before anything is allocated for it.
//!
//! `Records` reads the file once, front to back, through mcap's sans-I/O linear reader:
//! - a record outside chunks, and a whole chunk record (its compressed data), at most
//!   [`MAX_RECORD_BYTES`] (the linear reader enforces it);
//! - a chunk's declared uncompressed size at most [`StreamLimits::max_chunk_bytes`], and the
//!   chunk decompressed as a stream, one record at a time, never past what it declares (a zstd
//!   bomb stops at its declared size, and that is bounded); the decoder's window is bounded
//!   too ([`ZSTD_WINDOW_LOG_MAX`]);
//! - a record inside a chunk at most [`MAX_RECORD_BYTES`] and within the chunk;
//! - every length prefix inside a record the readers parse within the record
//!   (`check_lengths`): mcap's parser reserves a string's claimed length first, so a damaged
//!   26-byte header claiming a 2 GB string would allocate it;
//! - a message record's header parsed by hand (`Message`): the reader decides by its channel
//!   whether to read it at all, and checks its data against
//!   [`StreamLimits::max_message_bytes`] by the channel's name.
//!
//! `recover`'s walk leaves the chunks to mcap's reader instead (within the same record limit),
//! which gives a chunk's records before the chunk is whole: a cut file keeps what precedes the
//! cut.
//!
//! The 9-byte record header (opcode, length) is read by `head` and held to the limit by
//! `within_limit`, here and in the survey of a file's cost ([`super::cost::survey`]).
//!
//! Memory: one compressed chunk, one record and the decoder's window — at most some
//! 3 × [`MAX_RECORD_BYTES`] for any file, a few MB for the station's own.

use super::error::ReadError;
use mcap::records::{MessageHeader, Record, op};
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use std::io::{Cursor, Read};

/// The largest record any reader of a recording accepts, bytes: a record outside chunks, a
/// whole chunk record (compressed), or a record inside a chunk. 16 MiB: the station's writer
/// closes its chunks at 1 MiB uncompressed, so its chunk records and most of its records are
/// 16 times smaller; the one record that can outgrow a chunk is the `/metrics` message written
/// once at the end, which lists every movement of the session — some 300 bytes of JSON a
/// movement, a movement a second or so for the longest session
/// ([`super::cost::LONGEST_SESSION_S`], 4 h): about 4.3 MB, under a third of the limit. A
/// reader holds at most some three records' worth (a compressed chunk, the record read from
/// it, the decoder's window), so 16 MiB keeps a hostile file under 50 MB of memory per reader.
pub const MAX_RECORD_BYTES: usize = 16 << 20;

/// The largest zstd window the chunk decoder accepts, log2 bytes (16 MiB; the station's
/// chunks are 1 MiB, so their frames never need more).
pub const ZSTD_WINDOW_LOG_MAX: u32 = 24;

/// The bounds a reader enforces, besides [`MAX_RECORD_BYTES`], before it allocates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StreamLimits {
    /// Largest uncompressed size a chunk may declare, bytes.
    pub max_chunk_bytes: u64,
    /// Largest message on one of our channels, bytes.
    pub max_message_bytes: usize,
}

impl Default for StreamLimits {
    /// 16 MiB chunks (the station's writer closes chunks at 1 MiB), 256 KiB messages (a block
    /// of 100 samples is a few KB).
    fn default() -> Self {
        Self {
            max_chunk_bytes: 16 << 20,
            max_message_bytes: 256 << 10,
        }
    }
}

/// Asked while a walk reads, every [`CHECK_EVERY_RECORDS`] records and at each chunk: a
/// reason to stop reading (the reader went away, the work's CPU budget is spent), or `None`
/// to go on. A stop ends the walk with [`ReadError::Stopped`].
pub type Check = Box<dyn FnMut() -> Option<String> + Send>;

/// Records read between two calls of a walk's [`Check`] (a few milliseconds of work at
/// most, whatever the file holds).
pub const CHECK_EVERY_RECORDS: u32 = 4096;

/// A message record: its header parsed by hand, its data not yet looked at.
pub(crate) struct Message<'a> {
    /// Channel id, sequence, log and publish times.
    pub(crate) header: MessageHeader,
    /// The message's data, unchecked against [`StreamLimits::max_message_bytes`].
    pub(crate) data: &'a [u8],
}

impl<'a> Message<'a> {
    /// Bytes of a message record before its data: channel id (2), sequence (4), log and
    /// publish times (8 each) (MCAP specification, "Message").
    const HEADER_BYTES: usize = 2 + 4 + 8 + 8;

    /// The message of record `data` in `chunk`, or why it is damaged.
    fn parse(data: &'a [u8], chunk: u64) -> Result<Self, ReadError> {
        if data.len() < Self::HEADER_BYTES {
            return Err(ReadError::Damaged {
                chunk,
                reason: format!("a message record of {} bytes", data.len()),
            });
        }
        let u64_at = |at: usize| u64::from_le_bytes(data[at..at + 8].try_into().expect("8"));
        Ok(Self {
            header: MessageHeader {
                channel_id: u16::from_le_bytes([data[0], data[1]]),
                sequence: u32::from_le_bytes(data[2..6].try_into().expect("4 bytes")),
                log_time: u64_at(6),
                publish_time: u64_at(14),
            },
            data: &data[Self::HEADER_BYTES..],
        })
    }

    /// Its data, or the message refused by the name of its channel (`topic`) when it is over
    /// `max_bytes`.
    pub(crate) fn data_within(&self, topic: &str, max_bytes: usize) -> Result<&'a [u8], ReadError> {
        if self.data.len() > max_bytes {
            return Err(ReadError::TooLarge {
                what: format!("a message of channel {topic}"),
                claimed_bytes: self.data.len() as u64,
                limit_bytes: max_bytes as u64,
            });
        }
        Ok(self.data)
    }
}

/// One record of the file's data section, chunks unpacked, as far as a reader needs it.
pub(crate) enum Rec<'a> {
    /// A message record.
    Message(Message<'a>),
    /// A header, schema, channel or metadata record, its lengths checked and parsed, and the
    /// chunk holding it (from 1; 0: outside chunks).
    Record(Record<'a>, u64),
    /// A record no reader uses (parsed no further).
    Other,
    /// The end of the data section.
    End,
}

/// Records the readers use; the rest of the stream (indexes, statistics, attachments,
/// summary) is skipped unparsed.
const USED: [u8; 5] = [
    op::HEADER,
    op::SCHEMA,
    op::CHANNEL,
    op::MESSAGE,
    op::METADATA,
];

/// Where the walk stands after one step.
enum Step {
    /// A used record, in `record`: its opcode and chunk (0: none).
    Used(u8, u64),
    Other,
    End,
}

/// The chunk being read: its records, decompressed as they are read.
struct Chunk {
    /// Position in the file, from 1.
    number: u64,
    /// Uncompressed bytes it declares.
    declared: u64,
    /// Uncompressed bytes still to read.
    left: u64,
    /// Its records, uncompressed.
    body: Box<dyn Read + Send>,
}

/// The records of a recording read front to back from `R`, chunks unpacked, within
/// [`MAX_RECORD_BYTES`] and the [`StreamLimits`].
pub(crate) struct Records<R> {
    input: R,
    reader: LinearReader,
    limits: StreamLimits,
    chunk: Option<Chunk>,
    chunks: u64,
    /// The record being handed out.
    record: Vec<u8>,
    /// Asked now and then whether to stop.
    check: Option<Check>,
    /// Records read since `check` was last asked.
    since_check: u32,
}

impl<R: Read> Records<R> {
    /// The walk over `input`, chunks opened by the walk itself (within `limits`).
    pub(crate) fn new(input: R, limits: StreamLimits) -> Self {
        Self::with_chunks_emitted(input, limits, true)
    }

    /// The walk over `input` with mcap's linear reader unpacking the chunks, which gives a
    /// chunk's records as its bytes arrive: a chunk cut short (a file truncated in the middle
    /// of one) still gives the records before the cut, which `recover` wants to keep. Its
    /// records and chunks are held to [`MAX_RECORD_BYTES`] by mcap's reader (the chunk's
    /// uncompressed size included); the chunks get no number (0) in errors.
    pub(crate) fn unpacked_by_mcap(input: R) -> Self {
        Self::with_chunks_emitted(input, StreamLimits::default(), false)
    }

    fn with_chunks_emitted(input: R, limits: StreamLimits, emit_chunks: bool) -> Self {
        let options = LinearReaderOptions::default()
            .with_emit_chunks(emit_chunks)
            .with_record_length_limit(MAX_RECORD_BYTES);
        Self {
            input,
            reader: LinearReader::new_with_options(options),
            limits,
            chunk: None,
            chunks: 0,
            record: Vec::new(),
            check: None,
            since_check: 0,
        }
    }

    /// The walk, asking `check` now and then whether to stop.
    pub(crate) fn with_check(mut self, check: Option<Check>) -> Self {
        self.check = check;
        self
    }

    /// Chunks opened so far.
    pub(crate) fn chunks(&self) -> u64 {
        self.chunks
    }

    /// The limits the walk was made with.
    pub(crate) fn limits(&self) -> StreamLimits {
        self.limits
    }

    /// The next record, parsed as far as [`Rec`] says; [`Rec::End`] after the end.
    pub(crate) fn next(&mut self) -> Result<Rec<'_>, ReadError> {
        let (opcode, chunk) = match self.step()? {
            Step::End => return Ok(Rec::End),
            Step::Other => return Ok(Rec::Other),
            Step::Used(opcode, chunk) => (opcode, chunk),
        };
        let data = &self.record;
        if opcode == op::MESSAGE {
            return Message::parse(data, chunk).map(Rec::Message);
        }
        check_lengths(opcode, data).map_err(|reason| ReadError::Damaged { chunk, reason })?;
        Ok(Rec::Record(mcap::parse_record(opcode, data)?, chunk))
    }

    /// Reads up to the next record; a used one is left in `record`.
    fn step(&mut self) -> Result<Step, ReadError> {
        loop {
            ask(&mut self.check, &mut self.since_check, false)?;
            if let Some(chunk) = &mut self.chunk {
                if chunk.left > 0 {
                    let opcode = next_in_chunk(chunk, &mut self.record)?;
                    return Ok(if USED.contains(&opcode) {
                        Step::Used(opcode, chunk.number)
                    } else {
                        Step::Other
                    });
                }
                let number = chunk.number;
                let mut probe = [0u8; 1];
                if read_full(&mut chunk.body, &mut probe, number)? > 0 {
                    return Err(ReadError::BadChunk {
                        chunk: number,
                        reason: format!(
                            "decompresses to more than the {} bytes it declares",
                            chunk.declared
                        ),
                    });
                }
                self.chunk = None;
            }
            let Some(event) = self.reader.next_event() else {
                return Ok(Step::End);
            };
            let chunks = self.chunks;
            match event.map_err(|e| mcap_error(e, chunks))? {
                LinearReadEvent::ReadRequest(need) => {
                    let buf = self.reader.insert(need);
                    let n = loop {
                        match self.input.read(buf) {
                            Ok(n) => break n,
                            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                            Err(source) => {
                                return Err(ReadError::Io {
                                    path: String::new(),
                                    source,
                                });
                            }
                        }
                    };
                    // 0 is the end of the input.
                    self.reader.notify_read(n);
                }
                LinearReadEvent::Record { opcode, data } => match opcode {
                    op::CHUNK => {
                        ask(&mut self.check, &mut self.since_check, true)?;
                        self.chunks += 1;
                        let chunk = open_chunk(self.chunks, data, &self.limits)?;
                        self.chunk = Some(chunk);
                    }
                    op::DATA_END => return Ok(Step::End),
                    op if USED.contains(&op) => {
                        self.record.clear();
                        self.record.extend_from_slice(data);
                        return Ok(Step::Used(op, 0));
                    }
                    _ => return Ok(Step::Other),
                },
            }
        }
    }
}

/// The opcode and length of the 9-byte header that opens every record (MCAP specification,
/// "Records").
pub(crate) fn head(header: &[u8; 9]) -> (u8, u64) {
    let len = u64::from_le_bytes(header[1..].try_into().expect("8 bytes"));
    (header[0], len)
}

/// A record's length (`len`, of the record with `opcode` at `place`: `""` or ` in chunk 3`),
/// or the record refused by name when it is over [`MAX_RECORD_BYTES`].
pub(crate) fn within_limit(opcode: u8, len: u64, place: &str) -> Result<usize, ReadError> {
    match usize::try_from(len) {
        Ok(n) if n <= MAX_RECORD_BYTES => Ok(n),
        _ => Err(too_large(opcode, len, place)),
    }
}

/// A record refused for its length.
fn too_large(opcode: u8, len: u64, place: &str) -> ReadError {
    ReadError::TooLarge {
        what: format!("a record (opcode 0x{opcode:02x}){place}"),
        claimed_bytes: len,
        limit_bytes: MAX_RECORD_BYTES as u64,
    }
}

/// Asks `check` now (`force`) or once every [`CHECK_EVERY_RECORDS`] calls (`since`: the calls
/// since it was last asked).
fn ask(check: &mut Option<Check>, since: &mut u32, force: bool) -> Result<(), ReadError> {
    let Some(check) = check else {
        return Ok(());
    };
    *since += 1;
    if !force && *since < CHECK_EVERY_RECORDS {
        return Ok(());
    }
    *since = 0;
    match check() {
        Some(reason) => Err(ReadError::Stopped(reason)),
        None => Ok(()),
    }
}

/// mcap's length errors in this walk's words (`chunks`: the chunks read so far).
fn mcap_error(e: mcap::McapError, chunks: u64) -> ReadError {
    match e {
        mcap::McapError::RecordTooLarge { opcode, len } => too_large(opcode, len, ""),
        mcap::McapError::ChunkTooLarge(len) => ReadError::TooLarge {
            what: format!("chunk {}", chunks + 1),
            claimed_bytes: len,
            limit_bytes: MAX_RECORD_BYTES as u64,
        },
        other => ReadError::Mcap(other),
    }
}

/// Reads `buf.len()` bytes of a chunk's body, or up to its end; returns the bytes read.
fn read_full(body: &mut dyn Read, buf: &mut [u8], chunk: u64) -> Result<usize, ReadError> {
    let mut got = 0;
    while got < buf.len() {
        match body.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => {
                return Err(ReadError::BadChunk {
                    chunk,
                    reason: format!("does not decompress: {e}"),
                });
            }
        }
    }
    Ok(got)
}

/// The next record of `chunk` into `record`; returns its opcode.
fn next_in_chunk(chunk: &mut Chunk, record: &mut Vec<u8>) -> Result<u8, ReadError> {
    let number = chunk.number;
    let short = |what: &str, left: u64| ReadError::BadChunk {
        chunk: number,
        reason: format!("ends in the middle of {what} ({left} of its declared bytes left)"),
    };
    if chunk.left < 9 {
        return Err(short("a record header", chunk.left));
    }
    let mut header = [0u8; 9];
    if read_full(&mut chunk.body, &mut header, number)? < 9 {
        return Err(ReadError::BadChunk {
            chunk: number,
            reason: format!(
                "decompresses to fewer than the {} bytes it declares",
                chunk.declared
            ),
        });
    }
    chunk.left -= 9;
    let (opcode, len) = head(&header);
    if len > chunk.left {
        return Err(ReadError::BadChunk {
            chunk: number,
            reason: format!(
                "holds a record (opcode 0x{opcode:02x}) of {len} bytes, past its end ({} bytes \
                 left)",
                chunk.left
            ),
        });
    }
    let len = within_limit(opcode, len, &format!(" in chunk {number}"))?;
    record.clear();
    record.resize(len, 0);
    if read_full(&mut chunk.body, record, number)? < len {
        return Err(short("a record", chunk.left));
    }
    chunk.left -= len as u64;
    Ok(opcode)
}

/// A chunk record's header checked against the limits, and its body ready to decompress.
fn open_chunk(number: u64, data: &[u8], limits: &StreamLimits) -> Result<Chunk, ReadError> {
    let bad = |reason: String| ReadError::BadChunk {
        chunk: number,
        reason,
    };
    // start time, end time, uncompressed size, uncompressed CRC, compression (u32 length and
    // text), compressed size, then the records (MCAP specification, "Chunk").
    let u64_at = |at: usize| {
        data.get(at..at + 8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
            .ok_or_else(|| bad("has a truncated header".to_owned()))
    };
    let declared = u64_at(16)?;
    let name_len = data
        .get(28..32)
        .map(|b| u32::from_le_bytes(b.try_into().expect("4 bytes")) as usize)
        .ok_or_else(|| bad("has a truncated header".to_owned()))?;
    let name = data
        .get(32..32 + name_len)
        .ok_or_else(|| bad("has a truncated header".to_owned()))?;
    let compressed = u64_at(32 + name_len)?;
    let records = &data[(40 + name_len).min(data.len())..];
    if compressed > records.len() as u64 {
        return Err(bad(format!(
            "declares {compressed} compressed bytes, {} are there",
            records.len()
        )));
    }
    if declared > limits.max_chunk_bytes {
        return Err(ReadError::TooLarge {
            what: format!("the uncompressed data of chunk {number}"),
            claimed_bytes: declared,
            limit_bytes: limits.max_chunk_bytes,
        });
    }
    let records = records[..compressed as usize].to_vec();
    let body: Box<dyn Read + Send> = match name {
        b"" => {
            if declared != compressed {
                return Err(bad(format!(
                    "is uncompressed but declares {declared} bytes of {compressed}"
                )));
            }
            Box::new(Cursor::new(records))
        }
        b"zstd" => {
            let mut decoder = zstd::stream::read::Decoder::with_buffer(Cursor::new(records))
                .map_err(|e| bad(format!("cannot start its zstd decoder: {e}")))?;
            decoder
                .window_log_max(ZSTD_WINDOW_LOG_MAX)
                .map_err(|e| bad(format!("cannot bound its zstd decoder: {e}")))?;
            Box::new(decoder)
        }
        other => {
            return Err(bad(format!(
                "is compressed with {:?}, which this reader does not decode (the station \
                 writes zstd)",
                String::from_utf8_lossy(other)
            )));
        }
    };
    Ok(Chunk {
        number,
        declared,
        left: declared,
        body,
    })
}

/// Walks a record's fields, checking each length prefix against what is left.
struct Fields<'a> {
    opcode: u8,
    record_len: usize,
    rest: &'a [u8],
}

impl<'a> Fields<'a> {
    fn of(opcode: u8, data: &'a [u8]) -> Self {
        Self {
            opcode,
            record_len: data.len(),
            rest: data,
        }
    }

    /// The next `n` bytes of `field`.
    fn take(&mut self, field: &'static str, n: u64) -> Result<&'a [u8], String> {
        match usize::try_from(n) {
            Ok(n) if n <= self.rest.len() => {
                let (head, tail) = self.rest.split_at(n);
                self.rest = tail;
                Ok(head)
            }
            _ => Err(format!(
                "record opcode 0x{:02x}: its {field} claims {n} bytes, {} are left of the \
                 record's {}",
                self.opcode,
                self.rest.len(),
                self.record_len
            )),
        }
    }

    /// A fixed-size field.
    fn fixed(&mut self, field: &'static str, n: u64) -> Result<(), String> {
        self.take(field, n).map(drop)
    }

    /// A field behind a little-endian u32 length (a string, a map, schema data).
    fn prefixed(&mut self, field: &'static str) -> Result<&'a [u8], String> {
        let len = self.take(field, 4)?;
        let n = u32::from_le_bytes(len.try_into().expect("4 bytes"));
        self.take(field, u64::from(n))
    }

    /// A `map<string, string>`: its byte length, then each key and value within it.
    fn string_map(&mut self, field: &'static str) -> Result<(), String> {
        let mut entries = Fields {
            rest: self.prefixed(field)?,
            ..*self
        };
        while !entries.rest.is_empty() {
            entries.prefixed(field)?;
            entries.prefixed(field)?;
        }
        Ok(())
    }
}

/// Checks every length inside a record the readers parse (MCAP specification, "Records"),
/// so parsing it allocates no more than the record's own length; the reason, in words, when
/// one overruns the record. The summary's chunk and metadata indexes are checked too (for
/// [`super::select`], which reads them).
pub(crate) fn check_lengths(opcode: u8, data: &[u8]) -> Result<(), String> {
    let mut f = Fields::of(opcode, data);
    match opcode {
        op::HEADER => {
            f.prefixed("profile")?;
            f.prefixed("library")?;
        }
        op::SCHEMA => {
            f.fixed("schema id", 2)?;
            f.prefixed("schema name")?;
            f.prefixed("schema encoding")?;
            f.prefixed("schema data")?;
        }
        op::CHANNEL => {
            f.fixed("channel and schema ids", 4)?;
            f.prefixed("topic")?;
            f.prefixed("message encoding")?;
            f.string_map("channel metadata")?;
        }
        op::METADATA => {
            f.prefixed("metadata name")?;
            f.string_map("metadata")?;
        }
        op::CHUNK_INDEX => {
            f.fixed("message times and chunk place", 32)?;
            f.prefixed("message index offsets")?;
            f.fixed("message index length", 8)?;
            f.prefixed("compression")?;
            f.fixed("chunk sizes", 16)?;
        }
        op::METADATA_INDEX => {
            f.fixed("metadata place", 16)?;
            f.prefixed("metadata name")?;
        }
        _ => {}
    }
    Ok(())
}
