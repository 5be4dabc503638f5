//! The channels of a recording: topic, schema name and JSON schema, in one table.

use super::blocks::{BlockError, Layout};
use super::raw::{RawImuSample, RawWheelSample};
use super::types::{
    ArmCalibrationSample, ArmSample, AssistSample, MetricsSample, ScoreSample, Stamped,
    TimingSample, VehicleSample, WheelSample,
};
use schemars::JsonSchema;
use serde::Serialize;

/// Encoding of the low-rate channels' messages.
pub const MESSAGE_ENCODING: &str = "json";
/// Encoding of the low-rate channels' schemas (JSON Schema, draft 2020-12).
pub const SCHEMA_ENCODING: &str = "jsonschema";
/// Samples per block message of a high-rate channel (0.1 s at 1 kHz).
pub const BLOCK_SAMPLES: usize = 100;

/// One MCAP channel of a recording.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Channel {
    /// Wheel angle, velocity, torques and safety state, every tick ([`WheelSample`]).
    Wheel,
    /// Car pose, velocities and road position, every tick on the road ([`VehicleSample`]).
    Vehicle,
    /// Running score, every 100 ms of session time ([`ScoreSample`]).
    Score,
    /// Active assistance, every tick ([`AssistSample`]).
    Assist,
    /// Loop timing, every tick ([`TimingSample`]).
    Timing,
    /// Arm pose from the IMUs and raw gyro rates, every tick with arm sensing ([`ArmSample`]).
    Arm,
    /// The patient's arm calibrated from the session's data, once at the end
    /// ([`ArmCalibrationSample`]).
    ArmCalibration,
    /// The session's movement measures, once at the end ([`MetricsSample`]).
    Metrics,
    /// The raw inputs of every tick: the wheel's read, the body clock, pause and stop, the
    /// arm tracker's events ([`RawWheelSample`]).
    RawWheel,
    /// Every IMU sample the arm tracker consumed ([`RawImuSample`]).
    RawImu,
}

/// Makes the block layout of a channel from its schema name.
type LayoutOf = fn(&str) -> Result<Layout, BlockError>;

/// What the file says about one channel.
#[derive(Clone, Copy, Debug)]
pub struct ChannelSpec {
    /// The channel.
    pub channel: Channel,
    /// MCAP topic.
    pub topic: &'static str,
    /// Schema name (also the schema's `title`).
    pub schema_name: &'static str,
    /// The message schema without its title.
    schema: fn() -> schemars::Schema,
    /// The block layout of a high-rate channel (recorded in compact blocks, see
    /// [`super::blocks`]); `None` for a low-rate JSON channel.
    block: Option<LayoutOf>,
}

/// Every channel, in the order the writer registers them (`Channel as usize` indexes it).
pub const CHANNELS: [ChannelSpec; 10] = [
    blocks::<WheelSample>(Channel::Wheel, "/wheel", "telerehab.Wheel"),
    blocks::<VehicleSample>(Channel::Vehicle, "/vehicle", "telerehab.Vehicle"),
    spec::<ScoreSample>(Channel::Score, "/score", "telerehab.Score"),
    blocks::<AssistSample>(Channel::Assist, "/assist", "telerehab.Assist"),
    blocks::<TimingSample>(Channel::Timing, "/timing", "telerehab.LoopTiming"),
    blocks::<ArmSample>(Channel::Arm, "/arm", "telerehab.Arm"),
    spec::<ArmCalibrationSample>(
        Channel::ArmCalibration,
        "/arm_calibration",
        "telerehab.ArmCalibration",
    ),
    spec::<MetricsSample>(Channel::Metrics, "/metrics", "telerehab.Metrics"),
    blocks::<RawWheelSample>(Channel::RawWheel, "/raw/wheel", "telerehab.RawWheel"),
    blocks::<RawImuSample>(Channel::RawImu, "/raw/imu", "telerehab.RawImu"),
];

/// A channel whose messages are `Stamped<T>`.
const fn spec<T: JsonSchema>(
    channel: Channel,
    topic: &'static str,
    schema_name: &'static str,
) -> ChannelSpec {
    ChannelSpec {
        channel,
        topic,
        schema_name,
        schema: stamped_schema::<T>,
        block: None,
    }
}

/// A high-rate channel recorded in blocks of `T` samples (message `<schema_name>Block`).
const fn blocks<T: JsonSchema + Serialize + Default>(
    channel: Channel,
    topic: &'static str,
    schema_name: &'static str,
) -> ChannelSpec {
    ChannelSpec {
        block: Some(block_layout::<T>),
        ..spec::<T>(channel, topic, schema_name)
    }
}

