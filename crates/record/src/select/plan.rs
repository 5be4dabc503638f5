//! The indexed route of [`super::read_selected`]: which chunks hold the chosen channels'
//! messages in the window, found from the summary's chunk indexes and, at the window's edges,
//! the channels' own message indexes; those chunks decompressed by mcap's indexed reader, and
//! the chosen channels' messages among them decoded into columns.
//!
//! A block message is stamped with its first sample, so the samples at the start of the
//! window may be in the channel's last message stamped before it: that message's chunk is read
//! too (a JSON message holds one sample, at its stamp, and needs no such reach back).

use super::decompress::BoundedZstd;
use super::summary::{self, Index, read_at};
use super::{Route, Selected};
use crate::columns::{self, ChannelData, Reading, RecordingColumns};
use crate::error::ReadError;
use crate::selection::Picked;
use crate::types::SessionMetadata;
use crate::walk::{MAX_RECORD_BYTES, Message, StreamLimits};
use mcap::records::ChunkIndex;
use mcap::sans_io::indexed_reader::{
    IndexedReadEvent, IndexedReader, IndexedReaderOptions, ReadOrder,
};
use std::collections::{BTreeMap, BTreeSet};
use std::io::{Read, Seek};

/// How one attempt at the indexed route ended.
enum Outcome {
    /// Read.
    Read(Selected),
    /// A message's stamp disagrees with its first sample by another offset than the one
    /// assumed: the offset it shows, ns.
    Offset(u64),
    /// The file is not as the indexed route needs it (a channel's messages out of time
    /// order): read it front to back.
    Linear,
}

/// `picked` of the recording read by `input` through its summary, or `None` when it has no
/// usable one (then the caller reads it front to back).
pub(super) fn read_indexed<R: Read + Seek>(
    input: &mut R,
    limits: StreamLimits,
    picked: &Picked,
) -> Result<Option<Selected>, ReadError> {
    let Some(index) = summary::read_index(input)? else {
        return Ok(None);
    };
    let decodable = index
        .chunks
        .iter()
        .all(|c| matches!(c.compression.as_str(), "" | "zstd"));
    if !index.indexes_messages() || !decodable {
        return Ok(None);
    }
    let Some(metadata) = summary::metadata(input, &index, SessionMetadata::NAME)? else {
        return Ok(None);
    };
    let readable: BTreeSet<String> = index
        .channels
        .values()
        .filter(|c| columns::readable_channel(c))
        .map(|c| c.topic.clone())
        .collect();
    picked.missing(&readable)?;
    let mut offset_ns = index.first_stamp_ns().unwrap_or(0);
    let mut chunks_read = 0;
    // The offset from the earliest stamp, and once more with the one a message shows.
    for _ in 0..2 {
        let attempt = Attempt {
            index: &index,
            limits,
            picked,
            offset_ns,
        };
        match attempt.read(input, &metadata, &mut chunks_read)? {
            Outcome::Read(selected) => return Ok(Some(selected)),
            Outcome::Offset(shown) => offset_ns = shown,
            Outcome::Linear => break,
        }
    }
    Ok(None)
}

/// One reading of the selection through the summary, with an assumed offset between the
/// messages' log times and the session time.
struct Attempt<'a> {
    index: &'a Index,
    limits: StreamLimits,
    picked: &'a Picked,
    /// Log time of session time 0, ns.
    offset_ns: u64,
}

