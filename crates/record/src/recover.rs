//! Finishing the recording of a killed session.
//!
//! The recorder closes a chunk every second, so a killed process leaves every complete chunk
//! on disk and one unfinished chunk at the end (its length still the writer's placeholder).
//! Streaming readers can read up to that point; [`recover`] copies every schema, channel,
//! message and metadata record up to the first unreadable record into a new recording with a
//! summary section and an index, which every MCAP reader and Foxglove open.
//!
//! It streams, on the crate's one record walk ([`super::walk`]): the input is read front to
//! back once, holding at most one record (and one chunk being decompressed) at a time, so
//! memory stays bounded by [`super::MAX_RECORD_BYTES`] whatever the file's size; a record
//! claiming more ends the copy there, by name, instead of allocating its claimed length, and
//! every length prefix inside a record is checked before the record is parsed. Its walk lets
//! mcap's reader unpack the chunks, which gives a chunk's records as they arrive, so a file
//! cut in the middle of a chunk keeps the records before the cut.

use super::error::ReadError;
use super::walk::{Rec, Records};
use super::writer::mcap_options;
use mcap::records::Record;
use std::collections::BTreeMap;
use std::io::{Read, Seek, Write};

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
    NotMcap(ReadError),
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

/// Copy the readable part of the recording read from `input` into `out` as a finished
/// recording; returns what was copied and the sink. Reads `input` once, front to back, in
/// bounded memory.
pub fn recover<R: Read, W: Write + Seek>(input: R, out: W) -> Result<(Recovered, W), RecoverError> {
    let mut records = Records::unpacked_by_mcap(input);
    let mut writer =
        mcap_options(concat!("telerehab ", env!("CARGO_PKG_VERSION"), " recover")).create(out)?;
    let mut schemas: BTreeMap<u16, u16> = BTreeMap::new();
    let mut channels: BTreeMap<u16, u16> = BTreeMap::new();
    // The channels written, by their id in the output: a damaged file may declare one input
    // id twice with different contents (the later declaration wins for its messages).
    let mut written = std::collections::BTreeSet::new();
    let mut copied = Recovered::default();
    let mut first = true;
    loop {
        let record = match records.next() {
            Ok(record) => record,
            Err(ReadError::Io { source, .. }) => return Err(RecoverError::Read(source)),
            // Not even a header: not a recording (a killed one still has its header).
            Err(e) if first => return Err(RecoverError::NotMcap(e)),
            Err(e) => {
                copied.stopped_at = Some(e.to_string());
                break;
            }
        };
        first = false;
        let record = match record {
            Rec::End => break,
            Rec::Other => continue,
            Rec::Message(m) => {
                if let Some(&channel_id) = channels.get(&m.header.channel_id) {
                    writer.write_to_known_channel(
                        &mcap::records::MessageHeader {
                            channel_id,
                            ..m.header
                        },
                        m.data,
                    )?;
                    copied.messages += 1;
                }
                continue;
            }
            Rec::Record(record, _) => record,
        };
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
        // Cut inside the last chunk, as a SIGKILL leaves it.
        let summary = mcap::Summary::read(&whole).unwrap().unwrap();
        let last = summary.chunk_indexes.last().unwrap();
        whole.truncate((last.chunk_start_offset + last.chunk_length / 2) as usize);
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
        assert_eq!(
            stopped,
            format!(
                "a record (opcode 0x0c) claims {} bytes, more than the {} this reader accepts \
                 (a damaged or hostile recording)",
                1u64 << 40,
                crate::MAX_RECORD_BYTES
            )
        );
    }
}
