//! Two recordings compared sample by sample, channel by channel, read side by side in bounded
//! memory whatever their length (`telerehab replay` compares a session with its re-run so).
//!
//! Each file is read front to back as [`super::TickStream`] reads it (chunk by chunk, within
//! [`StreamLimits`]); the file behind (by the tick of the last sample read) is read next, and
//! each channel's samples are compared as soon as both files have given them. What is held is
//! the samples one file has given and the other not yet: a second or so of each channel for the
//! station's recordings (a channel's block is written every 100 samples or every second), at
//! most [`MAX_PENDING_SAMPLES`] a channel.
//!
//! Samples compare as [`super::recorded_rows`] gives them (a NaN or infinity as null, the same
//! fields with the same values): cell by cell when both files lay a channel out alike, which is
//! the same and faster, through their JSON rows otherwise (a column only the second file has,
//! a field newer than the first file, is not compared).

use super::blocks::{Cell, Layout};
use super::channels::Channel;
use super::error::ReadError;
use super::reader::{Decoder, Row};
use super::stream::SchemaTable;
use super::walk::{Rec, Records, StreamLimits};
use mcap::records::Record;
use std::collections::{BTreeMap, VecDeque};
use std::io::Read;
use std::path::Path;
use std::sync::Arc;

/// Channels in all.
const N: usize = Channel::ALL.len();

/// Samples of one channel held for one file, at most, while the other file has not given
/// them: past it the other file's channel is taken as lagging ([`SampleDifference::Lag`]), or,
/// when the other file has ended, as shorter.
pub const MAX_PENDING_SAMPLES: usize = 50_000;

/// Optional fields added to JSON channels since recordings were first written (`/metrics`'
/// each exercise's results and end reason): absent from the first recording compared, the
/// second's are not compared.
pub const ADDED_JSON_FIELDS: &[&str] = &["exercises", "end_reason"];

/// One recorded sample as read.
#[derive(Clone, Debug)]
pub enum Sample {
    /// The cells of one sample of a block message, with the layout that decoded them.
    Cells(Arc<Layout>, Vec<Cell>),
    /// A JSON message's fields.
    Row(Row),
}

impl Sample {
    /// The sample as [`super::recorded_rows`] gives it.
    pub fn row(&self) -> Row {
        match self {
            Self::Cells(layout, cells) => layout.row_of(cells),
            Self::Row(row) => row.clone(),
        }
    }

    /// Its tick.
    pub fn tick(&self) -> Option<u64> {
        match self {
            Self::Cells(_, cells) => match cells.first() {
                Some(Cell::Int(t)) => Some(*t),
                _ => None,
            },
            Self::Row(row) => row.get("tick").and_then(serde_json::Value::as_u64),
        }
    }

    /// One field of the sample (not its stamps), as its row holds it (`None`: absent).
    pub fn field(&self, name: &str) -> Option<serde_json::Value> {
        match self {
            Self::Row(row) => row.get(name).cloned(),
            Self::Cells(layout, cells) => {
                let mut at = 0;
                for c in layout.columns() {
                    if c.name == name && c.elements == 1 {
                        return match cells.get(at) {
                            None | Some(Cell::Absent) => None,
                            Some(cell) => Some(cell.json()),
                        };
                    }
                    at += c.elements;
                }
                None
            }
        }
    }
}

/// Where two recordings first part on one channel.
#[derive(Clone, Debug, PartialEq)]
pub enum SampleDifference {
    /// Sample `index` differs: each file's sample.
    Values {
        /// The sample's position on its channel, from 0.
        index: usize,
        /// The first file's sample.
        first: Row,
        /// The second file's sample.
        second: Row,
    },
    /// From sample `index` on, one file gave more than [`MAX_PENDING_SAMPLES`] samples of the
    /// channel that the other, still going, did not.
    Lag {
        /// The first sample not compared.
        index: usize,
    },
}

/// One channel of two recordings compared.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChannelComparison {
    /// Samples of the channel in the first and the second file.
    pub samples: [usize; 2],
    /// The first difference in their values; `None` if every sample both hold is the same
    /// (the counts may still differ).
    pub difference: Option<SampleDifference>,
}

