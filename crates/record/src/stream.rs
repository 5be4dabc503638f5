//! Reading a recording front to back in bounded memory, whatever its length, and whoever
//! wrote it (the hub replays recordings uploaded by stations: untrusted input).
//!
//! [`TickStream`] reads the file once, chunk by chunk in file order, on the crate's one
//! record walk ([`super::walk`]: every length checked against [`super::MAX_RECORD_BYTES`] and
//! the [`StreamLimits`] before anything is allocated for it), and gives the tick records back
//! as [`super::Recording::ticks`] joins them, holding only the samples of the last few seconds.
//!
//! Memory: what the walk holds (a few MB for the station's own recordings, chunks of 1 MiB
//! uncompressed) and the samples of the join window ([`JOIN_WINDOW_TICKS`]).

use super::channels::Channel;
use super::error::ReadError;
use super::raw::{RawImuSample, RawTick, RawWheelSample};
use super::reader::Decoder;
use super::types::{
    ArmCalibrationSample, ArmSample, AssistSample, MetricsSample, ScoreSample, SessionMetadata,
    Stamped, TickRecord, TimingSample, VehicleSample, WheelSample,
};
pub use super::walk::StreamLimits;
use super::walk::{Check, Rec, Records};
use mcap::records::Record;
use serde::de::DeserializeOwned;
use std::collections::{BTreeMap, VecDeque};
use std::io::{Cursor, Read};
use std::path::Path;

/// Ticks of `/wheel` held back while the other channels catch up: a high-rate channel's block
/// is written when it holds 100 samples or at the recorder's flush every second, so a tick's
/// samples are all in the file a little over a second after its `/wheel` sample. Beyond this
/// many ticks the oldest is given out with what has arrived (a sample arriving later still is
/// counted in [`TickStream::late_samples`]).
pub const JOIN_WINDOW_TICKS: usize = 8192;

/// Samples held on any one other channel, at most, before its oldest is dropped (counted as
/// late): bounds the memory of a file whose `/wheel` lags or is missing.
const QUEUE_CAP: usize = 4 * JOIN_WINDOW_TICKS;

/// One channel's samples waiting to be joined into ticks.
struct Queue<T> {
    samples: VecDeque<Stamped<T>>,
    /// Samples decoded so far (the index of the next one, for errors).
    decoded: usize,
    /// The tick of the last sample decoded.
    last_tick: Option<u64>,
}

impl<T> Default for Queue<T> {
    fn default() -> Self {
        Self {
            samples: VecDeque::new(),
            decoded: 0,
            last_tick: None,
        }
    }
}

impl<T: DeserializeOwned> Queue<T> {
    /// Appends the samples of one message; returns how many samples were dropped (beyond
    /// [`QUEUE_CAP`]).
    fn push(
        &mut self,
        channel: Channel,
        decoder: &mut Decoder,
        data: &[u8],
    ) -> Result<u64, ReadError> {
        let n = decoder.decode_into(channel, data, self.decoded, &mut self.samples)?;
        self.decoded += n;
        if let Some(last) = self.samples.back() {
            self.last_tick = Some(last.tick);
        }
        let over = self.samples.len().saturating_sub(QUEUE_CAP);
        self.samples.drain(..over);
        Ok(over as u64)
    }

    /// Whether every sample of `tick` has arrived: one past it has, or (`one_a_tick`) the
    /// tick's own has.
    fn past(&self, tick: u64, one_a_tick: bool) -> bool {
        self.last_tick
            .is_some_and(|t| t > tick || (one_a_tick && t == tick))
    }
}

impl<T: Copy> Queue<T> {
    /// The sample of `tick`, dropping earlier ones (counted in `late`).
    fn at(&mut self, tick: u64, late: &mut u64) -> Option<T> {
        while self.samples.front().is_some_and(|m| m.tick < tick) {
            self.samples.pop_front();
            *late += 1;
        }
        match self.samples.front() {
            Some(m) if m.tick == tick => self.samples.pop_front().map(|m| m.data),
            _ => None,
        }
    }
}

/// Every per-tick channel's waiting samples.
#[derive(Default)]
struct Queues {
    wheel: Queue<WheelSample>,
    vehicle: Queue<VehicleSample>,
    score: Queue<ScoreSample>,
    assist: Queue<AssistSample>,
    timing: Queue<TimingSample>,
    arm: Queue<ArmSample>,
    raw_wheel: Queue<RawWheelSample>,
    raw_imu: Queue<RawImuSample>,
}