impl Attempt<'_> {
    /// Reads the selection, counting the chunks decompressed into `chunks_read`.
    fn read<R: Read + Seek>(
        &self,
        input: &mut R,
        metadata: &BTreeMap<String, String>,
        chunks_read: &mut u64,
    ) -> Result<Outcome, ReadError> {
        let mut out = RecordingColumns {
            metadata: metadata.clone(),
            channels: Vec::new(),
        };
        let mut reading: BTreeMap<u16, Reading> = BTreeMap::new();
        for c in self.index.channels.values() {
            if columns::readable_channel(c)
                && self.picked.wants(&c.topic)
                && let Some(r) = columns::channel(&mut out, c, &self.index.schemas)?
            {
                reading.insert(c.id, r);
            }
        }
        let (from, chunks) = self.chunks(input, &reading, &out)?;
        let Some(earliest) = from.values().min().copied() else {
            return Ok(Outcome::Read(self.selected(out, *chunks_read)));
        };
        for chunk in &chunks {
            if chunk.uncompressed_size > self.limits.max_chunk_bytes {
                return Err(ReadError::TooLarge {
                    what: format!(
                        "the uncompressed data of the chunk at byte {}",
                        chunk.chunk_start_offset
                    ),
                    claimed_bytes: chunk.uncompressed_size,
                    limit_bytes: self.limits.max_chunk_bytes,
                });
            }
        }
        let summary = mcap::Summary {
            chunk_indexes: chunks,
            ..Default::default()
        };
        let mut options = IndexedReaderOptions::new()
            .with_order(ReadOrder::File)
            .with_record_length_limit(MAX_RECORD_BYTES);
        let window = &self.picked.window;
        if !window.is_all() {
            options = options
                .starting_at(earliest)
                .ending_before(self.log_ns(window.ns().1));
        }
        let mut reader = IndexedReader::new_with_options(&summary, options)?;
        reader.add_decompressor(BoundedZstd::default())?;
        let mut buf = Vec::new();
        let mut last_stamp: BTreeMap<u16, u64> = BTreeMap::new();
        while let Some(event) = reader.next_event() {
            let (header, data) = match event? {
                IndexedReadEvent::ReadChunkRequest { offset, length } => {
                    read_at(input, offset, length, &mut buf)?;
                    *chunks_read += 1;
                    reader.insert_chunk_record_data(offset, &buf)?;
                    continue;
                }
                IndexedReadEvent::Message { header, data } => (header, data),
            };
            let id = header.channel_id;
            match from.get(&id) {
                Some(&t) if header.log_time >= t => {}
                _ => continue,
            }
            if last_stamp.insert(id, header.log_time) > Some(header.log_time) {
                return Ok(Outcome::Linear);
            }
            let m = Message { header, data };
            let first = columns::message(
                &mut out,
                &reading,
                &m,
                self.limits.max_message_bytes,
                window,
            )?;
            if let Some(first_ns) = first
                && self.offset_ns.checked_add(first_ns) != Some(header.log_time)
            {
                return Ok(Outcome::Offset(header.log_time.wrapping_sub(first_ns)));
            }
        }
        Ok(Outcome::Read(self.selected(out, *chunks_read)))
    }

    /// The result, `chunks_read` chunks decompressed.
    fn selected(&self, columns: RecordingColumns, chunks_read: u64) -> Selected {
        Selected {
            columns,
            route: Route::Indexed,
            chunks_read,
            chunks_in_file: self.index.chunks.len() as u64,
        }
    }

    /// Log time of session time `t_ns`.
    fn log_ns(&self, t_ns: u64) -> u64 {
        self.offset_ns.saturating_add(t_ns)
    }

    /// The log time each read channel's messages are read from, and the chunks to
    /// decompress (in file order): those holding a message of a read channel stamped from
    /// then until the window's end.
    fn chunks<R: Read + Seek>(
        &self,
        input: &mut R,
        reading: &BTreeMap<u16, Reading>,
        out: &RecordingColumns,
    ) -> Result<(BTreeMap<u16, u64>, Vec<ChunkIndex>), ReadError> {
        let window = &self.picked.window;
        let (start_ns, end_ns) = window.ns();
        let (t0, t1) = (self.log_ns(start_ns), self.log_ns(end_ns));
        let mut from = BTreeMap::new();
        let mut chosen = BTreeSet::new();
        for (&id, r) in reading {
            let (Reading::Blocks(_, i) | Reading::Json(i)) = r;
            let blocks = matches!(out.channels[*i].1, ChannelData::Columns(_));
            let since = if window.is_all() {
                0
            } else if blocks {
                latest_stamp(input, self.index, id, t0)?.unwrap_or(t0)
            } else {
                t0
            };
            from.insert(id, since);
            for (k, chunk) in self.index.chunks.iter().enumerate() {
                if !chunk.message_index_offsets.contains_key(&id)
                    || chunk.message_end_time < since
                    || chunk.message_start_time >= t1
                {
                    continue;
                }
                let inside = chunk.message_start_time >= since && chunk.message_end_time < t1;
                if inside
                    || summary::stamps(input, chunk, id)?
                        .iter()
                        .any(|t| (since..t1).contains(t))
                {
                    chosen.insert(k);
                }
            }
        }
        let chunks = chosen
            .into_iter()
            .map(|k| self.index.chunks[k].clone())
            .collect();
        Ok((from, chunks))
    }
}

/// The latest stamp (log time, ns) of channel `id` at or before `t`, reading the message
/// indexes of only the chunks that could hold a later one than found so far (the chunks by
/// their last stamp, latest first).
pub(super) fn latest_stamp<R: Read + Seek>(
    input: &mut R,
    index: &Index,
    id: u16,
    t: u64,
) -> Result<Option<u64>, ReadError> {
    let mut chunks: Vec<&ChunkIndex> = index
        .chunks
        .iter()
        .filter(|c| c.message_index_offsets.contains_key(&id) && c.message_start_time <= t)
        .collect();
    chunks.sort_by_key(|c| std::cmp::Reverse(c.message_end_time));
    let mut best = None;
    for chunk in chunks {
        if best.is_some_and(|b| chunk.message_end_time.min(t) <= b) {
            break;
        }
        let found = summary::stamps(input, chunk, id)?
            .into_iter()
            .filter(|&s| s <= t)
            .max();
        best = best.max(found);
    }
    Ok(best)
}

/// The earliest stamp (log time, ns) of channel `id`, reading the message indexes of only
/// the chunks that could hold an earlier one than found so far.
pub(super) fn earliest_stamp<R: Read + Seek>(
    input: &mut R,
    index: &Index,
    id: u16,
) -> Result<Option<u64>, ReadError> {
    let mut chunks: Vec<&ChunkIndex> = index
        .chunks
        .iter()
        .filter(|c| c.message_index_offsets.contains_key(&id))
        .collect();
    chunks.sort_by_key(|c| c.message_start_time);
    let mut best: Option<u64> = None;
    for chunk in chunks {
        if best.is_some_and(|b| chunk.message_start_time >= b) {
            break;
        }
        let found = summary::stamps(input, chunk, id)?.into_iter().min();
        best = match (best, found) {
            (Some(b), Some(f)) => Some(b.min(f)),
            (b, f) => b.or(f),
        };
    }
    Ok(best)
}