/// A file of the two that could not be read.
#[derive(Debug)]
pub struct CompareError {
    /// The second file (else the first).
    pub second: bool,
    /// Why.
    pub source: ReadError,
}

impl std::fmt::Display for CompareError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let which = if self.second { "second" } else { "first" };
        write!(f, "the {which} recording: {}", self.source)
    }
}

impl std::error::Error for CompareError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}

/// Compares `channels` of the recordings at `first` and `second` ([`compare`]).
pub fn compare_files(
    first: &Path,
    second: &Path,
    channels: &[Channel],
    observed: &[Channel],
    observe: impl FnMut(Channel, &Sample),
) -> Result<BTreeMap<Channel, ChannelComparison>, CompareError> {
    let second = open_file(second).map_err(|source| CompareError {
        second: true,
        source,
    })?;
    compare_with(first, second, channels, observed, observe)
}

/// Compares `channels` of the recording at `first` with a second one read from `second` as
/// it comes (a file still being written, through a reader that waits for its bytes) —
/// [`compare`].
pub fn compare_with(
    first: &Path,
    second: impl Read,
    channels: &[Channel],
    observed: &[Channel],
    observe: impl FnMut(Channel, &Sample),
) -> Result<BTreeMap<Channel, ChannelComparison>, CompareError> {
    let first = open_file(first).map_err(|source| CompareError {
        second: false,
        source,
    })?;
    compare(
        first,
        second,
        StreamLimits::default(),
        channels,
        observed,
        observe,
    )
}

/// A recording's file, buffered for reading front to back.
fn open_file(path: &Path) -> Result<impl Read + use<>, ReadError> {
    std::fs::File::open(path)
        .map(|f| std::io::BufReader::with_capacity(256 << 10, f))
        .map_err(|source| ReadError::Io {
            path: format!(" {}", path.display()),
            source,
        })
}

/// Compares `channels` of two recordings read side by side, every sample of the first file
/// on the `observed` ones (a subset of `channels`) handed to `observe` as it is read; gives
/// each channel's comparison.
///
/// A block message of one file is compared with the other's next message of the channel as
/// bytes first: the same bytes in the same layout are the same samples, and neither is
/// decoded (the writer closes a channel's blocks at the same samples in two runs of one
/// session). Only where the bytes differ (blocks cut elsewhere, or a value that differs) are
/// the two decoded and compared sample by sample, so the first differing sample is still
/// named exactly.
pub fn compare(
    first: impl Read,
    second: impl Read,
    limits: StreamLimits,
    channels: &[Channel],
    observed: &[Channel],
    mut observe: impl FnMut(Channel, &Sample),
) -> Result<BTreeMap<Channel, ChannelComparison>, CompareError> {
    let mut wanted = [false; N];
    for c in channels {
        wanted[*c as usize] = true;
    }
    let mut watched = [false; N];
    for c in observed {
        watched[*c as usize] = true;
    }
    let mut a = Side::new(first, limits, wanted, watched);
    let mut b = Side::new(second, limits, wanted, [false; N]);
    let mut cmp = Comparer {
        keep: wanted,
        matched: [0; N],
        difference: std::array::from_fn(|_| None),
        layouts: Vec::new(),
    };
    loop {
        let read_first = match (a.ended, b.ended) {
            (true, true) => break,
            (false, true) => true,
            (true, false) => false,
            (false, false) => a.progress <= b.progress,
        };
        if read_first {
            a.pump(&cmp.keep, &mut observe)
                .map_err(|source| CompareError {
                    second: false,
                    source,
                })?;
        } else {
            b.pump(&cmp.keep, &mut |_, _| {})
                .map_err(|source| CompareError {
                    second: true,
                    source,
                })?;
        }
        cmp.settle(&mut a, &mut b)?;
    }
    let mut out = BTreeMap::new();
    for c in channels {
        let i = *c as usize;
        out.insert(
            *c,
            ChannelComparison {
                samples: [a.counts[i], b.counts[i]],
                difference: cmp.difference[i].take(),
            },
        );
    }
    Ok(out)
}

