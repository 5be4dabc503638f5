//! Finishing the recording of a killed session.
//!
//! The recorder closes a chunk every second, so a killed process leaves every complete chunk
//! on disk and one unfinished chunk at the end (its length still the writer's placeholder).
//! Streaming readers can read up to that point; [`recover`] copies every schema, channel,
//! message and metadata record up to the first unreadable record into a new recording with a
//! summary section and an index, which every MCAP reader and Foxglove open.

use super::writer::mcap_options;
use mcap::records::Record;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

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
    NotMcap(mcap::McapError),
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

/// Copy the readable part of the recording `bytes` into `out` as a finished recording;
/// returns what was copied and the sink.
pub fn recover<W: Write + Seek>(bytes: &[u8], out: W) -> Result<(Recovered, W), RecoverError> {
    let records = mcap::read::ChunkFlattener::new(bytes).map_err(RecoverError::NotMcap)?;
    let mut writer =
        mcap_options(concat!("telerehab ", env!("CARGO_PKG_VERSION"), " recover")).create(out)?;
    let mut schemas: BTreeMap<u16, u16> = BTreeMap::new();
    let mut channels: BTreeMap<u16, u16> = BTreeMap::new();
    let mut copied = Recovered::default();
    for record in records {
        let record = match record {
            Ok(r) => r,
            Err(e) => {
                copied.stopped_at = Some(e.to_string());
                break;
            }
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
    copied.channels = channels.len();
    writer.finish()?;
    Ok((copied, writer.into_inner()))
}
