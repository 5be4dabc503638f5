//! The recorder: per-tick records → MCAP (one JSON channel per stream, zstd chunks), thinned
//! summaries → the therapist link, and the loop-timing statistics for the final report.
//!
//! Runs on its own thread; the haptic thread never waits for it in real time.

use crate::arm_calibration::ArmCalibrationSample;
use crate::session::record::{
    ArmSample, AssistSample, ScoreSample, TickRecord, TimingSample, VehicleSample, WheelSample,
};
use crate::timing::TimingStats;
use mcap::records::MessageHeader;
use schemars::JsonSchema;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// MCAP topics, one per stream.
pub mod topics {
    /// Wheel angle, velocity, torques and safety state, every tick.
    pub const WHEEL: &str = "/wheel";
    /// Car pose, velocities and road position, every tick.
    pub const VEHICLE: &str = "/vehicle";
    /// Running lane score, every 100 ms.
    pub const SCORE: &str = "/score";
    /// Active assistance, every tick.
    pub const ASSIST: &str = "/assist";
    /// Loop timing, every tick.
    pub const TIMING: &str = "/timing";
    /// Arm pose from the IMUs and raw gyro rates, every tick.
    pub const ARM: &str = "/arm";
    /// The patient's arm calibrated from the session's data, once at the end.
    pub const ARM_CALIBRATION: &str = "/arm_calibration";
}

/// Session time between two score messages and two therapist summaries, s.
pub const SUMMARY_EVERY_S: f64 = 0.1;

/// A message: the tick and session time, then the sample's own fields.
#[derive(Serialize, JsonSchema)]
struct Stamped<T> {
    /// Haptic tick number since the session start.
    tick: u64,
    /// Session time, s.
    t_s: f64,
    #[serde(flatten)]
    data: T,
}

/// JSON Schema (draft 2020-12) of a channel whose messages are `Stamped<T>`.
fn schema_of<T: JsonSchema>(title: &str) -> String {
    let mut schema =
        serde_json::to_value(schemars::schema_for!(Stamped<T>)).expect("schemas serialise");
    schema["title"] = title.into();
    schema.to_string()
}

/// The channels: (topic, schema name, JSON schema), in channel-index order.
pub fn channel_schemas() -> [(&'static str, &'static str, String); CHANNELS] {
    [
        (
            topics::WHEEL,
            "telerehab.Wheel",
            schema_of::<WheelSample>("telerehab.Wheel"),
        ),
        (
            topics::VEHICLE,
            "telerehab.Vehicle",
            schema_of::<VehicleSample>("telerehab.Vehicle"),
        ),
        (
            topics::SCORE,
            "telerehab.Score",
            schema_of::<ScoreSample>("telerehab.Score"),
        ),
        (
            topics::ASSIST,
            "telerehab.Assist",
            schema_of::<AssistSample>("telerehab.Assist"),
        ),
        (
            topics::TIMING,
            "telerehab.LoopTiming",
            schema_of::<TimingSample>("telerehab.LoopTiming"),
        ),
        (
            topics::ARM,
            "telerehab.Arm",
            schema_of::<ArmSample>("telerehab.Arm"),
        ),
        (
            topics::ARM_CALIBRATION,
            "telerehab.ArmCalibration",
            schema_of::<ArmCalibrationSample>("telerehab.ArmCalibration"),
        ),
    ]
}

/// Channels in a recording.
pub const CHANNELS: usize = 7;

/// An MCAP file being written.
pub struct McapRecorder {
    writer: mcap::Writer<BufWriter<File>>,
    channels: [u16; CHANNELS],
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
        let mut channels = [0u16; CHANNELS];
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
        data: T,
    ) -> Result<(), RecorderError> {
        self.buf.clear();
        let msg = Stamped {
            tick: rec.tick,
            t_s: rec.t_ns as f64 * 1e-9,
            data,
        };
        serde_json::to_writer(&mut self.buf, &msg).expect("plain data structs always serialise");
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
        self.write(0, rec, rec.wheel)?;
        if let Some(vehicle) = rec.vehicle {
            self.write(1, rec, vehicle)?;
        }
        if with_score {
            self.write(2, rec, rec.score)?;
        }
        self.write(3, rec, rec.assist)?;
        self.write(4, rec, rec.timing)?;
        match rec.arm {
            Some(arm) => self.write(5, rec, arm),
            None => Ok(()),
        }
    }

    /// Record the arm calibration fitted at the end of the session, stamped with the last tick.
    pub fn record_arm_calibration(
        &mut self,
        last: &TickRecord,
        calibration: &ArmCalibrationSample,
    ) -> Result<(), RecorderError> {
        self.write(6, last, calibration)
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

impl RecorderOutcome {
    /// Account for one tick.
    pub fn add(&mut self, rec: &TickRecord) {
        self.records += 1;
        self.timing.add(
            rec.timing.lateness_ns,
            rec.timing.period_ns,
            rec.timing.work_ns,
        );
        self.max_abs_torque_nm = self.max_abs_torque_nm.max(rec.wheel.commanded_nm.abs());
        self.clipped_ticks += u64::from(rec.wheel.clipped);
        let active = !rec.score.paused;
        self.road_ticks += u64::from(active && rec.vehicle.is_some());
        self.dial_ticks += u64::from(active && rec.vehicle.is_none());
        self.paused_ticks += u64::from(!active);
        self.fault_ticks += u64::from(rec.wheel.watchdog.starts_with("fault"));
        if rec.assist.active {
            self.assist_ticks += 1;
            self.assist_level_sum += rec.assist.assistance_level;
            self.assist_error_sq_sum += rec.assist.error_rad * rec.assist.error_rad;
            self.assist_saturated_ticks += u64::from(rec.assist.saturated);
        }
        self.last = *rec;
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
    /// Ticks on which the safety chain limited the torque.
    pub clipped_ticks: u64,
    /// Ticks spent on road exercises (not paused).
    pub road_ticks: u64,
    /// Ticks spent on the dial task (not paused).
    pub dial_ticks: u64,
    /// Ticks the patient had the exercise paused.
    pub paused_ticks: u64,
    /// Ticks on which the safety supervisor saw a fault (missed deadline, stale reading).
    pub fault_ticks: u64,
    /// Ticks with an active assist controller.
    pub assist_ticks: u64,
    /// Sum of the assistance level over assisted ticks.
    pub assist_level_sum: f64,
    /// Sum of the squared assist tracking error over assisted ticks, rad².
    pub assist_error_sq_sum: f64,
    /// Assisted ticks on which a torque limit cut the assist.
    pub assist_saturated_ticks: u64,
    /// The arm calibrated from this session's data, or why not (None without arm sensing).
    pub arm_calibration: Option<Result<ArmCalibrationSample, String>>,
    /// Size of the finished MCAP file, bytes (None without recording).
    pub mcap_bytes: Option<u64>,
    /// The first recording error, if any (recording stops, the session goes on).
    pub error: Option<String>,
}
