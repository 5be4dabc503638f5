//! Reads a recording back into the types it was written from (replay, reports, Python).

use super::blocks::{self, DecodeScratch, Layout};
use super::channels::Channel;
use super::error::ReadError;
use super::raw::{RawImuSample, RawTick, RawWheelSample};
use super::types::{
    ArmCalibrationSample, ArmSample, AssistSample, MetricsSample, ScoreSample, SessionMetadata,
    Stamped, TickRecord, TimingSample, VehicleSample, WheelSample,
};
use super::walk::{Rec, Records, StreamLimits};
use mcap::records::Record;
use serde::de::DeserializeOwned;
use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

/// A whole recording, decoded: the session metadata and every channel's messages in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recording {
    /// The `session` metadata record.
    pub metadata: SessionMetadata,
    /// `/wheel`, every tick.
    pub wheel: Vec<Stamped<WheelSample>>,
    /// `/vehicle`, every tick on the road.
    pub vehicle: Vec<Stamped<VehicleSample>>,
    /// `/score`, every 100 ms of session time.
    pub score: Vec<Stamped<ScoreSample>>,
    /// `/assist`, every tick.
    pub assist: Vec<Stamped<AssistSample>>,
    /// `/timing`, every tick.
    pub timing: Vec<Stamped<TimingSample>>,
    /// `/arm`, every tick with arm sensing.
    pub arm: Vec<Stamped<ArmSample>>,
    /// `/arm_calibration`, at most once, at the end.
    pub arm_calibration: Vec<Stamped<ArmCalibrationSample>>,
    /// `/metrics`, at most once, at the end.
    pub metrics: Vec<Stamped<MetricsSample>>,
    /// `/raw/wheel`, every tick: the raw inputs besides the IMU samples.
    pub raw_wheel: Vec<Stamped<RawWheelSample>>,
    /// `/raw/imu`, every IMU sample the arm tracker consumed.
    pub raw_imu: Vec<Stamped<RawImuSample>>,
}

impl Recording {
    /// Read the recording at `path`.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, ReadError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| ReadError::Io {
            path: format!(" {}", path.display()),
            source,
        })?;
        Self::from_bytes(&bytes)
    }

    /// Read a recording from a stream (read to its end first).
    pub fn read(mut reader: impl Read) -> Result<Self, ReadError> {
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .map_err(|source| ReadError::Io {
                path: String::new(),
                source,
            })?;
        Self::from_bytes(&bytes)
    }

    /// Read a recording held in memory. Messages on topics that are not ours are skipped.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, ReadError> {
        let (metadata, mut raw) = channel_messages(bytes)?;
        let mut take = |channel| raw.remove(&channel);
        Ok(Self {
            metadata,
            wheel: decode(Channel::Wheel, take(Channel::Wheel))?,
            vehicle: decode(Channel::Vehicle, take(Channel::Vehicle))?,
            score: decode(Channel::Score, take(Channel::Score))?,
            assist: decode(Channel::Assist, take(Channel::Assist))?,
            timing: decode(Channel::Timing, take(Channel::Timing))?,
            arm: decode(Channel::Arm, take(Channel::Arm))?,
            arm_calibration: decode(Channel::ArmCalibration, take(Channel::ArmCalibration))?,
            metrics: decode(Channel::Metrics, take(Channel::Metrics))?,
            raw_wheel: decode(Channel::RawWheel, take(Channel::RawWheel))?,
            raw_imu: decode(Channel::RawImu, take(Channel::RawImu))?,
        })
    }

    /// The tick records again, in tick order, one per `/wheel` message: every per-tick
    /// channel joined on the tick; the score is the latest recorded at or before the tick
    /// (the default before the first), as the score is recorded every 100 ms only.
    pub fn ticks(&self) -> impl Iterator<Item = TickRecord> + '_ {
        let mut vehicle = self.vehicle.iter().peekable();
        let mut score = self.score.iter().peekable();
        let mut assist = self.assist.iter().peekable();
        let mut timing = self.timing.iter().peekable();
        let mut arm = self.arm.iter().peekable();
        let mut raw_wheel = self.raw_wheel.iter().peekable();
        let mut raw_imu = self.raw_imu.iter().peekable();
        let mut last_score = ScoreSample::default();
        self.wheel.iter().map(move |w| {
            let tick = w.tick;
            while let Some(s) = score.next_if(|s| s.tick <= tick) {
                last_score = s.data;
            }
            let mut imu = [None; 2];
            while raw_imu.next_if(|m| m.tick < tick).is_some() {}
            while let Some(m) = raw_imu.next_if(|m| m.tick == tick) {
                if let Some(slot) = imu.get_mut(m.data.sensor as usize) {
                    *slot = Some(m.data);
                }
            }
            TickRecord {
                tick,
                t_ns: w.t_ns(),
                wheel: w.data,
                vehicle: at_tick(&mut vehicle, tick),
                score: last_score,
                assist: at_tick(&mut assist, tick).unwrap_or_default(),
                arm: at_tick(&mut arm, tick),
                timing: at_tick(&mut timing, tick).unwrap_or_default(),
                raw: RawTick {
                    wheel: at_tick(&mut raw_wheel, tick).unwrap_or_default(),
                    imu,
                },
            }
        })
    }
}

