//! Finishing the recording of a killed session.
//!
//! The recorder closes a chunk every second, so a killed process leaves every complete chunk
//! on disk and one unfinished chunk at the end (its length still the writer's placeholder).
//! Streaming readers can read up to that point; [`recover`] copies every schema, channel,
//! message and metadata record up to the first unreadable record into a new recording with a
//! summary section and an index, which every MCAP reader and Foxglove open.
//!
//! It streams: the input is read front to back once through mcap's sans-I/O linear reader,
//! which holds at most one record (and one chunk's decompressed records) at a time, so memory
//! stays bounded by [`MAX_RECORD_BYTES`] whatever the file's size. Every length prefix inside
//! a record is checked against the record's own length before the record is parsed (mcap's
//! parser reserves a string's claimed length first: a damaged 26-byte header claiming a
//! 2 GB string would allocate it), and records the copy does not use are not parsed.

use super::writer::mcap_options;
use mcap::records::Record;
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use std::collections::BTreeMap;
use std::io::{Read, Seek, Write};

/// The largest record (outside chunks) or chunk data buffered while reading, bytes. The
/// station's records are far smaller (chunks close at 1 MiB uncompressed); a longer record
/// in a damaged tail ends the copy there instead of allocating its claimed length.
pub const MAX_RECORD_BYTES: usize = 64 * 1024 * 1024;

/// What a recovery copied.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Recovered {
    /// Messages copied.
    pub messages: u64,
    /// Channels copied.
    pub channels: usize,
    /// Why reading stopped early, if it did (the truncated tail).
    pub stopped_at: Option<String>,
}

/// Why a recording could not be recovered.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RecoverError {
    /// The input does not even start like an MCAP file.
    #[error("not an MCAP file: {0}")]
    NotMcap(Damaged),
    /// The input could not be read (an I/O error, not its end).
    #[error("cannot read the recording: {0}")]
    Read(std::io::Error),
    /// A channel refers to a schema the file never defined.
    #[error("channel {topic} comes before its schema {schema_id}")]
    ChannelBeforeSchema {
        /// The channel's topic.
        topic: String,
        /// The schema id it refers to.
        schema_id: u16,
    },
    /// Writing the recovered file failed.
    #[error("cannot write the recovered recording: {0}")]
    Write(#[from] mcap::McapError),
}

/// Why the stream stops making sense at a record.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Damaged {
    /// The MCAP reader refused it.
    #[error(transparent)]
    Mcap(#[from] mcap::McapError),
    /// A length inside a record claims more bytes than the record has.
    #[error(
        "record opcode 0x{opcode:02x}: its {field} claims {claimed} bytes, {left} are left of \
         the record's {record_len}"
    )]
    Overrun {
        /// The record's opcode.
        opcode: u8,
        /// The field whose length prefix overruns.
        field: &'static str,
        /// The length the prefix claims, bytes.
        claimed: u64,
        /// Bytes of the record left at the field.
        left: usize,
        /// The record's length, bytes.
        record_len: usize,
    },
}

/// A record read, the reason the stream stops making sense, or the input's I/O error.
type NextRecord = Result<Result<Record<'static>, Damaged>, std::io::Error>;

