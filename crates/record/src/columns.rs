//! A recording as columns, one per field of each channel, read front to back in bounded
//! memory: what the Python package's `telerehab.session.read` returns as numpy arrays.
//!
//! The file is read once through the streaming reader of [`super::stream`] (the same limits on
//! every record, chunk and message), so the memory held is the columns returned, plus one
//! chunk. A high-rate channel's blocks ([`super::blocks`]) are decoded straight into its
//! columns, as the file declares them (another version's recording reads as well): floats
//! as `f64` (NaN for an optional field left out), integers as `u64` (every integer the
//! station records is unsigned), flags as `bool`, enum labels as codes into their distinct
//! labels; the stamp `t_ns` becomes `t_s` (s, `t_ns · 1e-9` as [`super::Stamped`] has it). A
//! low-rate JSON channel's messages are kept as they are (a few a second at most). Other
//! channels (the Foxglove scene, topics of other tools) are skipped unparsed.

use super::blocks::{self, BlockError, ColumnValues, Kind, Layout};
use super::error::ReadError;
use super::selection::{Picked, Selection, Window};
use super::stream::SchemaTable;
use super::walk::{Message, Rec, Records, StreamLimits};
use mcap::records::Record;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::io::Read;
use std::path::Path;

/// The values of one column.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// Floats (and `t_s`).
    F64(Vec<f64>),
    /// Unsigned integers.
    U64(Vec<u64>),
    /// Flags.
    Bool(Vec<bool>),
    /// Enum labels: one code a value, indexing `labels`.
    Text {
        /// The value's label, as an index into `labels`.
        codes: Vec<u32>,
        /// The distinct labels, in order of first appearance.
        labels: Vec<String>,
    },
}

/// One column of a high-rate channel.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnData {
    /// The field's name (`t_s` for the stamp `t_ns`).
    pub name: String,
    /// Elements per sample (an array field's length): the values are sample-major, elements
    /// interleaved (a row-major samples × elements array).
    pub elements: usize,
    /// What the field is, unit included, as the file describes it.
    pub description: String,
    /// The values.
    pub values: Values,
    /// Text labels already seen, to their code.
    codes: HashMap<String, u32>,
}

/// A channel's columns, or its messages.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelData {
    /// A high-rate channel: its columns in the file's order, stamps first.
    Columns(Vec<ColumnData>),
    /// A low-rate channel: its JSON messages as recorded, and its JSON schema.
    Json {
        /// The channel's schema (JSON Schema; empty if the file has none).
        schema: Vec<u8>,
        /// The messages, in file order.
        messages: Vec<Vec<u8>>,
    },
}

/// A recording's channels and session metadata.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RecordingColumns {
    /// The `session` metadata record as it is in the file (name → value).
    pub metadata: BTreeMap<String, String>,
    /// Each channel read, by topic, in order of first appearance.
    pub channels: Vec<(String, ChannelData)>,
}

impl RecordingColumns {
    /// The channel on `topic`.
    pub fn channel(&self, topic: &str) -> Option<&ChannelData> {
        self.channels
            .iter()
            .find(|(t, _)| t == topic)
            .map(|(_, c)| c)
    }
}

impl ColumnData {
    fn new(c: &blocks::Column) -> Self {
        let (name, description, values) = match (c.kind, c.name.as_str()) {
            (Kind::Int, "t_ns") => ("t_s", "Session time, s.", Values::F64(Vec::new())),
            (Kind::Float, _) => (&*c.name, &*c.description, Values::F64(Vec::new())),
            (Kind::Int, _) => (&*c.name, &*c.description, Values::U64(Vec::new())),
            (Kind::Bool, _) => (&*c.name, &*c.description, Values::Bool(Vec::new())),
            (Kind::Text, _) => (
                &*c.name,
                &*c.description,
                Values::Text {
                    codes: Vec::new(),
                    labels: Vec::new(),
                },
            ),
        };
        Self {
            name: name.to_owned(),
            elements: c.elements,
            description: description.to_owned(),
            values,
            codes: HashMap::new(),
        }
    }

