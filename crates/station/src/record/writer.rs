//! The MCAP writer: one JSON channel per stream, zstd chunks, the session metadata record.
//!
//! Generic over any `Write + Seek` sink (a buffered file for a session, a `Cursor<Vec<u8>>`
//! in tests); it knows nothing of paths, threads or clocks.

use super::channels::{CHANNELS, Channel, MESSAGE_ENCODING, SCHEMA_ENCODING};
use super::types::{ArmCalibrationSample, MetricsSample, SessionMetadata, Stamped, TickRecord};
use mcap::records::MessageHeader;
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

/// Uncompressed bytes per chunk (about a second of a session at 1 kHz).
const CHUNK_BYTES: u64 = 1024 * 1024;

/// The MCAP writer settings of every file the station writes (sessions and recoveries);
/// `library` names the writer in the file header.
pub fn mcap_options(library: &str) -> mcap::WriteOptions {
    mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .profile("")
        .library(library)
        .chunk_size(Some(CHUNK_BYTES))
}

/// A recording being written to `W`.
pub struct RecordWriter<W: Write + Seek> {
    writer: mcap::Writer<W>,
    channels: [u16; CHANNELS.len()],
    sequence: u32,
    start_unix_ns: u64,
    buf: Vec<u8>,
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
        for (id, spec) in channels.iter_mut().zip(&CHANNELS) {
            let schema = spec.schema().to_string();
            let schema_id =
                writer.add_schema(spec.schema_name, SCHEMA_ENCODING, schema.as_bytes())?;
            *id = writer.add_channel(schema_id, spec.topic, MESSAGE_ENCODING, &BTreeMap::new())?;
        }
        writer.write_metadata(&mcap::records::Metadata {
            name: SessionMetadata::NAME.into(),
            metadata: metadata.to_map(),
        })?;
        Ok(Self {
            writer,
            channels,
            sequence: 0,
            start_unix_ns,
            buf: Vec::with_capacity(512),
        })
    }

    fn write<T: Serialize>(
        &mut self,
        channel: Channel,
        rec: &TickRecord,
        data: T,
    ) -> Result<(), mcap::McapError> {
        self.buf.clear();
        serde_json::to_writer(&mut self.buf, &Stamped::at(rec, data))
            .expect("plain data structs always serialise");
        self.sequence = self.sequence.wrapping_add(1);
        let time = self.start_unix_ns + rec.t_ns;
        let header = MessageHeader {
            channel_id: self.channels[channel as usize],
            sequence: self.sequence,
            log_time: time,
            publish_time: time,
        };
        self.writer.write_to_known_channel(&header, &self.buf)
    }

    /// Record one tick on the per-tick channels (vehicle and arm when present), and the
    /// score when `with_score`.
    pub fn write_tick(
        &mut self,
        rec: &TickRecord,
        with_score: bool,
    ) -> Result<(), mcap::McapError> {
        self.write(Channel::Wheel, rec, rec.wheel)?;
        if let Some(vehicle) = rec.vehicle {
            self.write(Channel::Vehicle, rec, vehicle)?;
        }
        if with_score {
            self.write(Channel::Score, rec, rec.score)?;
        }
        self.write(Channel::Assist, rec, rec.assist)?;
        self.write(Channel::Timing, rec, rec.timing)?;
        match rec.arm {
            Some(arm) => self.write(Channel::Arm, rec, arm),
            None => Ok(()),
        }
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

    /// Close the current chunk and flush it to the sink, so a killed process loses at most
    /// what came after this call.
    pub fn flush(&mut self) -> Result<(), mcap::McapError> {
        self.writer.flush()
    }

    /// Write the summary section and the footer; returns the sink.
    pub fn finish(mut self) -> Result<W, mcap::McapError> {
        self.writer.finish()?;
        Ok(self.writer.into_inner())
    }
}