/// The records the copy uses (header, schema, channel, message, metadata); the rest of the
/// stream (indexes, statistics, attachments, summary) is skipped unparsed.
const COPIED: [u8; 5] = [
    mcap::records::op::HEADER,
    mcap::records::op::SCHEMA,
    mcap::records::op::CHANNEL,
    mcap::records::op::MESSAGE,
    mcap::records::op::METADATA,
];

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
    fn take(&mut self, field: &'static str, n: u64) -> Result<&'a [u8], Damaged> {
        match usize::try_from(n) {
            Ok(n) if n <= self.rest.len() => {
                let (head, tail) = self.rest.split_at(n);
                self.rest = tail;
                Ok(head)
            }
            _ => Err(Damaged::Overrun {
                opcode: self.opcode,
                field,
                claimed: n,
                left: self.rest.len(),
                record_len: self.record_len,
            }),
        }
    }

    /// A fixed-size field.
    fn fixed(&mut self, field: &'static str, n: u64) -> Result<(), Damaged> {
        self.take(field, n).map(drop)
    }

    /// A field behind a little-endian u32 length (a string, a map, schema data).
    fn prefixed(&mut self, field: &'static str) -> Result<&'a [u8], Damaged> {
        let len = self.take(field, 4)?;
        let n = u32::from_le_bytes(len.try_into().expect("4 bytes"));
        self.take(field, u64::from(n))
    }

    /// A `map<string, string>`: its byte length, then each key and value within it.
    fn string_map(&mut self, field: &'static str) -> Result<(), Damaged> {
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

/// Checks every length inside a record the copy parses (MCAP specification, "Records"), so
/// parsing it allocates no more than the record's own length.
pub(super) fn check_lengths(opcode: u8, data: &[u8]) -> Result<(), Damaged> {
    use mcap::records::op;
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
        op::MESSAGE => f.fixed("message header", 2 + 4 + 8 + 8)?,
        op::METADATA => {
            f.prefixed("metadata name")?;
            f.string_map("metadata")?;
        }
        _ => {}
    }
    Ok(())
}

/// The records of an MCAP stream read from `input` front to back, chunks unpacked: each item
/// is the next record, `Err(McapError)` where the stream stops making sense (a truncated or
/// damaged tail), or an I/O error of the input itself.
struct Records<R> {
    input: R,
    reader: LinearReader,
}

impl<R: Read> Records<R> {
    fn new(input: R) -> Self {
        let options = LinearReaderOptions::default().with_record_length_limit(MAX_RECORD_BYTES);
        Self {
            input,
            reader: LinearReader::new_with_options(options),
        }
    }

    /// The next record, `None` at the end of a finished stream.
    fn next_record(&mut self) -> Option<NextRecord> {
        loop {
            match self.reader.next_event()? {
                Ok(LinearReadEvent::ReadRequest(need)) => {
                    let buf = self.reader.insert(need);
                    let n = loop {
                        match self.input.read(buf) {
                            Ok(n) => break n,
                            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                            Err(e) => return Some(Err(e)),
                        }
                    };
                    // 0 is the end of the input.
                    self.reader.notify_read(n);
                }
                Ok(LinearReadEvent::Record { opcode, data }) => {
                    if !COPIED.contains(&opcode) {
                        continue;
                    }
                    return Some(Ok(check_lengths(opcode, data).and_then(|()| {
                        mcap::parse_record(opcode, data)
                            .map(Record::into_owned)
                            .map_err(Damaged::from)
                    })));
                }
                Err(e) => return Some(Ok(Err(e.into()))),
            }
        }
    }
}

/// Copy the readable part of the recording read from `input` into `out` as a finished
/// recording; returns what was copied and the sink. Reads `input` once, front to back, in
/// bounded memory.
pub fn recover<R: Read, W: Write + Seek>(input: R, out: W) -> Result<(Recovered, W), RecoverError> {
    let mut records = Records::new(input);
    let mut writer =
        mcap_options(concat!("telerehab ", env!("CARGO_PKG_VERSION"), " recover")).create(out)?;
    let mut schemas: BTreeMap<u16, u16> = BTreeMap::new();
    let mut channels: BTreeMap<u16, u16> = BTreeMap::new();
    // The channels written, by their id in the output: a damaged file may declare one input
    // id twice with different contents (the later declaration wins for its messages).
    let mut written = std::collections::BTreeSet::new();
    let mut copied = Recovered::default();
    let mut first = true;
    while let Some(record) = records.next_record() {
        let record = match record.map_err(RecoverError::Read)? {
            Ok(r) => r,
            // Not even a header: not a recording (a killed one still has its header).
            Err(e) if first => return Err(RecoverError::NotMcap(e)),
            Err(e) => {
                copied.stopped_at = Some(e.to_string());
                break;
            }
        };
        first = false;
        match record {
            Record::Schema { header, data } => {
                let id = writer.add_schema(&header.name, &header.encoding, &data)?;
                schemas.insert(header.id, id);
            }
            Record::Channel(c) => {
                let schema_id = match c.schema_id {
                    0 => 0,
                    id => *schemas
                        .get(&id)
                        .ok_or_else(|| RecoverError::ChannelBeforeSchema {
                            topic: c.topic.clone(),
                            schema_id: id,
                        })?,
                };
                let id =
                    writer.add_channel(schema_id, &c.topic, &c.message_encoding, &c.metadata)?;
                channels.insert(c.id, id);
                written.insert(id);
            }
            Record::Message { header, data } => {
                if let Some(&channel_id) = channels.get(&header.channel_id) {
                    writer.write_to_known_channel(
                        &mcap::records::MessageHeader {
                            channel_id,
                            ..header
                        },
                        &data,
                    )?;
                    copied.messages += 1;
                }
            }
            Record::Metadata(m) => writer.write_metadata(&m)?,
            _ => {}
        }
    }
    copied.channels = written.len();
    writer.finish()?;
    Ok((copied, writer.into_inner()))
}

#[cfg(test)]
mod tests {
    use super::{RecoverError, recover};
    use crate::{RecordWriter, SessionMetadata, TickRecord};
    use std::io::{Cursor, Read};

    /// A killed session's file: 2500 ticks with a chunk closed every 1000, no summary.
    fn killed() -> Vec<u8> {
        let mut w =
            RecordWriter::new(Cursor::new(Vec::new()), 0, &SessionMetadata::default()).unwrap();
        let mut closed = 0;
        for tick in 0..2500u64 {
            let rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                ..Default::default()
            };
            w.write_tick(&rec, tick % 100 == 0).unwrap();
            if tick % 1000 == 999 {
                w.flush().unwrap();
                closed = tick;
            }
        }
        assert_eq!(closed, 1999);
        let mut whole = w.finish().unwrap().into_inner();
        // Cut inside the summary section and the last chunk, as a SIGKILL leaves it.
        whole.truncate(whole.len() * 9 / 10);
        whole
    }

    /// Hands out at most `step` bytes per read, and counts what was read.
    struct Trickle<'a> {
        bytes: &'a [u8],
        step: usize,
        read: usize,
    }

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = buf.len().min(self.step).min(self.bytes.len());
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            self.read += n;
            Ok(n)
        }
    }

    #[test]
    fn short_reads_recover_the_same_file_as_one_read_reading_each_byte_once() {
        let input = killed();
        let (whole, out) = recover(input.as_slice(), Cursor::new(Vec::new())).unwrap();
        assert!(
            whole.messages > 0 && whole.stopped_at.is_some(),
            "{whole:?}"
        );
        for step in [1, 7, 4096] {
            let mut trickle = Trickle {
                bytes: &input,
                step,
                read: 0,
            };
            let (copied, again) = recover(&mut trickle, Cursor::new(Vec::new())).unwrap();
            assert_eq!(copied, whole, "{step} bytes a read");
            assert_eq!(again.get_ref(), out.get_ref(), "{step} bytes a read");
            assert!(trickle.read <= input.len(), "read once, front to back");
        }
    }

    #[test]
    fn an_unreadable_input_is_an_error_not_a_truncated_tail() {
        struct Failing<'a>(&'a [u8]);
        impl Read for Failing<'_> {
            fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
                if self.0.is_empty() {
                    return Err(std::io::Error::other("the drive went away"));
                }
                self.0.read(buf)
            }
        }
        let input = killed();
        let err = recover(Failing(&input[..input.len() / 2]), Cursor::new(Vec::new())).unwrap_err();
        assert!(matches!(err, RecoverError::Read(_)), "{err}");
        assert!(err.to_string().contains("the drive went away"), "{err}");
    }

    #[test]
    fn a_file_that_is_not_a_recording_is_refused() {
        for input in [&b"not a recording"[..], &b""[..]] {
            let err = recover(input, Cursor::new(Vec::new())).unwrap_err();
            assert!(matches!(err, RecoverError::NotMcap(_)), "{err}");
        }
    }

    #[test]
    fn a_record_claiming_more_than_the_limit_ends_the_copy_without_allocating_it() {
        let mut input = killed();
        let header_end = 8 + 9 + u64::from_le_bytes(input[9..17].try_into().unwrap()) as usize;
        // A metadata record (opcode 0x0C) right after the header claiming 1 TiB.
        let mut forged = input[..header_end].to_vec();
        forged.push(0x0C);
        forged.extend_from_slice(&(1u64 << 40).to_le_bytes());
        forged.extend_from_slice(&input.split_off(header_end));
        let (copied, _) = recover(forged.as_slice(), Cursor::new(Vec::new())).unwrap();
        assert_eq!(copied.messages, 0);
        let stopped = copied.stopped_at.unwrap();
        assert!(stopped.contains("exceeds limit"), "{stopped}");
    }
}