/// One recorded sample as its fields: `tick`, `t_s`, then the sample's own, as written (a
/// JSON object; a high-rate channel's block unpacked to its samples).
pub type Row = serde_json::Map<String, serde_json::Value>;

/// Every sample of each of our channels as recorded, in file order, by channel.
pub type RecordedRows = BTreeMap<Channel, Vec<Row>>;

/// How one of our channels' messages decode.
pub(super) enum Decoder {
    /// One JSON sample a message.
    Json,
    /// A block of samples a message, and whether the file's columns are the channel's own
    /// (decoded straight from its columns into the samples, `Layout::decode_samples`, its
    /// columns kept from message to message in the scratch) or another version's (rebuilt
    /// through JSON).
    Blocks(Box<Layout>, bool, DecodeScratch),
}

impl Decoder {
    /// The decoder of `channel` as the file declares it (`c`), its schema among `schemas`.
    pub(super) fn of(
        channel: Channel,
        c: &mcap::records::Channel,
        schemas: &BTreeMap<u16, (String, Vec<u8>)>,
    ) -> Result<Self, ReadError> {
        if c.message_encoding != blocks::ENCODING {
            return Ok(Self::Json);
        }
        let (name, schema) = schemas.get(&c.schema_id).cloned().unwrap_or_default();
        let layout =
            Layout::from_file(&name, &schema, &c.metadata).map_err(|source| ReadError::Block {
                topic: channel.topic(),
                index: usize::MAX,
                source,
            })?;
        let own = channel.spec().block_layout().and_then(Result::ok);
        let same = own.is_some_and(|own| own.column_names().eq(layout.column_names()));
        Ok(Self::Blocks(
            Box::new(layout),
            same,
            DecodeScratch::default(),
        ))
    }

    /// Appends the samples of one message of `channel` to `out` as `T`: a JSON message
    /// deserialised, a block decoded column by column (NaN and infinities kept) when the file's
    /// columns are `T`'s own, through JSON otherwise. `index` is the position of the message's
    /// first sample within its channel (for errors); returns the number of samples appended.
    pub(super) fn decode_into<T: DeserializeOwned>(
        &mut self,
        channel: Channel,
        data: &[u8],
        index: usize,
        out: &mut impl Extend<Stamped<T>>,
    ) -> Result<usize, ReadError> {
        let json_error = |index, source| ReadError::Decode {
            topic: channel.topic(),
            index,
            source,
        };
        let block_error = |index, source| ReadError::Block {
            topic: channel.topic(),
            index,
            source,
        };
        let mut n = 0;
        match self {
            Self::Json => {
                let sample = serde_json::from_slice(data).map_err(|e| json_error(index, e))?;
                out.extend([sample]);
                n = 1;
            }
            Self::Blocks(layout, false, _) => {
                for row in layout.decode(data).map_err(|e| block_error(index, e))? {
                    let v = serde_json::Value::Object(row);
                    let sample = serde_json::from_value(v).map_err(|e| json_error(index + n, e))?;
                    out.extend([sample]);
                    n += 1;
                }
            }
            Self::Blocks(layout, true, scratch) => {
                // Straight from the block's columns into the samples (no cells a sample).
                n = layout
                    .decode_samples(data, scratch, |tick, t_ns, data| {
                        out.extend([Stamped {
                            tick,
                            t_s: t_ns as f64 * 1e-9,
                            data,
                        }]);
                    })
                    .map_err(|(at, e)| block_error(index + at, e))?;
            }
        }
        Ok(n)
    }
}