    /// Appends one block's values of this column (`c` as the file declares it).
    fn extend(&mut self, c: &blocks::Column, values: ColumnValues) {
        let quantum = c.quantum.unwrap_or(1.0);
        match (&mut self.values, values) {
            (Values::F64(out), ColumnValues::Stored(v)) if c.kind == Kind::Int => {
                out.extend(v.into_iter().map(|q| q as u64 as f64 * 1e-9));
            }
            (Values::F64(out), ColumnValues::Stored(v)) => out.extend(
                v.into_iter()
                    .map(|q| blocks::unquantise(q, quantum).unwrap_or(f64::NAN)),
            ),
            (Values::U64(out), ColumnValues::Stored(v)) => {
                out.extend(v.into_iter().map(|q| q as u64));
            }
            (Values::Bool(out), ColumnValues::Bools(v)) => out.extend(v),
            (Values::Text { codes, labels }, ColumnValues::Texts(v)) => {
                for t in v {
                    let code = *self.codes.entry(t).or_insert_with_key(|t| {
                        labels.push(t.clone());
                        u32::try_from(labels.len() - 1).unwrap_or(u32::MAX)
                    });
                    codes.push(code);
                }
            }
            // `decode_columns` gives each kind its own values.
            _ => unreachable!("a column's values match its kind"),
        }
    }
}

/// How one channel id of the file is read.
pub(crate) enum Reading {
    /// Into the block columns of channel `index` of the output.
    Blocks(Box<Layout>, usize),
    /// Its messages kept, in channel `index` of the output.
    Json(usize),
}

/// Reads the recording at `path` into columns ([`read_columns`]).
pub fn read_columns_path(path: &Path, limits: StreamLimits) -> Result<RecordingColumns, ReadError> {
    let file = std::fs::File::open(path).map_err(|source| ReadError::Io {
        path: format!(" {}", path.display()),
        source,
    })?;
    read_columns(std::io::BufReader::new(file), limits)
}

/// Reads a recording front to back into columns, within `limits` (the module's documentation
/// says what is read and how). Fails on a file without its `session` metadata record, and
/// where the streaming reader fails ([`super::TickStream`]): a file cut short (a killed
/// session's, before `telerehab recover`) among them.
pub fn read_columns(input: impl Read, limits: StreamLimits) -> Result<RecordingColumns, ReadError> {
    let all = Selection::default().checked()?;
    read_picked(input, limits, &all).map(|(columns, _)| columns)
}

/// [`read_columns`] of the channels and window `picked` only (the others skipped unparsed, the
/// samples outside the window dropped); also returns the chunks walked. Fails, after the
/// walk, on a topic asked for that the file has no readable channel of.
pub(crate) fn read_picked(
    input: impl Read,
    limits: StreamLimits,
    picked: &Picked,
) -> Result<(RecordingColumns, u64), ReadError> {
    let mut records = Records::new(input, limits);
    let mut out = RecordingColumns::default();
    let mut schemas = SchemaTable::default();
    let mut reading: BTreeMap<u16, Reading> = BTreeMap::new();
    let mut readable = BTreeSet::new();
    let mut metadata = None;
    let window = &picked.window;
    loop {
        let (record, chunk) = match records.next()? {
            Rec::End => break,
            Rec::Other => continue,
            Rec::Message(m) => {
                message(&mut out, &reading, &m, limits.max_message_bytes, window)?;
                continue;
            }
            Rec::Record(record, chunk) => (record, chunk),
        };
        match record {
            Record::Schema { header, data } => schemas.keep(header, data.into_owned(), chunk)?,
            Record::Channel(c) if readable_channel(&c) => {
                readable.insert(c.topic.clone());
                if picked.wants(&c.topic)
                    && let Some(r) = channel(&mut out, &c, &schemas)?
                {
                    reading.insert(c.id, r);
                }
            }
            Record::Metadata(m) if m.name == record_name() => metadata = Some(m.metadata),
            _ => {}
        }
    }
    out.metadata = metadata.ok_or(ReadError::NoMetadata)?;
    picked.missing(&readable)?;
    Ok((out, records.chunks()))
}