/// Most bytes of schema records a stream keeps, names included (the station's own are a
/// few kilobytes in all).
pub(crate) const MAX_SCHEMA_BYTES: usize = 4 << 20;

/// The schemas a file declares, by id (name and data, as [`Decoder::of`] takes them, and
/// each one's encoding), kept within [`MAX_SCHEMA_BYTES`] in all: a file of many large
/// schemas cannot make a reader hold gigabytes, and the running total makes each schema
/// record cost the same however many a hostile file declares or re-declares.
#[derive(Debug, Default)]
pub(crate) struct SchemaTable {
    by_id: BTreeMap<u16, (String, Vec<u8>)>,
    encodings: BTreeMap<u16, String>,
    bytes: usize,
}

impl SchemaTable {
    /// Keeps the schema of `header` with `data` (replacing one of the same id), or refuses
    /// the file, naming `chunk`, when the schemas would add up to more than the limit.
    pub(crate) fn keep(
        &mut self,
        header: mcap::records::SchemaHeader,
        data: Vec<u8>,
        chunk: u64,
    ) -> Result<(), ReadError> {
        let size =
            |name: &str, encoding: &str, data: &[u8]| name.len() + encoding.len() + data.len();
        let replaced = match (self.by_id.get(&header.id), self.encodings.get(&header.id)) {
            (Some((name, data)), Some(encoding)) => size(name, encoding, data),
            _ => 0,
        };
        let bytes = self.bytes - replaced + size(&header.name, &header.encoding, &data);
        if bytes > MAX_SCHEMA_BYTES {
            return Err(ReadError::Damaged {
                chunk,
                reason: format!(
                    "its schemas add up to more than {} MiB",
                    MAX_SCHEMA_BYTES >> 20
                ),
            });
        }
        self.bytes = bytes;
        self.encodings.insert(header.id, header.encoding);
        self.by_id.insert(header.id, (header.name, data));
        Ok(())
    }

    /// The schemas by id: name and data.
    pub(crate) fn by_id(&self) -> &BTreeMap<u16, (String, Vec<u8>)> {
        &self.by_id
    }

    /// How channel record `c` decodes, when it is one of ours among `wanted` (by
    /// [`Channel`] index), its schema among those kept; `None` for a channel not read.
    pub(crate) fn decoder_of(
        &self,
        c: &mcap::records::Channel,
        wanted: &[bool; Channel::ALL.len()],
    ) -> Result<Option<(Channel, Decoder)>, ReadError> {
        match Channel::from_topic(&c.topic) {
            Some(channel) if wanted[channel as usize] => {
                Ok(Some((channel, Decoder::of(channel, c, &self.by_id)?)))
            }
            _ => Ok(None),
        }
    }

    /// The encoding of schema `id` (`""` if the file declared none by that id).
    pub(crate) fn encoding(&self, id: u16) -> &str {
        self.encodings.get(&id).map_or("", String::as_str)
    }
}

/// The tick records of a recording, read front to back in bounded memory (the module's
/// documentation says how). Gives the same records as [`super::Recording::ticks`] for the
/// channels it reads (the others left at their defaults).
pub struct TickStream<R> {
    records: Records<R>,
    metadata: SessionMetadata,
    wanted: [bool; Channel::ALL.len()],
    schemas: SchemaTable,
    channels: BTreeMap<u16, (Channel, Decoder)>,
    queues: Queues,
    last_score: ScoreSample,
    ended: bool,
    failed: bool,
    late: u64,
    /// The first `/score` sample read.
    first_score: Option<Stamped<ScoreSample>>,
    /// The last `/metrics` sample read (when `/metrics` is read).
    metrics: Option<Stamped<MetricsSample>>,
    /// The last `/arm_calibration` sample read (when `/arm_calibration` is read).
    arm_calibration: Option<Stamped<ArmCalibrationSample>>,
    /// The earliest log time of any message read, ns.
    first_log_ns: Option<u64>,
}