/// The comparison so far.
struct Comparer {
    /// Channels still compared (not yet found different).
    keep: [bool; N],
    /// Samples found the same so far, per channel.
    matched: [usize; N],
    /// The first difference found, per channel.
    difference: [Option<SampleDifference>; N],
    /// Pairs of layouts (by address) and whether they lay samples out alike.
    layouts: Vec<(usize, usize, bool)>,
}

impl Comparer {
    /// Compares what both files have given; stops holding what can no longer be compared.
    fn settle<A: Read, B: Read>(
        &mut self,
        a: &mut Side<A>,
        b: &mut Side<B>,
    ) -> Result<(), CompareError> {
        for c in 0..N {
            if !self.keep[c] {
                continue;
            }
            while let (Some(x), Some(y)) = (a.pending[c].front(), b.pending[c].front()) {
                match (x, y) {
                    (Held::Block(lx, bx, nx), Held::Block(ly, by, ny))
                        if nx == ny && bx == by && self.alike(lx, ly) =>
                    {
                        let n = *nx;
                        a.pop(c);
                        b.pop(c);
                        self.matched[c] += n;
                        continue;
                    }
                    (Held::Block(..), _) => {
                        a.unpack_front(c).map_err(|source| CompareError {
                            second: false,
                            source,
                        })?;
                        continue;
                    }
                    (_, Held::Block(..)) => {
                        b.unpack_front(c).map_err(|source| CompareError {
                            second: true,
                            source,
                        })?;
                        continue;
                    }
                    (Held::Sample(x), Held::Sample(y)) => {
                        if !self.same(x, y) {
                            self.difference[c] = Some(SampleDifference::Values {
                                index: self.matched[c],
                                first: x.row(),
                                second: y.row(),
                            });
                            self.drop_channel(c, a, b);
                            break;
                        }
                    }
                }
                a.pop(c);
                b.pop(c);
                self.matched[c] += 1;
            }
            let (held_a, held_b) = (a.held[c], b.held[c]);
            if (held_a > 0 && b.ended) || (held_b > 0 && a.ended) {
                // Nothing more comes from the file that ended: the counts tell the rest.
                self.drop_channel(c, a, b);
            } else if held_a.max(held_b) > MAX_PENDING_SAMPLES {
                self.difference[c] = Some(SampleDifference::Lag {
                    index: self.matched[c],
                });
                self.drop_channel(c, a, b);
            }
        }
        Ok(())
    }

    /// Channel `c` is decided: its samples are only counted from now on.
    fn drop_channel<A, B>(&mut self, c: usize, a: &mut Side<A>, b: &mut Side<B>) {
        self.keep[c] = false;
        a.pending[c] = VecDeque::new();
        b.pending[c] = VecDeque::new();
        a.held[c] = 0;
        b.held[c] = 0;
    }
    /// Whether two samples are the same as their rows would be.
    fn same(&mut self, x: &Sample, y: &Sample) -> bool {
        match (x, y) {
            (Sample::Cells(lx, cx), Sample::Cells(ly, cy)) if self.alike(lx, ly) => {
                same_cells(cx, cy)
            }
            (Sample::Cells(lx, _), Sample::Cells(..)) => {
                // A column of the second file that the first file's layout does not have (a
                // field newer than the first file, such as the pedals on `/raw/wheel`) has
                // nothing to be compared with.
                let mut second = y.row();
                second.retain(|k, _| k == "t_s" || lx.column_names().any(|n| n == k));
                x.row() == second
            }
            _ => {
                let (x, mut y) = (x.row(), y.row());
                // Fields a later version added to a JSON channel: a replay of an older
                // recording writes them, which is no difference.
                for key in ADDED_JSON_FIELDS {
                    if !x.contains_key(*key) {
                        y.remove(*key);
                    }
                }
                // Measures a later version added (`/metrics`' named measures): a replay of an
                // older recording names them too, which is no difference; every measure both
                // name is still compared.
                if let (
                    Some(serde_json::Value::Object(named)),
                    Some(serde_json::Value::Object(replayed)),
                ) = (x.get("measures"), y.get_mut("measures"))
                {
                    replayed.retain(|name, _| named.contains_key(name));
                }
                x == y
            }
        }
    }

