//! The MCAP writer: the high-rate channels in compact protobuf blocks ([`super::blocks`]), the
//! low-rate ones in JSON, the arm as a Foxglove 3-D scene, zstd chunks, the session metadata
//! record.
//!
//! Generic over any `Write + Seek` sink (a buffered file for a session, a `Cursor<Vec<u8>>`
//! in tests); it knows nothing of paths, threads or clocks.

use super::blocks::{self, BlockBuilder, BlockError, Layout};
use super::channels::{BLOCK_SAMPLES, CHANNELS, Channel, MESSAGE_ENCODING, SCHEMA_ENCODING};
use super::scene::{SCENE_RATE_HZ, arm_scene};
use super::types::{ArmCalibrationSample, MetricsSample, SessionMetadata, Stamped, TickRecord};
use foxglove::Encode as _;
use mcap::records::MessageHeader;
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

/// Uncompressed bytes per chunk (about a second of a session at 1 kHz).
const CHUNK_BYTES: u64 = 1024 * 1024;

/// The MCAP writer settings of every file the station writes (sessions and recoveries);
/// `library` names the writer in the file header.
///
/// Chunks are compressed on the writing thread (`compression_threads(0)`): mcap's default is a
/// zstd worker per physical core, but a 1 MiB chunk is smaller than one zstd job, so the writer
/// waited for its one worker at every chunk's end anyway, and at `--speed max` on two cores the
/// workers were a third thread contending with the haptic thread and the recorder (issue 47).
/// The messages and their bytes are the same either way.
pub fn mcap_options(library: &str) -> mcap::WriteOptions {
    mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .compression_threads(0)
        .profile("")
        .library(library)
        .chunk_size(Some(CHUNK_BYTES))
}

/// The topic of the arm's 3-D scene (`foxglove.SceneUpdate`).
pub const SCENE_TOPIC: &str = "/arm/scene";

/// A high-rate channel's samples gathering into its next block.
struct Pending {
    layout: Layout,
    block: BlockBuilder,
}

/// A recording being written to `W`.
pub struct RecordWriter<W: Write + Seek> {
    writer: mcap::Writer<W>,
    channels: [u16; CHANNELS.len()],
    /// The block being gathered of each high-rate channel (`None`: a JSON channel).
    pending: [Option<Pending>; CHANNELS.len()],
    scene_channel: u16,
    scene_every_ns: u64,
    next_scene_ns: u64,
    sequence: u32,
    start_unix_ns: u64,
    buf: Vec<u8>,
}

fn block_error(e: BlockError) -> mcap::McapError {
    mcap::McapError::Io(std::io::Error::other(e))
}

impl<W: Write + Seek> RecordWriter<W> {
    /// Start a recording in `sink`: header, every channel's schema and the session metadata.
    /// `start_unix_ns` anchors the messages' log times (log time = start + session time).
    pub fn new(
        sink: W,
        start_unix_ns: u64,
        metadata: &SessionMetadata,
    ) -> Result<Self, mcap::McapError> {
        let mut writer =
            mcap_options(concat!("telerehab ", env!("CARGO_PKG_VERSION"))).create(sink)?;
        let mut channels = [0u16; CHANNELS.len()];
        let mut pending: [Option<Pending>; CHANNELS.len()] = Default::default();
        for ((id, pending), spec) in channels.iter_mut().zip(&mut pending).zip(&CHANNELS) {
            match spec.block_layout().transpose().map_err(block_error)? {
                Some(layout) => {
                    let schema_id = writer.add_schema(
                        layout.message_name(),
                        blocks::ENCODING,
                        layout.schema(),
                    )?;
                    *id = writer.add_channel(
                        schema_id,
                        spec.topic,
                        blocks::ENCODING,
                        &layout.channel_metadata(),
                    )?;
                    *pending = Some(Pending {
                        layout,
                        block: BlockBuilder::new(),
                    });
                }
                None => {
                    let schema = spec.schema().to_string();
                    let schema_id =
                        writer.add_schema(spec.schema_name, SCHEMA_ENCODING, schema.as_bytes())?;
                    *id = writer.add_channel(
                        schema_id,
                        spec.topic,
                        MESSAGE_ENCODING,
                        &BTreeMap::new(),
                    )?;
                }
            }
        }
        let scene = foxglove::messages::SceneUpdate::get_schema().expect("a well-known schema");
        let scene_schema = writer.add_schema(&scene.name, &scene.encoding, &scene.data)?;
        let scene_channel = writer.add_channel(
            scene_schema,
            SCENE_TOPIC,
            &foxglove::messages::SceneUpdate::get_message_encoding(),
            &BTreeMap::new(),
        )?;
        writer.write_metadata(&mcap::records::Metadata {
            name: SessionMetadata::NAME.into(),
            metadata: metadata.to_map(),
        })?;
        Ok(Self {
            writer,
            channels,
            pending,
            scene_channel,
            scene_every_ns: 1_000_000_000 / SCENE_RATE_HZ,
            next_scene_ns: 0,
            sequence: 0,
            start_unix_ns,
            buf: Vec::with_capacity(512),
        })
    }