impl TickStream<std::io::BufReader<std::fs::File>> {
    /// [`TickStream::open`] on the file at `path`.
    pub fn open_path(
        path: &Path,
        limits: StreamLimits,
        channels: &[Channel],
    ) -> Result<Self, ReadError> {
        let file = std::fs::File::open(path).map_err(|source| ReadError::Io {
            path: format!(" {}", path.display()),
            source,
        })?;
        Self::open(std::io::BufReader::new(file), limits, channels)
    }
}

impl<R: Read> TickStream<R> {
    /// Starts reading the recording from `input` up to its session metadata; the ticks
    /// follow as the iterator is advanced. Only `channels` are decoded (`/wheel` always: a
    /// tick is a `/wheel` sample); the others are skipped unparsed and left at their defaults
    /// in the records.
    pub fn open(input: R, limits: StreamLimits, channels: &[Channel]) -> Result<Self, ReadError> {
        Self::open_checked(input, limits, channels, None)
    }

    /// [`TickStream::open`], asking `check` now and then (while it opens and as the ticks are
    /// read) whether to stop: a stopped stream ends with [`ReadError::Stopped`].
    pub fn open_checked(
        input: R,
        limits: StreamLimits,
        channels: &[Channel],
        check: Option<Check>,
    ) -> Result<Self, ReadError> {
        let records = Records::new(input, limits).with_check(check);
        let mut wanted = [false; Channel::ALL.len()];
        for c in channels.iter().chain([&Channel::Wheel]) {
            wanted[*c as usize] = true;
        }
        let mut stream = Self {
            records,
            metadata: SessionMetadata::default(),
            wanted,
            schemas: SchemaTable::default(),
            channels: BTreeMap::new(),
            queues: Queues::default(),
            last_score: ScoreSample::default(),
            ended: false,
            failed: false,
            late: 0,
            first_score: None,
            metrics: None,
            arm_calibration: None,
            first_log_ns: None,
        };
        loop {
            if stream.ended {
                return Err(ReadError::NoMetadata);
            }
            if let Some(metadata) = stream.pump()? {
                stream.metadata = metadata;
                return Ok(stream);
            }
        }
    }

    /// The session metadata record.
    pub fn metadata(&self) -> &SessionMetadata {
        &self.metadata
    }

    /// The first `/score` sample read (the score of the ticks before it; `None` before it is
    /// read, or without `/score`).
    pub fn first_score(&self) -> Option<&Stamped<ScoreSample>> {
        self.first_score.as_ref()
    }

    /// The last `/metrics` sample read, when `/metrics` is one of the channels read (it is
    /// recorded once, at the end).
    pub fn metrics(&self) -> Option<&Stamped<MetricsSample>> {
        self.metrics.as_ref()
    }

    /// The last `/arm_calibration` sample read, when it is one of the channels read (it is
    /// recorded once, at the end, by sessions with arm sensors).
    pub fn arm_calibration(&self) -> Option<&Stamped<ArmCalibrationSample>> {
        self.arm_calibration.as_ref()
    }

    /// The earliest log time of the messages read so far, ns since the Unix epoch (at the
    /// end, the file's message start time).
    pub fn first_log_ns(&self) -> Option<u64> {
        self.first_log_ns
    }

    /// Whether the file has declared `channel` so far (and it is one read): a channel is
    /// declared before its first message.
    pub fn has_channel(&self, channel: Channel) -> bool {
        self.channels.values().any(|(c, _)| *c == channel)
    }

    /// Samples that arrived after their tick had been given out, or were dropped beyond the
    /// join window (0 for any recording the station wrote).
    pub fn late_samples(&self) -> u64 {
        self.late
    }