    /// Whether two layouts lay samples out alike (remembered by address).
    fn alike(&mut self, x: &Arc<Layout>, y: &Arc<Layout>) -> bool {
        let key = (Arc::as_ptr(x) as usize, Arc::as_ptr(y) as usize);
        if let Some(&(_, _, alike)) = self.layouts.iter().find(|l| (l.0, l.1) == key) {
            return alike;
        }
        let alike = x.same_cells_as(y);
        self.layouts.push((key.0, key.1, alike));
        alike
    }
}

/// Whether two samples' cells give the same row: a NaN or infinity is null, so any two are
/// the same.
fn same_cells(x: &[Cell], y: &[Cell]) -> bool {
    x.len() == y.len()
        && x.iter().zip(y).all(|pair| match pair {
            (Cell::Float(x), Cell::Float(y)) => x == y || (!x.is_finite() && !y.is_finite()),
            (x, y) => x == y,
        })
}

/// What one file has given of a channel and the other not yet.
enum Held {
    /// A block message not decoded: its layout, its bytes and its number of samples.
    Block(Arc<Layout>, Vec<u8>, usize),
    /// One sample, decoded (a JSON message, or a block's sample once its bytes differed).
    Sample(Sample),
}

/// One file being read.
struct Side<R> {
    records: Records<R>,
    wanted: [bool; N],
    /// Channels whose samples are handed to the observer as they are read.
    watched: [bool; N],
    schemas: SchemaTable,
    /// Our channels by id: each one's layout (`None`: JSON messages).
    channels: BTreeMap<u16, (Channel, Option<Arc<Layout>>)>,
    /// What was read and not yet compared, per channel.
    pending: [VecDeque<Held>; N],
    /// Samples in `pending`, per channel.
    held: [usize; N],
    /// Samples read, per channel.
    counts: [usize; N],
    /// The tick of the last sample read.
    progress: u64,
    ended: bool,
}

impl<R: Read> Side<R> {
    fn new(input: R, limits: StreamLimits, wanted: [bool; N], watched: [bool; N]) -> Self {
        Self {
            records: Records::new(input, limits),
            wanted,
            watched,
            schemas: SchemaTable::default(),
            channels: BTreeMap::new(),
            pending: std::array::from_fn(|_| VecDeque::new()),
            held: [0; N],
            counts: [0; N],
            progress: 0,
            ended: false,
        }
    }

    /// Drops the first item held of channel `c`.
    fn pop(&mut self, c: usize) {
        match self.pending[c].pop_front() {
            Some(Held::Block(_, _, n)) => self.held[c] -= n,
            Some(Held::Sample(_)) => self.held[c] -= 1,
            None => {}
        }
    }

    /// Replaces the block first held of channel `c` with its samples, decoded.
    fn unpack_front(&mut self, c: usize) -> Result<(), ReadError> {
        let Some(Held::Block(layout, bytes, n)) = self.pending[c].pop_front() else {
            return Ok(());
        };
        let topic = Channel::ALL[c].topic();
        let index = self.counts[c] - self.held[c];
        let cells = layout
            .decode_cells(&bytes)
            .map_err(|source| ReadError::Block {
                topic,
                index,
                source,
            })?;
        if cells.len() != n {
            return Err(ReadError::Block {
                topic,
                index,
                source: super::blocks::BlockError::Decode(format!(
                    "{} samples decoded of the {n} its ticks count",
                    cells.len()
                )),
            });
        }
        for cells in cells.into_iter().rev() {
            self.pending[c].push_front(Held::Sample(Sample::Cells(Arc::clone(&layout), cells)));
        }
        Ok(())
    }

