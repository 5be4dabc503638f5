//! The recorder: per-tick records → MCAP (one JSON channel per stream, zstd chunks), thinned
//! summaries → the therapist link, and the loop-timing statistics for the final report.
//!
//! Runs on its own thread; the haptic thread never waits for it in real time.

use crate::session::record::TickRecord;
use crate::timing::TimingStats;
use mcap::records::MessageHeader;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// MCAP topics, one per stream.
pub mod topics {
    /// Wheel angle, velocity and torques, every tick.
    pub const WHEEL: &str = "/wheel";
    /// Car pose, velocities and road position, every tick.
    pub const VEHICLE: &str = "/vehicle";
    /// Running lane score, every 100 ms.
    pub const SCORE: &str = "/score";
    /// Loop timing, every tick.
    pub const TIMING: &str = "/timing";
}

/// Ticks between two score messages and two therapist summaries (100 ms at 1 kHz).
pub const SUMMARY_EVERY_S: f64 = 0.1;

/// A JSON Schema (draft 2020-12) for a flat object of numbers/integers/booleans.
fn json_schema(title: &str, fields: &[Field]) -> String {
    let mut props = serde_json::Map::new();
    for (name, ty, description) in fields {
        props.insert(
            (*name).into(),
            serde_json::json!({ "type": ty, "description": description }),
        );
    }
    let required: Vec<&str> = fields.iter().map(|f| f.0).collect();
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": title,
        "type": "object",
        "properties": props,
        "required": required,
    })
    .to_string()
}

/// A schema field: name, JSON type, description with units.
type Field = (&'static str, &'static str, &'static str);

const COMMON: [Field; 2] = [
    (
        "tick",
        "integer",
        "haptic tick number since the session start",
    ),
    ("t_s", "number", "session time, s"),
];

/// Schemas of the four channels: (topic, schema name, field list).
pub fn channel_schemas() -> Vec<(&'static str, &'static str, String)> {
    fn with_common(fields: &[Field]) -> Vec<Field> {
        let mut all = COMMON.to_vec();
        all.extend_from_slice(fields);
        all
    }
    vec![
        (
            topics::WHEEL,
            "telerehab.Wheel",
            json_schema(
                "telerehab.Wheel",
                &with_common(&[
                    (
                        "angle_rad",
                        "number",
                        "angle read from the device (quantised), rad",
                    ),
                    (
                        "velocity_rad_s",
                        "number",
                        "estimated angular velocity, rad/s",
                    ),
                    (
                        "requested_nm",
                        "number",
                        "haptic torque before the safety chain, N·m",
                    ),
                    ("commanded_nm", "number", "torque sent to the motor, N·m"),
                    ("clipped", "boolean", "the safety chain limited the request"),
                    (
                        "true_angle_rad",
                        "number",
                        "true angle (simulation only), rad",
                    ),
                    ("hand_nm", "number", "simulated patient's hand torque, N·m"),
                    ("target_rad", "number", "angle the patient aims for, rad"),
                ]),
            ),
        ),
        (
            topics::VEHICLE,
            "telerehab.Vehicle",
            json_schema(
                "telerehab.Vehicle",
                &with_common(&[
                    ("x_m", "number", "global x, m"),
                    ("y_m", "number", "global y, m"),
                    ("yaw_rad", "number", "heading, rad"),
                    ("ux_m_s", "number", "forward velocity, m/s"),
                    ("uy_m_s", "number", "lateral velocity, m/s"),
                    ("r_rad_s", "number", "yaw rate, rad/s"),
                    ("steer_rad", "number", "road-wheel angle, rad"),
                    ("front_lateral_n", "number", "front lateral tyre force, N"),
                    ("s_m", "number", "distance along the road, m"),
                    (
                        "lateral_m",
                        "number",
                        "deviation from the road centre, m (left positive)",
                    ),
                ]),
            ),
        ),
        (
            topics::SCORE,
            "telerehab.Score",
            json_schema(
                "telerehab.Score",
                &with_common(&[
                    ("rms_lateral_m", "number", "RMS lateral deviation so far, m"),
                    (
                        "max_lateral_m",
                        "number",
                        "largest |lateral deviation| so far, m",
                    ),
                    (
                        "pct_in_lane",
                        "number",
                        "share of time in the lane so far, %",
                    ),
                ]),
            ),
        ),
        (
            topics::TIMING,
            "telerehab.LoopTiming",
            json_schema(
                "telerehab.LoopTiming",
                &with_common(&[
                    (
                        "lateness_ns",
                        "integer",
                        "tick start after its absolute deadline, ns",
                    ),
                    (
                        "period_ns",
                        "integer",
                        "wall time since the previous tick, ns",
                    ),
                    ("work_ns", "integer", "compute time of the tick, ns"),
                    (
                        "dropped_records",
                        "integer",
                        "records dropped so far (ring full)",
                    ),
                ]),
            ),
        ),
    ]
}

#[derive(Serialize)]
struct Stamped<'a, T: Serialize> {
    tick: u64,
    t_s: f64,
    #[serde(flatten)]
    data: &'a T,
}