/// One of our channels in a file: how its messages decode, and the messages in file order.
struct ChannelMessages {
    decoder: Decoder,
    messages: Vec<Vec<u8>>,
}

/// The session metadata and every message of our channels, by channel, read on the crate's
/// one record walk ([`super::walk`]). Messages on topics that are not ours are skipped.
fn channel_messages(
    bytes: &[u8],
) -> Result<(SessionMetadata, BTreeMap<Channel, ChannelMessages>), ReadError> {
    let mut schemas: BTreeMap<u16, (String, Vec<u8>)> = BTreeMap::new();
    let mut topics: BTreeMap<u16, Channel> = BTreeMap::new();
    let mut out: BTreeMap<Channel, ChannelMessages> = BTreeMap::new();
    let mut metadata = None;
    let mut records = Records::new(bytes, StreamLimits::default());
    loop {
        match records.next()? {
            Rec::End => break,
            Rec::Record(Record::Schema { header, data }, _) => {
                schemas.insert(header.id, (header.name, data.into_owned()));
            }
            Rec::Record(Record::Channel(c), _) => {
                let Some(channel) = Channel::from_topic(&c.topic) else {
                    continue;
                };
                let decoder = Decoder::of(channel, &c, &schemas)?;
                topics.insert(c.id, channel);
                out.entry(channel).or_insert(ChannelMessages {
                    decoder,
                    messages: Vec::new(),
                });
            }
            Rec::Message(m) => {
                if let Some(channel) = topics.get(&m.header.channel_id)
                    && let Some(c) = out.get_mut(channel)
                {
                    c.messages.push(m.data.to_vec());
                }
            }
            Rec::Record(Record::Metadata(m), _) if m.name == SessionMetadata::NAME => {
                metadata = Some(SessionMetadata::from_map(&m.metadata)?);
            }
            _ => {}
        }
    }
    Ok((metadata.ok_or(ReadError::NoMetadata)?, out))
}

/// The session metadata and every sample of our channels as recorded, in file order, by
/// channel: what `telerehab replay` compares bit for bit (a NaN or infinity as null). Messages
/// on topics that are not ours are skipped.
pub fn recorded_rows(bytes: &[u8]) -> Result<(SessionMetadata, RecordedRows), ReadError> {
    let (metadata, channels) = channel_messages(bytes)?;
    let mut rows = RecordedRows::new();
    for (channel, c) in channels {
        let out = rows.entry(channel).or_default();
        for data in &c.messages {
            match &c.decoder {
                Decoder::Json => {
                    out.push(
                        serde_json::from_slice(data).map_err(|source| ReadError::Decode {
                            topic: channel.topic(),
                            index: out.len(),
                            source,
                        })?,
                    )
                }
                Decoder::Blocks(layout, ..) => {
                    out.extend(layout.decode(data).map_err(|source| ReadError::Block {
                        topic: channel.topic(),
                        index: out.len(),
                        source,
                    })?)
                }
            }
        }
    }
    Ok((metadata, rows))
}

/// The message of `tick`, skipping any earlier ones.
fn at_tick<'a, T: Copy + 'a>(
    it: &mut std::iter::Peekable<impl Iterator<Item = &'a Stamped<T>>>,
    tick: u64,
) -> Option<T> {
    while it.next_if(|m| m.tick < tick).is_some() {}
    it.next_if(|m| m.tick == tick).map(|m| m.data)
}

/// A channel's samples as `T` ([`Decoder::decode_into`]).
fn decode<T: DeserializeOwned>(
    channel: Channel,
    messages: Option<ChannelMessages>,
) -> Result<Vec<Stamped<T>>, ReadError> {
    let Some(mut c) = messages else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for data in &c.messages {
        c.decoder.decode_into(channel, data, out.len(), &mut out)?;
    }
    Ok(out)
}
