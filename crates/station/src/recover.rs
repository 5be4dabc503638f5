//! `telerehab recover`: turn the recording of a killed session into a finished MCAP file.
//!
//! The recorder closes a chunk every second, so a killed process leaves every complete chunk
//! on disk and one unfinished chunk at the end (its length still the writer's placeholder).
//! Streaming readers can read up to that point; this command copies every schema, channel,
//! message and metadata record up to the first unreadable record into a new file with a
//! summary section and an index, which every MCAP reader and Foxglove open.

use anyhow::Context;
use mcap::records::Record;
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::Path;

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

/// Copy the readable part of `input` into a finished MCAP file `output`.
pub fn recover(input: &Path, output: &Path) -> anyhow::Result<Recovered> {
    let bytes = std::fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
    let file = std::fs::File::create(output)
        .with_context(|| format!("cannot create {}", output.display()))?;
    let mut writer = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .library(concat!("telerehab ", env!("CARGO_PKG_VERSION"), " recover"))
        .create(BufWriter::new(file))
        .context("cannot start the recovered file")?;
    let mut schemas: BTreeMap<u16, u16> = BTreeMap::new();
    let mut channels: BTreeMap<u16, u16> = BTreeMap::new();
    let mut out = Recovered::default();
    let records =
        mcap::read::ChunkFlattener::new(&bytes).context("not an MCAP file (bad magic)")?;
    for record in records {
        let record = match record {
            Ok(r) => r,
            Err(e) => {
                out.stopped_at = Some(e.to_string());
                break;
            }
        };
        match record {
            Record::Schema { header, data } => {
                let id = writer.add_schema(&header.name, &header.encoding, &data)?;
                schemas.insert(header.id, id);
            }
            Record::Channel(c) => {
                let schema_id = if c.schema_id == 0 {
                    0
                } else {
                    *schemas
                        .get(&c.schema_id)
                        .context("channel before its schema")?
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
                    out.messages += 1;
                }
            }
            Record::Metadata(m) => writer.write_metadata(&m)?,
            _ => {}
        }
    }
    out.channels = channels.len();
    writer
        .finish()
        .context("cannot finish the recovered file")?;
    Ok(out)
}