/// An MCAP file being written.
pub struct McapRecorder {
    writer: mcap::Writer<BufWriter<File>>,
    channels: [u16; 4],
    sequence: u32,
    start_unix_ns: u64,
    path: PathBuf,
    buf: Vec<u8>,
}

/// A recorder problem.
#[derive(Debug, thiserror::Error)]
pub enum RecorderError {
    /// The file could not be created or written.
    #[error("recording {path}: {source}")]
    Io {
        /// The MCAP file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The MCAP library refused.
    #[error("recording {path}: {source}")]
    Mcap {
        /// The MCAP file.
        path: String,
        /// Why.
        source: mcap::McapError,
    },
}

impl McapRecorder {
    /// Create `path` and register the channels. `start_unix_ns` anchors log times.
    pub fn create(
        path: &Path,
        start_unix_ns: u64,
        metadata: &BTreeMap<String, String>,
    ) -> Result<Self, RecorderError> {
        let p = path.display().to_string();
        let file = File::create(path).map_err(|source| RecorderError::Io {
            path: p.clone(),
            source,
        })?;
        let mcap_err = |source| RecorderError::Mcap {
            path: p.clone(),
            source,
        };
        let mut writer = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Zstd))
            .profile("")
            .library(concat!("telerehab ", env!("CARGO_PKG_VERSION")))
            .chunk_size(Some(1024 * 1024))
            .create(BufWriter::new(file))
            .map_err(mcap_err)?;
        let mut channels = [0u16; 4];
        for (i, (topic, name, schema)) in channel_schemas().into_iter().enumerate() {
            let schema_id = writer
                .add_schema(name, "jsonschema", schema.as_bytes())
                .map_err(mcap_err)?;
            channels[i] = writer
                .add_channel(schema_id, topic, "json", &BTreeMap::new())
                .map_err(mcap_err)?;
        }
        writer
            .write_metadata(&mcap::records::Metadata {
                name: "session".into(),
                metadata: metadata.clone(),
            })
            .map_err(mcap_err)?;
        Ok(Self {
            writer,
            channels,
            sequence: 0,
            start_unix_ns,
            path: path.to_path_buf(),
            buf: Vec::with_capacity(512),
        })
    }

    fn err(&self, source: mcap::McapError) -> RecorderError {
        RecorderError::Mcap {
            path: self.path.display().to_string(),
            source,
        }
    }

    fn write<T: Serialize>(
        &mut self,
        channel: usize,
        rec: &TickRecord,
        data: &T,
    ) -> Result<(), RecorderError> {
        self.buf.clear();
        let msg = Stamped {
            tick: rec.tick,
            t_s: rec.t_ns as f64 * 1e-9,
            data,
        };
        serde_json::to_writer(&mut self.buf, &msg).expect("plain numeric structs always serialise");
        self.sequence = self.sequence.wrapping_add(1);
        let time = self.start_unix_ns + rec.t_ns;
        let header = MessageHeader {
            channel_id: self.channels[channel],
            sequence: self.sequence,
            log_time: time,
            publish_time: time,
        };
        let buf = std::mem::take(&mut self.buf);
        let res = self
            .writer
            .write_to_known_channel(&header, &buf)
            .map_err(|e| self.err(e));
        self.buf = buf;
        res
    }

    /// Record one tick on the per-tick channels, and the score when `with_score`.
    pub fn record(&mut self, rec: &TickRecord, with_score: bool) -> Result<(), RecorderError> {
        self.write(0, rec, &rec.wheel)?;
        self.write(1, rec, &rec.vehicle)?;
        if with_score {
            self.write(2, rec, &rec.score)?;
        }
        self.write(3, rec, &rec.timing)
    }

    /// Close the current chunk and flush it to disk, so a killed process loses at most what
    /// came after this call.
    pub fn flush(&mut self) -> Result<(), RecorderError> {
        self.writer.flush().map_err(|e| self.err(e))
    }

    /// Write the summary section and close the file; returns its size in bytes.
    pub fn finish(mut self) -> Result<u64, RecorderError> {
        self.writer.finish().map_err(|e| self.err(e))?;
        let path = self.path.clone();
        drop(self.writer);
        std::fs::metadata(&path)
            .map(|m| m.len())
            .map_err(|source| RecorderError::Io {
                path: path.display().to_string(),
                source,
            })
    }
}

/// What the recorder hands back when the session ends.
#[derive(Debug, Default)]
pub struct RecorderOutcome {
    /// Records received from the haptic thread.
    pub records: u64,
    /// Loop timing statistics.
    pub timing: TimingStats,
    /// Last record (final score, pose).
    pub last: TickRecord,
    /// Largest |commanded torque|, N·m.
    pub max_abs_torque_nm: f64,
    /// Size of the finished MCAP file, bytes (None without recording).
    pub mcap_bytes: Option<u64>,
    /// The first recording error, if any (recording stops, the session goes on).
    pub error: Option<String>,
}