    /// Reads one record: a message's samples are counted, handed to `observe` when its
    /// channel is watched and, on the channels still compared (`keep`), held (a block
    /// message whole, undecoded).
    fn pump(
        &mut self,
        keep: &[bool; N],
        observe: &mut dyn FnMut(Channel, &Sample),
    ) -> Result<(), ReadError> {
        let max_message = self.records.limits().max_message_bytes;
        let (record, chunk) = match self.records.next()? {
            Rec::End => {
                self.ended = true;
                return Ok(());
            }
            Rec::Other => return Ok(()),
            Rec::Record(record, chunk) => (record, chunk),
            Rec::Message(m) => {
                let Some((channel, layout)) = self.channels.get(&m.header.channel_id) else {
                    return Ok(());
                };
                let (channel, c) = (*channel, *channel as usize);
                let body = m.data_within(channel.topic(), max_message)?;
                let index = self.counts[c];
                let block_error = |source| ReadError::Block {
                    topic: channel.topic(),
                    index,
                    source,
                };
                match layout {
                    None => {
                        let s = Sample::Row(serde_json::from_slice(body).map_err(|source| {
                            ReadError::Decode {
                                topic: channel.topic(),
                                index,
                                source,
                            }
                        })?);
                        if self.watched[c] {
                            observe(channel, &s);
                        }
                        self.counts[c] += 1;
                        self.progress = self.progress.max(s.tick().unwrap_or(0));
                        if keep[c] {
                            self.pending[c].push_back(Held::Sample(s));
                            self.held[c] += 1;
                        }
                    }
                    Some(layout) => {
                        let (n, last) = layout.stamps(body).map_err(block_error)?;
                        if self.watched[c] {
                            for cells in layout.decode_cells(body).map_err(block_error)? {
                                observe(channel, &Sample::Cells(Arc::clone(layout), cells));
                            }
                        }
                        self.counts[c] += n;
                        self.progress = self.progress.max(last.unwrap_or(0));
                        if keep[c] && n > 0 {
                            self.pending[c].push_back(Held::Block(
                                Arc::clone(layout),
                                body.to_vec(),
                                n,
                            ));
                            self.held[c] += n;
                        }
                    }
                }
                return Ok(());
            }
        };
        match record {
            Record::Schema { header, data } => {
                self.schemas.keep(header, data.into_owned(), chunk)?;
            }
            Record::Channel(c) => {
                if let Some((channel, decoder)) = self.schemas.decoder_of(&c, &self.wanted)? {
                    let layout = match decoder {
                        Decoder::Json => None,
                        Decoder::Blocks(layout, ..) => Some(Arc::from(layout)),
                    };
                    self.channels.insert(c.id, (channel, layout));
                }
            }
            _ => {}
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{RecordWriter, SessionMetadata, TickRecord, recorded_rows};
    use std::io::Cursor;

    /// A recording of `n` ticks at 1 kHz (a score every 100), `change` applied to each tick,
    /// flushed every `flush_every` ticks.
    fn recording(n: u64, flush_every: u64, change: impl Fn(&mut TickRecord)) -> Vec<u8> {
        let meta = SessionMetadata {
            loop_rate_hz: 1000.0,
            ..Default::default()
        };
        let mut w = RecordWriter::new(Cursor::new(Vec::new()), 0, &meta).unwrap();
        for tick in 0..n {
            let mut rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                ..Default::default()
            };
            rec.wheel.angle_rad = (tick as f64 * 1e-3).sin();
            rec.assist.torque_nm = 0.1;
            change(&mut rec);
            w.write_tick(&rec, tick % 100 == 0).unwrap();
            if tick % flush_every == flush_every - 1 {
                w.flush().unwrap();
            }
        }
        w.finish().unwrap().into_inner()
    }

    fn compared(a: &[u8], b: &[u8]) -> BTreeMap<Channel, ChannelComparison> {
        compare(
            a,
            b,
            StreamLimits::default(),
            &[Channel::Wheel, Channel::Score, Channel::Assist],
            &[],
            |_, _| {},
        )
        .unwrap()
    }

    #[test]
    fn two_files_of_one_session_written_in_different_chunks_are_the_same() {
        let a = recording(5000, 1000, |_| {});
        let b = recording(5000, 333, |_| {});
        assert_ne!(a, b);
        for c in compared(&a, &b).values() {
            assert_eq!(c.difference, None);
            assert_eq!(c.samples[0], c.samples[1]);
        }
        assert_eq!(compared(&a, &b)[&Channel::Wheel].samples, [5000, 5000]);
        assert_eq!(compared(&a, &b)[&Channel::Score].samples, [50, 50]);
    }

    #[test]
    fn the_first_differing_sample_is_given_as_recorded_rows_give_it() {
        let a = recording(5000, 1000, |_| {});
        let b = recording(5000, 700, |r| {
            if r.tick >= 3210 {
                r.assist.torque_nm = 0.2;
            }
        });
        let c = compared(&a, &b);
        assert_eq!(c[&Channel::Wheel].difference, None);
        let (_, rows_a) = recorded_rows(&a).unwrap();
        let (_, rows_b) = recorded_rows(&b).unwrap();
        assert_eq!(
            c[&Channel::Assist].difference,
            Some(SampleDifference::Values {
                index: 3210,
                first: rows_a[&Channel::Assist][3210].clone(),
                second: rows_b[&Channel::Assist][3210].clone(),
            })
        );
    }

    #[test]
    fn fields_added_since_an_older_recording_are_no_difference_but_their_values_are() {
        let mut cmp = Comparer {
            keep: [true; N],
            matched: [0; N],
            difference: std::array::from_fn(|_| None),
            layouts: Vec::new(),
        };
        let row = |v: serde_json::Value| Sample::Row(v.as_object().unwrap().clone());
        let older = row(serde_json::json!({"tick": 9, "measures": {"movements": 2.0}}));
        let replayed = row(
            serde_json::json!({"tick": 9, "measures": {"movements": 2.0},
            "end_reason": "complete", "exercises": [{"index": 0}]}),
        );
        assert!(cmp.same(&older, &replayed));
        let other = row(
            serde_json::json!({"tick": 9, "measures": {"movements": 3.0},
            "end_reason": "complete"}),
        );
        assert!(!cmp.same(&older, &other), "the other fields still compared");
        let newer = row(
            serde_json::json!({"tick": 9, "measures": {"movements": 2.0},
            "end_reason": "ended early"}),
        );
        assert!(
            !cmp.same(&newer, &replayed),
            "recorded on both sides: compared"
        );
        // A measure a later version added is no difference; one both name still is.
        let with_dose = row(
            serde_json::json!({"tick": 9, "measures": {"movements": 2.0, "movements_per_min": 15.0}}),
        );
        assert!(cmp.same(&older, &with_dose));
        let moved = row(
            serde_json::json!({"tick": 9, "measures": {"movements": 3.0, "movements_per_min": 15.0}}),
        );
        assert!(!cmp.same(&older, &moved));
    }

    #[test]
    fn a_shorter_file_differs_in_its_counts_only() {
        let a = recording(5000, 1000, |_| {});
        let b = recording(3000, 1000, |_| {});
        let c = compared(&a, &b);
        assert_eq!(c[&Channel::Wheel].samples, [5000, 3000]);
        assert_eq!(c[&Channel::Wheel].difference, None);
    }

    #[test]
    fn every_sample_of_the_first_file_is_observed_with_its_fields() {
        let a = recording(1000, 1000, |r| r.score.paused = r.tick >= 500);
        let mut paused_ticks = Vec::new();
        compare(
            &a[..],
            &a[..],
            StreamLimits::default(),
            &[Channel::Score],
            &[Channel::Score],
            |c, s| {
                assert_eq!(c, Channel::Score);
                if s.field("paused") == Some(serde_json::Value::Bool(true)) {
                    paused_ticks.push(s.tick().unwrap());
                }
            },
        )
        .unwrap();
        assert_eq!(paused_ticks, [500, 600, 700, 800, 900]);
    }
}