/// The name of the session metadata record.
fn record_name() -> &'static str {
    super::SessionMetadata::NAME
}

/// Whether channel `c` is one this reader reads: blocks of columns, or JSON.
pub(crate) fn readable_channel(c: &mcap::records::Channel) -> bool {
    is_blocks(c) || c.message_encoding == super::channels::MESSAGE_ENCODING
}

/// Whether channel `c` holds blocks of columns ([`super::blocks`]).
fn is_blocks(c: &mcap::records::Channel) -> bool {
    c.message_encoding == blocks::ENCODING && c.metadata.contains_key(blocks::COLUMNS_KEY)
}

/// How channel `c` is read (`None`: skipped), its output channel made on first sight.
pub(crate) fn channel(
    out: &mut RecordingColumns,
    c: &mcap::records::Channel,
    schemas: &SchemaTable,
) -> Result<Option<Reading>, ReadError> {
    let topic: &'static str = super::Channel::from_topic(&c.topic).map_or("", |ch| ch.topic());
    let (name, schema) = schemas
        .by_id()
        .get(&c.schema_id)
        .cloned()
        .unwrap_or_default();
    let encoding = schemas.encoding(c.schema_id);
    let index = out.channels.iter().position(|(t, _)| *t == c.topic);
    let layout_error = |source| ReadError::Block {
        topic,
        index: usize::MAX,
        source,
    };
    if is_blocks(c) {
        let layout = Layout::from_file(&name, &schema, &c.metadata).map_err(layout_error)?;
        let columns: Vec<ColumnData> = layout.columns().iter().map(ColumnData::new).collect();
        let index = match index {
            None => {
                out.channels
                    .push((c.topic.clone(), ChannelData::Columns(columns)));
                out.channels.len() - 1
            }
            Some(i) => match &out.channels[i].1 {
                ChannelData::Columns(had) if same_columns(had, &columns) => i,
                _ => {
                    let why = format!("channel {} is declared twice, differently", c.topic);
                    return Err(layout_error(BlockError::Layout(why)));
                }
            },
        };
        return Ok(Some(Reading::Blocks(Box::new(layout), index)));
    }
    if c.message_encoding != super::channels::MESSAGE_ENCODING {
        return Ok(None);
    }
    let schema = if encoding == super::channels::SCHEMA_ENCODING {
        schema
    } else {
        Vec::new()
    };
    let index = index.unwrap_or_else(|| {
        out.channels.push((
            c.topic.clone(),
            ChannelData::Json {
                schema,
                messages: Vec::new(),
            },
        ));
        out.channels.len() - 1
    });
    Ok(match out.channels[index].1 {
        ChannelData::Json { .. } => Some(Reading::Json(index)),
        ChannelData::Columns(_) => None,
    })
}

/// Whether two declarations of a channel's columns are the same.
fn same_columns(a: &[ColumnData], b: &[ColumnData]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(a, b)| {
            a.name == b.name
                && a.elements == b.elements
                && std::mem::discriminant(&a.values) == std::mem::discriminant(&b.values)
        })
}

