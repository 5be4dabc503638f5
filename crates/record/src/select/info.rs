//! What a recording holds — its channels, their message counts and time spans, its session
//! metadata — from its summary and indexes alone ([`recording_info`]): what to choose a
//! selection from ([`super::Selection`]) without reading the file. A recording without a
//! summary is walked front to back instead (its chunks decompressed, its messages not decoded).
//!
//! Times are session times, s, from the messages' stamps: the earliest stamp of the file is
//! taken as 0 s (the session's first tick, as the station records it). A block message is
//! stamped with its first sample, so a channel of blocks has samples up to a block's span
//! (100 samples, at most a second) after its `last_s`.

use super::plan::{earliest_stamp, latest_stamp};
use super::summary;
use crate::columns::readable_channel;
use crate::error::ReadError;
use crate::stream::SchemaTable;
use crate::types::SessionMetadata;
use crate::walk::{Rec, Records, StreamLimits};
use mcap::records::{Channel, Record};
use std::collections::BTreeMap;
use std::io::{Read, Seek};
use std::path::Path;

/// One channel of a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelInfo {
    /// The topic (`/wheel`).
    pub topic: String,
    /// How its messages are encoded (`protobuf` for blocks and the Foxglove scene, `json`).
    pub encoding: String,
    /// Its schema's name (`telerehab.Wheel`; empty if none).
    pub schema: String,
    /// Whether `telerehab.session` reads it (blocks of columns, or JSON).
    pub readable: bool,
    /// Its messages (a block holds up to 100 samples).
    pub messages: u64,
    /// The stamp of its first message, s of session time (`None`: no message).
    pub first_s: Option<f64>,
    /// The stamp of its last message, s of session time (`None`: no message).
    pub last_s: Option<f64>,
}

/// What a recording holds.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordingInfo {
    /// The `session` metadata record as it is in the file (name → value).
    pub metadata: BTreeMap<String, String>,
    /// Its channels, in the order of their ids (the order the station declares them).
    pub channels: Vec<ChannelInfo>,
    /// Its chunks.
    pub chunks: u64,
    /// Whether this came from the summary and indexes (`false`: the file was walked).
    pub indexed: bool,
}

/// [`recording_info`] of the file at `path`.
pub fn recording_info_path(path: &Path, limits: StreamLimits) -> Result<RecordingInfo, ReadError> {
    let file = std::fs::File::open(path).map_err(|source| ReadError::Io {
        path: format!(" {}", path.display()),
        source,
    })?;
    recording_info(std::io::BufReader::new(file), limits)
}

/// What the recording read by `input` holds (the module's documentation says how). Fails on
/// a file without its `session` metadata record, and where the walk fails on one without a
/// summary.
pub fn recording_info<R: Read + Seek>(
    mut input: R,
    limits: StreamLimits,
) -> Result<RecordingInfo, ReadError> {
    if let Some(index) = summary::read_index(&mut input)?
        && index.indexes_messages()
        && let Some(stats) = &index.stats
        && let Some(metadata) = summary::metadata(&mut input, &index, SessionMetadata::NAME)?
    {
        let zero = index.first_stamp_ns().unwrap_or(0);
        let mut channels = Vec::new();
        for (&id, c) in &index.channels {
            let first = earliest_stamp(&mut input, &index, id)?;
            let last = latest_stamp(&mut input, &index, id, u64::MAX)?;
            let messages = stats.channel_message_counts.get(&id).copied().unwrap_or(0);
            channels.push(info(c, &index.schemas, messages, first, last, zero));
        }
        return Ok(RecordingInfo {
            metadata,
            channels,
            chunks: index.chunks.len() as u64,
            indexed: true,
        });
    }
    input.rewind().map_err(summary::io)?;
    walked(input, limits)
}

/// The channel `c`'s description: `messages` messages, stamped from `first` to `last` (log
/// time, ns; session time 0 at `zero`).
fn info(
    c: &Channel,
    schemas: &SchemaTable,
    messages: u64,
    first: Option<u64>,
    last: Option<u64>,
    zero: u64,
) -> ChannelInfo {
    let s = |t: u64| t.saturating_sub(zero) as f64 * 1e-9;
    ChannelInfo {
        topic: c.topic.clone(),
        encoding: c.message_encoding.clone(),
        schema: schemas
            .by_id()
            .get(&c.schema_id)
            .map(|(name, _)| name.clone())
            .unwrap_or_default(),
        readable: readable_channel(c),
        messages,
        first_s: first.map(s),
        last_s: last.map(s),
    }
}

/// [`recording_info`] by a walk over the whole file (its chunks decompressed, its messages'
/// headers read).
fn walked(input: impl Read, limits: StreamLimits) -> Result<RecordingInfo, ReadError> {
    let mut records = Records::new(input, limits);
    let mut schemas = SchemaTable::default();
    let mut channels: BTreeMap<u16, Channel> = BTreeMap::new();
    // Messages, first and last stamp, by channel id.
    let mut seen: BTreeMap<u16, (u64, u64, u64)> = BTreeMap::new();
    let mut metadata = None;
    loop {
        match records.next()? {
            Rec::End => break,
            Rec::Other => {}
            Rec::Message(m) => {
                let t = m.header.log_time;
                let e = seen.entry(m.header.channel_id).or_insert((0, t, t));
                *e = (e.0 + 1, e.1.min(t), e.2.max(t));
            }
            Rec::Record(Record::Schema { header, data }, chunk) => {
                schemas.keep(header, data.into_owned(), chunk)?;
            }
            Rec::Record(Record::Channel(c), _) => {
                channels.insert(c.id, c);
            }
            Rec::Record(Record::Metadata(m), _) if m.name == SessionMetadata::NAME => {
                metadata = Some(m.metadata);
            }
            Rec::Record(..) => {}
        }
    }
    let metadata = metadata.ok_or(ReadError::NoMetadata)?;
    let zero = seen.values().map(|s| s.1).min().unwrap_or(0);
    let channels = channels
        .iter()
        .map(|(id, c)| {
            let (n, first, last) = match seen.get(id) {
                Some(&(n, first, last)) => (n, Some(first), Some(last)),
                None => (0, None, None),
            };
            info(c, &schemas, n, first, last, zero)
        })
        .collect();
    Ok(RecordingInfo {
        metadata,
        channels,
        chunks: records.chunks(),
        indexed: false,
    })
}