/// The layout of message `telerehab.<Name>Block` for schema name `telerehab.<Name>`.
fn block_layout<T: JsonSchema + Serialize + Default>(
    schema_name: &str,
) -> Result<Layout, BlockError> {
    let name = schema_name
        .strip_prefix("telerehab.")
        .unwrap_or(schema_name);
    Layout::of::<T>(&format!("{name}Block"))
}

fn stamped_schema<T: JsonSchema>() -> schemars::Schema {
    schemars::schema_for!(Stamped<T>)
}

impl ChannelSpec {
    /// The block layout of a high-rate channel, `None` for a JSON one.
    pub fn block_layout(&self) -> Option<Result<Layout, BlockError>> {
        self.block.map(|layout| layout(self.schema_name))
    }

    /// The message schema (JSON Schema draft 2020-12), titled with the schema name.
    pub fn schema(&self) -> serde_json::Value {
        let mut schema = serde_json::to_value((self.schema)()).expect("schemas serialise");
        schema["title"] = self.schema_name.into();
        schema
    }
}

impl Channel {
    /// Every channel, in registration order.
    pub const ALL: [Channel; 10] = [
        Channel::Wheel,
        Channel::Vehicle,
        Channel::Score,
        Channel::Assist,
        Channel::Timing,
        Channel::Arm,
        Channel::ArmCalibration,
        Channel::Metrics,
        Channel::RawWheel,
        Channel::RawImu,
    ];

    /// Its row of [`CHANNELS`].
    pub fn spec(self) -> &'static ChannelSpec {
        &CHANNELS[self as usize]
    }

    /// Its MCAP topic.
    pub fn topic(self) -> &'static str {
        self.spec().topic
    }

    /// The channel recorded on `topic`, if it is one of ours.
    pub fn from_topic(topic: &str) -> Option<Self> {
        CHANNELS
            .iter()
            .find(|c| c.topic == topic)
            .map(|c| c.channel)
    }
}

#[cfg(test)]
mod tests {
    use super::{CHANNELS, Channel};
    use std::path::PathBuf;

    #[test]
    fn the_table_is_indexed_by_the_channel() {
        for (i, c) in Channel::ALL.into_iter().enumerate() {
            assert_eq!(CHANNELS[i].channel, c);
            assert_eq!(Channel::from_topic(c.topic()), Some(c));
        }
        assert_eq!(Channel::from_topic("/nope"), None);
    }

    /// Foxglove-family viewers (Lichtblick among them) reject `$ref` and `["number", "null"]`
    /// unions: every schema is inline, and an optional field is left out, not null.
    #[test]
    fn schemas_have_no_refs_and_no_type_unions() {
        fn walk(v: &serde_json::Value, at: &str, bad: &mut Vec<String>) {
            match v {
                serde_json::Value::Object(m) => {
                    for (k, x) in m {
                        let here = format!("{at}/{k}");
                        if k == "$ref" || k == "$defs" || (k == "type" && x.is_array()) {
                            bad.push(here.clone());
                        }
                        walk(x, &here, bad);
                    }
                }
                serde_json::Value::Array(a) => {
                    for (i, x) in a.iter().enumerate() {
                        walk(x, &format!("{at}/{i}"), bad);
                    }
                }
                _ => {}
            }
        }
        let mut bad = Vec::new();
        for spec in &CHANNELS {
            walk(&spec.schema(), spec.schema_name, &mut bad);
        }
        assert!(bad.is_empty(), "refs or type unions at {bad:?}");
    }

    /// Every channel's schema is the checked-in snapshot: a change to the recording format
    /// shows as a diff of `src/snapshots/`.
    #[test]
    fn schemas_match_the_snapshots() {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/snapshots");
        let update = std::env::var_os("UPDATE_SNAPSHOTS").is_some_and(|v| v == "1");
        let mut stale = Vec::new();
        for spec in &CHANNELS {
            let file = dir.join(format!("{}.json", spec.schema_name));
            let mut now = serde_json::to_string_pretty(&spec.schema()).unwrap();
            now.push('\n');
            if update {
                std::fs::write(&file, &now).unwrap();
            } else if std::fs::read_to_string(&file).ok().as_deref() != Some(now.as_str()) {
                stale.push(file.display().to_string());
            }
        }
        assert!(
            stale.is_empty(),
            "the recorded JSON schema changed for {stale:?}; if that is intended, run \
             `UPDATE_SNAPSHOTS=1 cargo test -p record --lib channels` and commit \
             the snapshot diff"
        );
    }
}