/// Reads one message record (`m`) into its channel's columns or messages, keeping the samples
/// in `window`; returns the session time of the message's first sample, ns, when it was read
/// under a window (`None` otherwise, and for a channel not read).
pub(crate) fn message(
    out: &mut RecordingColumns,
    reading: &BTreeMap<u16, Reading>,
    m: &Message<'_>,
    max_message_bytes: usize,
    window: &Window,
) -> Result<Option<u64>, ReadError> {
    let Some(r) = reading.get(&m.header.channel_id) else {
        return Ok(None);
    };
    let index = match r {
        Reading::Blocks(_, i) | Reading::Json(i) => *i,
    };
    let (topic, channel) = &mut out.channels[index];
    let body = m.data_within(topic, max_message_bytes)?;
    let ours = super::Channel::from_topic(topic).map_or("", |c| c.topic());
    match (r, channel) {
        (Reading::Json(_), ChannelData::Json { messages, .. }) => {
            if window.is_all() {
                messages.push(body.to_vec());
                return Ok(None);
            }
            let stamp: JsonStamp =
                serde_json::from_slice(body).map_err(|source| ReadError::Decode {
                    topic: ours,
                    index: messages.len(),
                    source,
                })?;
            if window.holds(stamp.t_s) {
                messages.push(body.to_vec());
            }
            Ok(Some((stamp.t_s * 1e9).round() as u64))
        }
        (Reading::Blocks(layout, _), ChannelData::Columns(columns)) => {
            let first = match columns.first().map(|c| &c.values) {
                Some(Values::U64(v)) => v.len(),
                _ => 0,
            };
            let block_error = |source| ReadError::Block {
                topic: ours,
                index: first,
                source,
            };
            if window.is_all() {
                let mut at = columns.iter_mut();
                layout
                    .decode_columns(body, |c, values| {
                        if let Some(col) = at.next() {
                            col.extend(c, values);
                        }
                        Ok(())
                    })
                    .map_err(block_error)?;
                return Ok(None);
            }
            let mut decoded = Vec::with_capacity(columns.len());
            layout
                .decode_columns(body, |_, values| {
                    decoded.push(values);
                    Ok(())
                })
                .map_err(block_error)?;
            let described = layout.columns();
            let stamps = described.iter().zip(&decoded).find_map(|(c, v)| match v {
                ColumnValues::Stored(v) if c.kind == Kind::Int && c.name == "t_ns" => Some(v),
                _ => None,
            });
            let Some(stamps) = stamps else {
                let why = BlockError::Decode("a block without its t_ns column".into());
                return Err(block_error(why));
            };
            let first_ns = stamps.first().map(|&q| q as u64);
            let keep: Vec<bool> = stamps
                .iter()
                .map(|&q| window.holds(q as u64 as f64 * 1e-9))
                .collect();
            let all = keep.iter().all(|&k| k);
            if all || keep.iter().any(|&k| k) {
                for ((col, c), values) in columns.iter_mut().zip(described).zip(decoded) {
                    let values = if all {
                        values
                    } else {
                        keep_rows(values, &keep, c.elements)
                    };
                    col.extend(c, values);
                }
            }
            Ok(first_ns)
        }
        _ => Ok(None),
    }
}

/// The stamp of a JSON message ([`super::Stamped`]): its session time, s.
#[derive(serde::Deserialize)]
struct JsonStamp {
    t_s: f64,
}