    /// Reads one record; a session metadata record is returned.
    fn pump(&mut self) -> Result<Option<SessionMetadata>, ReadError> {
        let max_message = self.records.limits().max_message_bytes;
        let (record, chunk) = match self.records.next()? {
            Rec::End => {
                self.ended = true;
                return Ok(None);
            }
            Rec::Other => return Ok(None),
            Rec::Message(m) => {
                let log_ns = m.header.log_time;
                self.first_log_ns = Some(self.first_log_ns.map_or(log_ns, |t| t.min(log_ns)));
                let Some((channel, decoder)) = self.channels.get_mut(&m.header.channel_id) else {
                    return Ok(None);
                };
                let body = m.data_within(channel.topic(), max_message)?;
                let q = &mut self.queues;
                let dropped = match channel {
                    Channel::Wheel => q.wheel.push(*channel, decoder, body)?,
                    Channel::Vehicle => q.vehicle.push(*channel, decoder, body)?,
                    Channel::Score => {
                        let dropped = q.score.push(*channel, decoder, body)?;
                        if self.first_score.is_none() {
                            self.first_score = q.score.samples.front().cloned();
                        }
                        dropped
                    }
                    Channel::Assist => q.assist.push(*channel, decoder, body)?,
                    Channel::Timing => q.timing.push(*channel, decoder, body)?,
                    Channel::Arm => q.arm.push(*channel, decoder, body)?,
                    Channel::RawWheel => q.raw_wheel.push(*channel, decoder, body)?,
                    Channel::RawImu => q.raw_imu.push(*channel, decoder, body)?,
                    Channel::Metrics => {
                        let mut one = Vec::new();
                        decoder.decode_into(*channel, body, 0, &mut one)?;
                        if let Some(m) = one.pop() {
                            self.metrics = Some(m);
                        }
                        0
                    }
                    Channel::ArmCalibration => {
                        let mut one = Vec::new();
                        decoder.decode_into(*channel, body, 0, &mut one)?;
                        if let Some(c) = one.pop() {
                            self.arm_calibration = Some(c);
                        }
                        0
                    }
                };
                self.late += dropped;
                return Ok(None);
            }
            Rec::Record(record, chunk) => (record, chunk),
        };
        match record {
            Record::Schema { header, data } => {
                // Each schema is within a record's limit; their sum is bounded too, or a file
                // of many 16 MiB schemas would hold gigabytes (ours are a few kilobytes).
                self.schemas.keep(header, data.into_owned(), chunk)?;
            }
            Record::Channel(c) => {
                if let Some(read) = self.schemas.decoder_of(&c, &self.wanted)? {
                    self.channels.insert(c.id, read);
                }
            }
            Record::Metadata(m) if m.name == SessionMetadata::NAME => {
                return Ok(Some(SessionMetadata::from_map(&m.metadata)?));
            }
            _ => {}
        }
        Ok(None)
    }

    /// Whether the oldest `/wheel` sample's tick can be given out: every channel read has
    /// gone past it, the file has ended, or the join window is full.
    fn ready(&self, tick: u64) -> bool {
        let q = &self.queues;
        let w = |c: Channel| !self.wanted[c as usize];
        self.ended
            || q.wheel.samples.len() > JOIN_WINDOW_TICKS
            || ((w(Channel::Vehicle) || q.vehicle.past(tick, true))
                && (w(Channel::Score) || q.score.past(tick, true))
                && (w(Channel::Assist) || q.assist.past(tick, true))
                && (w(Channel::Timing) || q.timing.past(tick, true))
                && (w(Channel::Arm) || q.arm.past(tick, true))
                && (w(Channel::RawWheel) || q.raw_wheel.past(tick, true))
                && (w(Channel::RawImu) || q.raw_imu.past(tick, false)))
    }

    /// The record of the oldest `/wheel` sample, joined with what the other channels hold.
    fn join(&mut self, w: Stamped<WheelSample>) -> TickRecord {
        let tick = w.tick;
        let q = &mut self.queues;
        while q.score.samples.front().is_some_and(|s| s.tick <= tick) {
            if let Some(s) = q.score.samples.pop_front() {
                self.last_score = s.data;
            }
        }
        let mut imu = [None; 2];
        let late = &mut self.late;
        while q.raw_imu.samples.front().is_some_and(|m| m.tick < tick) {
            q.raw_imu.samples.pop_front();
            *late += 1;
        }
        while let Some(m) = q.raw_imu.samples.front().filter(|m| m.tick == tick) {
            if let Some(slot) = imu.get_mut(m.data.sensor as usize) {
                *slot = Some(m.data);
            }
            q.raw_imu.samples.pop_front();
        }
        TickRecord {
            tick,
            t_ns: w.t_ns(),
            wheel: w.data,
            vehicle: q.vehicle.at(tick, late),
            score: self.last_score,
            assist: q.assist.at(tick, late).unwrap_or_default(),
            arm: q.arm.at(tick, late),
            timing: q.timing.at(tick, late).unwrap_or_default(),
            raw: RawTick {
                wheel: q.raw_wheel.at(tick, late).unwrap_or_default(),
                imu,
            },
        }
    }
}