    /// Write `self.buf` as a message of MCAP channel `channel_id` at session time `t_ns`.
    fn write_buf(&mut self, channel_id: u16, t_ns: u64) -> Result<(), mcap::McapError> {
        self.sequence = self.sequence.wrapping_add(1);
        let time = self.start_unix_ns + t_ns;
        let header = MessageHeader {
            channel_id,
            sequence: self.sequence,
            log_time: time,
            publish_time: time,
        };
        self.writer.write_to_known_channel(&header, &self.buf)
    }

    /// Write one JSON message on a low-rate channel.
    fn write<T: Serialize>(
        &mut self,
        channel: Channel,
        rec: &TickRecord,
        data: T,
    ) -> Result<(), mcap::McapError> {
        self.buf.clear();
        serde_json::to_writer(&mut self.buf, &Stamped::at(rec, data))
            .expect("plain data structs always serialise");
        self.write_buf(self.channels[channel as usize], rec.t_ns)
    }

    /// Add one sample to a high-rate channel's block; write the block when it is full.
    fn gather<T: Serialize>(
        &mut self,
        channel: Channel,
        rec: &TickRecord,
        data: &T,
    ) -> Result<(), mcap::McapError> {
        let full = {
            let pending = self.pending[channel as usize]
                .as_mut()
                .expect("a high-rate channel has a block");
            pending
                .block
                .push(rec.tick, rec.t_ns, data)
                .map_err(block_error)?;
            pending.block.len() >= BLOCK_SAMPLES
        };
        if full {
            self.write_block(channel as usize)?;
        }
        Ok(())
    }

    /// Write the block gathered on channel `index`, if any, stamped with its first sample.
    fn write_block(&mut self, index: usize) -> Result<(), mcap::McapError> {
        let Some(pending) = self.pending[index].as_mut() else {
            return Ok(());
        };
        if pending.block.is_empty() {
            return Ok(());
        }
        let t_ns = pending.block.first_t_ns();
        pending
            .block
            .take_into(&pending.layout, &mut self.buf)
            .map_err(block_error)?;
        self.write_buf(self.channels[index], t_ns)
    }

    /// Write every block gathered so far.
    fn write_blocks(&mut self) -> Result<(), mcap::McapError> {
        (0..CHANNELS.len()).try_for_each(|i| self.write_block(i))
    }

    /// Record one tick on the per-tick channels (vehicle and arm when present), and the
    /// score when `with_score`.
    pub fn write_tick(
        &mut self,
        rec: &TickRecord,
        with_score: bool,
    ) -> Result<(), mcap::McapError> {
        self.gather(Channel::Wheel, rec, &rec.wheel)?;
        if let Some(vehicle) = &rec.vehicle {
            self.gather(Channel::Vehicle, rec, vehicle)?;
        }
        if with_score {
            self.write(Channel::Score, rec, rec.score)?;
        }
        self.gather(Channel::Assist, rec, &rec.assist)?;
        self.gather(Channel::Timing, rec, &rec.timing)?;
        self.gather(Channel::RawWheel, rec, &rec.raw.wheel)?;
        for sample in rec.raw.imu.iter().flatten() {
            self.gather(Channel::RawImu, rec, sample)?;
        }
        if let Some(arm) = &rec.arm {
            self.gather(Channel::Arm, rec, arm)?;
            if rec.t_ns >= self.next_scene_ns {
                self.next_scene_ns = rec.t_ns + self.scene_every_ns;
                if let Some(scene) = arm_scene(arm, self.start_unix_ns + rec.t_ns) {
                    self.buf.clear();
                    scene
                        .encode(&mut self.buf)
                        .map_err(|e| mcap::McapError::Io(std::io::Error::other(e.to_string())))?;
                    self.write_buf(self.scene_channel, rec.t_ns)?;
                }
            }
        }
        Ok(())
    }

    /// Record the arm calibration fitted at the end of the session, stamped with `last`.
    pub fn write_arm_calibration(
        &mut self,
        last: &TickRecord,
        calibration: &ArmCalibrationSample,
    ) -> Result<(), mcap::McapError> {
        self.write(Channel::ArmCalibration, last, calibration)
    }

    /// Record the session's movement measures, stamped with `last`.
    pub fn write_metrics(
        &mut self,
        last: &TickRecord,
        metrics: &MetricsSample,
    ) -> Result<(), mcap::McapError> {
        self.write(Channel::Metrics, last, metrics)
    }

    /// Write the blocks gathered so far, close the current chunk and flush it to the sink, so
    /// a killed process loses at most what came after this call.
    pub fn flush(&mut self) -> Result<(), mcap::McapError> {
        self.write_blocks()?;
        self.writer.flush()
    }

    /// Write the blocks still gathering, the summary section and the footer; returns the sink.
    pub fn finish(mut self) -> Result<W, mcap::McapError> {
        self.write_blocks()?;
        self.writer.finish()?;
        Ok(self.writer.into_inner())
    }
}