/// The values of the rows `keep` marks (`elements` values a row).
fn keep_rows(values: ColumnValues, keep: &[bool], elements: usize) -> ColumnValues {
    fn kept<T>(v: Vec<T>, keep: &[bool], elements: usize) -> Vec<T> {
        let per_row = elements.max(1);
        v.into_iter()
            .enumerate()
            .filter(|(i, _)| keep[i / per_row])
            .map(|(_, x)| x)
            .collect()
    }
    match values {
        ColumnValues::Stored(v) => ColumnValues::Stored(kept(v, keep, elements)),
        ColumnValues::Bools(v) => ColumnValues::Bools(kept(v, keep, elements)),
        ColumnValues::Texts(v) => ColumnValues::Texts(kept(v, keep, elements)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{RecordWriter, Recording, SessionMetadata, TickRecord, VehicleSample};
    use std::io::Cursor;

    /// `n` ticks at 1 kHz, the car on the road from tick 100 to 300, a score every 100.
    fn recording(n: u64) -> Vec<u8> {
        let meta = SessionMetadata {
            seed: 9,
            loop_rate_hz: 1000.0,
            ..Default::default()
        };
        let mut w = RecordWriter::new(Cursor::new(Vec::new()), 0, &meta).unwrap();
        for tick in 0..n {
            let x = (tick as f64 * 0.01).sin();
            let mut rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                ..Default::default()
            };
            rec.wheel.angle_rad = x;
            rec.timing.lateness_ns = tick % 7;
            if (100..300).contains(&tick) {
                rec.vehicle = Some(VehicleSample {
                    lateral_m: x,
                    ..Default::default()
                });
            }
            w.write_tick(&rec, tick % 100 == 0).unwrap();
            if tick % 250 == 249 {
                w.flush().unwrap();
            }
        }
        w.finish().unwrap().into_inner()
    }

    fn column<'a>(r: &'a RecordingColumns, topic: &str, name: &str) -> &'a Values {
        match r.channel(topic) {
            Some(ChannelData::Columns(cols)) => {
                &cols.iter().find(|c| c.name == name).expect(name).values
            }
            other => panic!("{topic}: {other:?}"),
        }
    }

    #[test]
    fn the_columns_hold_what_the_whole_file_reader_reads_sample_by_sample() {
        let bytes = recording(1000);
        let whole = Recording::from_bytes(&bytes).unwrap();
        let cols = read_columns(Cursor::new(&bytes), StreamLimits::default()).unwrap();
        assert_eq!(cols.metadata["seed"], "9");
        let ticks: Vec<u64> = whole.wheel.iter().map(|s| s.tick).collect();
        assert_eq!(column(&cols, "/wheel", "tick"), &Values::U64(ticks));
        let t_s: Vec<f64> = whole.wheel.iter().map(|s| s.t_s).collect();
        assert_eq!(column(&cols, "/wheel", "t_s"), &Values::F64(t_s));
        let angle: Vec<f64> = whole.wheel.iter().map(|s| s.data.angle_rad).collect();
        assert_eq!(column(&cols, "/wheel", "angle_rad"), &Values::F64(angle));
        let lateral: Vec<f64> = whole.vehicle.iter().map(|s| s.data.lateral_m).collect();
        assert_eq!(lateral.len(), 200);
        assert_eq!(
            column(&cols, "/vehicle", "lateral_m"),
            &Values::F64(lateral)
        );
        let late: Vec<u64> = whole.timing.iter().map(|s| s.data.lateness_ns).collect();
        assert_eq!(column(&cols, "/timing", "lateness_ns"), &Values::U64(late));
        match cols.channel("/score") {
            Some(ChannelData::Json { schema, messages }) => {
                assert_eq!(messages.len(), whole.score.len());
                assert!(String::from_utf8_lossy(schema).contains("properties"));
            }
            other => panic!("/score: {other:?}"),
        }
    }

    #[test]
    fn a_file_without_session_metadata_or_cut_short_is_refused() {
        let mut w = mcap::WriteOptions::new()
            .create(Cursor::new(Vec::new()))
            .unwrap();
        w.finish().unwrap();
        let empty = w.into_inner().into_inner();
        let e = read_columns(Cursor::new(empty), StreamLimits::default()).unwrap_err();
        assert!(matches!(e, ReadError::NoMetadata), "{e}");
        // Cut within its data (its first quarter: schemas, channels and chunks), and between
        // records, as a killed session leaves it: before its Data End record (opcode 0x0f, 4
        // bytes long).
        let whole = recording(2000);
        let data_end = [0x0f, 4, 0, 0, 0, 0, 0, 0, 0];
        let at = whole.windows(9).rposition(|w| w == data_end).unwrap();
        for cut in [&whole[..whole.len() / 4], &whole[..at]] {
            let e = read_columns(Cursor::new(cut), StreamLimits::default());
            assert!(matches!(e, Err(ReadError::Mcap(_))), "{e:?}");
        }
    }
}