impl<R: Read> Iterator for TickStream<R> {
    type Item = Result<TickRecord, ReadError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        loop {
            if let Some(tick) = self.queues.wheel.samples.front().map(|w| w.tick)
                && self.ready(tick)
            {
                let w = self.queues.wheel.samples.pop_front()?;
                return Some(Ok(self.join(w)));
            }
            if self.ended {
                return None;
            }
            if let Err(e) = self.pump() {
                self.failed = true;
                return Some(Err(e));
            }
        }
    }
}

/// Reads a whole buffered input through [`TickStream`] — for tests and small files.
impl TickStream<Cursor<Vec<u8>>> {
    /// [`TickStream::open`] on bytes in memory.
    pub fn from_bytes(
        bytes: Vec<u8>,
        limits: StreamLimits,
        channels: &[Channel],
    ) -> Result<Self, ReadError> {
        Self::open(Cursor::new(bytes), limits, channels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_schema_declared_again_replaces_its_bytes_and_the_sum_stays_bounded() {
        let header = |id: u16| mcap::records::SchemaHeader {
            id,
            name: "telerehab.Wheel".into(),
            encoding: "jsonschema".into(),
        };
        let mut table = SchemaTable::default();
        let mib = vec![b'x'; 1 << 20];
        for _ in 0..100 {
            // The same id again and again: the total is one schema's, not a hundred.
            table
                .keep(header(1), [&mib[..], &mib[..], &mib[..]].concat(), 1)
                .unwrap();
        }
        assert_eq!(table.by_id().len(), 1);
        assert_eq!(table.encoding(1), "jsonschema");
        assert_eq!(table.encoding(9), "");
        let e = table
            .keep(header(2), [&mib[..], &mib[..]].concat(), 3)
            .unwrap_err();
        assert!(
            e.to_string().contains("schemas add up to more than 4 MiB"),
            "{e}"
        );
        table.keep(header(2), mib[..1 << 19].to_vec(), 3).unwrap();
    }
    use crate::{RecordWriter, Recording};
    use mcap::records::op;

    /// A little generator with a fixed seed (xorshift64*).
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }

        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// `n` ticks at 1 kHz: the car on the road from tick 1500 to 3700, the arm sensed on most
    /// ticks, IMU samples now and then (sometimes two a tick), a score every 100 ticks.
    fn ticks(n: u64, seed: u64) -> Vec<(TickRecord, bool)> {
        let mut rng = Rng(seed);
        (0..n)
            .map(|tick| {
                let x = rng.unit();
                let mut rec = TickRecord {
                    tick,
                    t_ns: tick * 1_000_000,
                    ..Default::default()
                };
                rec.wheel.angle_rad = x;
                rec.wheel.commanded_nm = 0.5 * x;
                rec.assist.torque_nm = -x;
                rec.timing.lateness_ns = tick % 7;
                rec.raw.wheel.angle_rad = x;
                rec.score.pct_in_lane = (tick / 100) as f64;
                if (1500..3700).contains(&tick) {
                    rec.vehicle = Some(VehicleSample {
                        x_m: tick as f64,
                        lateral_m: x - 0.5,
                        ..Default::default()
                    });
                }
                if rng.unit() < 0.9 {
                    rec.arm = Some(ArmSample {
                        elbow_flexion_rad: x,
                        ..Default::default()
                    });
                }
                for sensor in 0..2 {
                    if rng.unit() < 0.2 {
                        rec.raw.imu[sensor as usize] = Some(RawImuSample {
                            sensor,
                            gyro_x_rad_s: x,
                            ..Default::default()
                        });
                    }
                }
                (rec, tick % 100 == 0)
            })
            .collect()
    }

    /// A recording of `ticks`, the chunk closed every `flush_every` ticks (0: never).
    fn write(ticks: &[(TickRecord, bool)], flush_every: u64) -> Vec<u8> {
        let meta = SessionMetadata {
            loop_rate_hz: 1000.0,
            ..Default::default()
        };
        let mut w = RecordWriter::new(Cursor::new(Vec::new()), 0, &meta).unwrap();
        for (rec, with_score) in ticks {
            w.write_tick(rec, *with_score).unwrap();
            if flush_every > 0 && rec.tick % flush_every == flush_every - 1 {
                w.flush().unwrap();
            }
        }
        w.finish().unwrap().into_inner()
    }

    fn streamed(bytes: &[u8], limits: StreamLimits, channels: &[Channel]) -> Vec<TickRecord> {
        let stream = TickStream::from_bytes(bytes.to_vec(), limits, channels).unwrap();
        stream.collect::<Result<_, _>>().unwrap()
    }

    #[test]
    fn the_stream_gives_the_ticks_the_whole_file_reader_gives() {
        for flush_every in [0, 1000, 333] {
            let bytes = write(&ticks(5000, 7), flush_every);
            let whole: Vec<TickRecord> = Recording::from_bytes(&bytes).unwrap().ticks().collect();
            let mut stream =
                TickStream::from_bytes(bytes.clone(), StreamLimits::default(), &Channel::ALL)
                    .unwrap();
            let got: Vec<TickRecord> = stream.by_ref().collect::<Result<_, _>>().unwrap();
            assert_eq!(got.len(), 5000);
            assert_eq!(got, whole, "flushed every {flush_every} ticks");
            assert_eq!(stream.late_samples(), 0);
        }
    }

    #[test]
    fn channels_left_out_are_skipped_and_left_at_their_defaults() {
        let bytes = write(&ticks(2000, 3), 1000);
        let whole: Vec<TickRecord> = Recording::from_bytes(&bytes).unwrap().ticks().collect();
        let got = streamed(&bytes, StreamLimits::default(), &[Channel::Vehicle]);
        assert_eq!(got.len(), whole.len());
        for (g, w) in got.iter().zip(&whole) {
            assert_eq!((g.wheel, g.vehicle), (w.wheel, w.vehicle));
            assert_eq!((g.arm, g.raw), (None, RawTick::default()));
        }
    }

    #[test]
    fn the_arm_calibration_recorded_at_the_end_is_read_when_asked_for() {
        let ticks = ticks(300, 5);
        let meta = SessionMetadata {
            loop_rate_hz: 1000.0,
            ..Default::default()
        };
        let mut w = RecordWriter::new(Cursor::new(Vec::new()), 0, &meta).unwrap();
        for (rec, with_score) in &ticks {
            w.write_tick(rec, *with_score).unwrap();
        }
        let fit = ArmCalibrationSample {
            upper_arm_m: 0.31,
            forearm_m: 0.27,
            rms_residual_m: 0.004,
            ..Default::default()
        };
        w.write_arm_calibration(&ticks[299].0, &fit).unwrap();
        let bytes = w.finish().unwrap().into_inner();
        let mut stream = TickStream::from_bytes(
            bytes.clone(),
            StreamLimits::default(),
            &[Channel::ArmCalibration],
        )
        .unwrap();
        assert_eq!(stream.by_ref().count(), 300);
        assert_eq!(stream.arm_calibration().map(|c| &c.data), Some(&fit));
        let mut without =
            TickStream::from_bytes(bytes, StreamLimits::default(), &[Channel::Vehicle]).unwrap();
        assert_eq!(without.by_ref().count(), 300);
        assert!(without.arm_calibration().is_none(), "not asked for");
    }

    /// The records of a chunk record (MCAP specification, "Chunk") declaring `declared`
    /// uncompressed bytes.
    fn chunk_record(declared: u64, compression: &str, records: &[u8]) -> Vec<u8> {
        let mut body = Vec::new();
        body.extend(0u64.to_le_bytes());
        body.extend(0u64.to_le_bytes());
        body.extend(declared.to_le_bytes());
        body.extend(0u32.to_le_bytes());
        body.extend((compression.len() as u32).to_le_bytes());
        body.extend(compression.as_bytes());
        body.extend((records.len() as u64).to_le_bytes());
        body.extend(records);
        let mut record = vec![op::CHUNK];
        record.extend((body.len() as u64).to_le_bytes());
        record.extend(body);
        record
    }

    /// A recording of a few ticks with `record` right after the header.
    fn with_record_after_header(record: &[u8]) -> Vec<u8> {
        let honest = write(&ticks(300, 1), 0);
        let header_end = 8 + 9 + u64::from_le_bytes(honest[9..17].try_into().unwrap()) as usize;
        let mut forged = honest[..header_end].to_vec();
        forged.extend(record);
        forged.extend(&honest[header_end..]);
        forged
    }

    fn refused(bytes: Vec<u8>, limits: StreamLimits) -> ReadError {
        match TickStream::from_bytes(bytes, limits, &Channel::ALL) {
            Err(e) => e,
            Ok(stream) => stream
                .filter_map(Result::err)
                .next()
                .expect("the stream refuses it"),
        }
    }

    #[test]
    fn a_chunk_declaring_gigabytes_is_refused_before_it_is_decompressed() {
        let zeros = zstd::bulk::compress(&vec![0u8; 1 << 20], 3).unwrap();
        let bomb = with_record_after_header(&chunk_record(5_368_700_000, "zstd", &zeros));
        let e = refused(bomb, StreamLimits::default());
        assert!(
            matches!(
                e,
                ReadError::TooLarge {
                    claimed_bytes: 5_368_700_000,
                    ..
                }
            ),
            "{e}"
        );
        let text = e.to_string();
        assert!(text.contains("uncompressed data of chunk 1"), "{text}");
    }

    #[test]
    fn a_chunk_decompressing_past_what_it_declares_is_stopped_there() {
        // 64 MiB of zeros (empty records of opcode 0) in a chunk declaring 900 000 bytes.
        let mut encoder = zstd::stream::write::Encoder::new(Vec::new(), 3).unwrap();
        let mib = vec![0u8; 1 << 20];
        for _ in 0..64 {
            std::io::Write::write_all(&mut encoder, &mib).unwrap();
        }
        let zeros = encoder.finish().unwrap();
        let bomb = with_record_after_header(&chunk_record(900_000, "zstd", &zeros));
        let e = refused(bomb, StreamLimits::default());
        assert!(
            e.to_string()
                .contains("chunk 1 decompresses to more than the 900000 bytes it declares"),
            "{e}"
        );
    }

    #[test]
    fn a_record_claiming_more_than_its_chunk_or_the_limit_is_refused_unallocated() {
        // A message record claiming 5 GB in an uncompressed chunk of 9 bytes.
        let mut head = vec![op::MESSAGE];
        head.extend(5_000_000_000u64.to_le_bytes());
        let e = refused(
            with_record_after_header(&chunk_record(9, "", &head)),
            StreamLimits::default(),
        );
        assert!(e.to_string().contains("past its end"), "{e}");
        // A record claiming one byte over the limit, in a chunk that holds it (raised
        // chunk limit): refused by name before its bytes are read.
        let over = crate::MAX_RECORD_BYTES as u64 + 1;
        let mut records = vec![op::METADATA];
        records.extend(over.to_le_bytes());
        records.resize(9 + over as usize, 0);
        let zeros = zstd::bulk::compress(&records, 3).unwrap();
        let limits = StreamLimits {
            max_chunk_bytes: 64 << 20,
            ..Default::default()
        };
        let e = refused(
            with_record_after_header(&chunk_record(records.len() as u64, "zstd", &zeros)),
            limits,
        );
        assert!(
            matches!(
                &e,
                ReadError::TooLarge { what, claimed_bytes, limit_bytes }
                    if what == "a record (opcode 0x0c) in chunk 1"
                        && *claimed_bytes == over
                        && *limit_bytes == crate::MAX_RECORD_BYTES as u64
            ),
            "{e}"
        );
    }

    #[test]
    fn a_chunk_that_decompresses_to_less_than_it_declares_is_refused() {
        let one = zstd::bulk::compress(&[0u8; 9], 3).unwrap();
        let e = refused(
            with_record_after_header(&chunk_record(18, "zstd", &one)),
            StreamLimits::default(),
        );
        assert!(e.to_string().contains("fewer than the 18 bytes"), "{e}");
    }

    #[test]
    fn an_oversized_message_on_our_channels_is_refused_by_name() {
        let bytes = write(&ticks(300, 1), 0);
        let limits = StreamLimits {
            max_message_bytes: 64,
            ..Default::default()
        };
        let e = refused(bytes, limits);
        assert!(e.to_string().contains("a message of channel /"), "{e}");
    }

    #[test]
    fn a_file_without_session_metadata_is_refused_at_open() {
        let mut w = mcap::WriteOptions::new()
            .create(Cursor::new(Vec::new()))
            .unwrap();
        w.finish().unwrap();
        let bytes = w.into_inner().into_inner();
        let e = TickStream::from_bytes(bytes, StreamLimits::default(), &[]).err();
        assert!(matches!(e, Some(ReadError::NoMetadata)), "{e:?}");
    }
}
