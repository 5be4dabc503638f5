//! What the therapist's console draws of a session, live and replayed: the same named numbers
//! per instant (`live_pose`), sent in every live summary's `extra` and, for a replay, read
//! from the session's recording at [`REPLAY_RATE_HZ`] ([`replay_ndjson`], which the hub
//! streams for `GET /api/sessions/{id}/replay`).

use crate::{Channel, TickRecord, TickStream};
use std::collections::BTreeMap;

/// Frames per second of session time in a replay (the live view's summaries come at 10 Hz).
pub const REPLAY_RATE_HZ: f64 = 20.0;

/// What the therapist's live view draws at the summary's tick: the wheel and its target, the
/// torque against its ceiling, the car on the road, the joint angles, and the arm's pose in
/// the wheel frame (grip point and segment directions, with the segment lengths the station
/// was set up with). About 30 numbers, some 1 KB of JSON a summary: 10 KB/s at 10 Hz.
pub fn live_pose(rec: &TickRecord, arm_lengths_m: [f64; 2]) -> Vec<(String, f64)> {
    let mut v: Vec<(String, f64)> = vec![
        ("wheel_angle_rad".into(), rec.wheel.angle_rad),
        ("wheel_target_rad".into(), rec.wheel.target_rad),
        ("torque_nm".into(), rec.wheel.commanded_nm),
        ("ceiling_nm".into(), rec.wheel.ceiling_nm),
        ("safety_scale".into(), rec.wheel.safety_scale),
        ("assist_torque_nm".into(), rec.assist.torque_nm),
        ("paused".into(), f64::from(u8::from(rec.score.paused))),
        (
            "watchdog_fault".into(),
            f64::from(u8::from(rec.wheel.watchdog.is_fault())),
        ),
    ];
    if let Some(car) = &rec.vehicle {
        v.extend([
            ("car_x_m".into(), car.x_m),
            ("car_y_m".into(), car.y_m),
            ("car_yaw_rad".into(), car.yaw_rad),
        ]);
    }
    if let Some(arm) = &rec.arm {
        let deg = |name: &str, rad: f64| (format!("{name}_deg"), rad.to_degrees());
        v.extend([
            deg("shoulder_elevation", arm.shoulder_elevation_rad),
            deg("shoulder_plane", arm.shoulder_plane_rad),
            deg("shoulder_rotation", arm.shoulder_rotation_rad),
            deg("elbow_flexion", arm.elbow_flexion_rad),
            deg("forearm_pronation", arm.forearm_pronation_rad),
            ("upper_arm_m".into(), arm_lengths_m[0]),
            ("forearm_m".into(), arm_lengths_m[1]),
        ]);
        for (name, xyz) in [
            ("upper_axis", arm.upper_axis),
            ("fore_axis", arm.fore_axis),
            ("grip_m", arm.grip_m),
        ] {
            for (axis, x) in ["x", "y", "z"].iter().zip(xyz) {
                v.push((format!("{name}_{axis}"), x));
            }
        }
    }
    v
}

/// Most frames in a replay: past this the frame rate halves (an hour of a 1 kHz session
/// replays at 10 frames/s), so a replay's answer stays under some 15 MB whatever the length.
pub const MAX_REPLAY_FRAMES: usize = 40_000;

/// The channels a replay draws from (the rest of the recording is skipped unparsed).
pub const REPLAY_CHANNELS: [Channel; 4] = [
    Channel::Vehicle,
    Channel::Score,
    Channel::Assist,
    Channel::Arm,
];

/// The frames of the recording read by `stream`, at most `max_frames` of them, as one JSON
/// answer: `{"rate_hz", "duration_s", "exercise", "columns": {name: [value or null, …]}}`.
/// What the streamed lines of [`replay_ndjson`] must add up to (the tests' reference; the hub
/// never holds a whole replay).
#[cfg(test)]
fn replay_frames_of<R: std::io::Read>(
    stream: TickStream<R>,
    max_frames: usize,
) -> Result<Vec<u8>, String> {
    let meta = stream.metadata().clone();
    let lengths = arm_lengths_m(&meta.config_toml);
    let mut every = ((meta.loop_rate_hz / REPLAY_RATE_HZ).round() as usize).max(1);
    let mut frames = Frames::default();
    for (i, rec) in stream.enumerate() {
        let rec = rec.map_err(|e| e.to_string())?;
        if i % every != 0 {
            continue;
        }
        frames.push(&rec, lengths);
        if frames.len > max_frames.max(1) {
            frames.keep_every_other();
            every *= 2;
        }
    }
    #[derive(serde::Serialize)]
    struct Replay<'a> {
        rate_hz: f64,
        duration_s: f64,
        exercise: &'a str,
        columns: &'a BTreeMap<String, Vec<Option<f32>>>,
    }
    serde_json::to_vec(&Replay {
        rate_hz: meta.loop_rate_hz / every as f64,
        duration_s: frames
            .columns
            .get("t_s")
            .and_then(|t| t.last().copied().flatten())
            .map_or(0.0, f64::from),
        exercise: &meta.exercise,
        columns: &frames.columns,
    })
    .map_err(|e| e.to_string())
}

/// Frames in the first line of frames a streamed replay sends: one second of session time,
/// so that the console draws at once.
pub const FIRST_CHUNK_FRAMES: usize = 20;

/// Frames in each later line of frames of a streamed replay.
pub const CHUNK_FRAMES: usize = 1000;

/// The frames of the recording read by `stream` at [`REPLAY_RATE_HZ`] (halved past `max_frames`), given
/// as they are made, as NDJSON lines (each ending in `\n`) handed to `send` (which answers
/// whether to go on: `false` when the reader has gone):
/// - first `{"exercise", "loop_rate_hz", "rate_hz", "expected_duration_s"}` (the duration the
///   recorded configuration asked for, 0 if unknown);
/// - then `{"frames": n, "columns": {name: [value or null, …]}}`, `n` frames more, each column
///   `n` long (a name absent from a line: null in all its frames);
/// - `{"rate_hz"}` when the frames passed `max_frames`: the rate halves, and the frames sent
///   so far are to be thinned to their even ones (0, 2, 4, …), as the server has;
/// - last `{"end": true, "duration_s", "rate_hz", "total_frames"}`, or `{"error"}` if the file
///   turns out damaged part-way.
///
/// Memory is one line's frames, whatever the recording's length.
pub fn replay_ndjson<R: std::io::Read>(
    stream: TickStream<R>,
    max_frames: usize,
    mut send: impl FnMut(Vec<u8>) -> bool,
) -> bool {
    let meta = stream.metadata().clone();
    let lengths = arm_lengths_m(&meta.config_toml);
    let line = |v: serde_json::Value| ndjson_line(&v);
    let mut every = ((meta.loop_rate_hz / REPLAY_RATE_HZ).round() as usize).max(1);
    let rate = |every: usize| meta.loop_rate_hz / every as f64;
    if !send(line(serde_json::json!({
        "exercise": meta.exercise,
        "loop_rate_hz": meta.loop_rate_hz,
        "rate_hz": rate(every),
        "expected_duration_s": expected_duration_s(&meta.config_toml),
    }))) {
        return false;
    }
    let (mut held, mut chunk) = (0usize, Frames::default());
    let mut last_t_s = 0.0;
    let flush = |chunk: &mut Frames, send: &mut dyn FnMut(Vec<u8>) -> bool| {
        if chunk.len == 0 {
            return true;
        }
        /// A line of frames (the values written as the `f32` they are).
        #[derive(serde::Serialize)]
        struct Chunk<'a> {
            frames: usize,
            columns: &'a BTreeMap<String, Vec<Option<f32>>>,
        }
        let taken = std::mem::take(chunk);
        let chunk = Chunk {
            frames: taken.len,
            columns: &taken.columns,
        };
        send(ndjson_line(&chunk))
    };
    for (i, rec) in stream.enumerate() {
        let rec = match rec {
            Ok(rec) => rec,
            Err(e) => {
                return flush(&mut chunk, &mut send)
                    && send(line(serde_json::json!({"error": e.to_string()})));
            }
        };
        if i % every != 0 {
            continue;
        }
        chunk.push(&rec, lengths);
        last_t_s = rec.t_ns as f64 * 1e-9;
        held += 1;
        if held > max_frames.max(1) {
            every *= 2;
            held = held.div_ceil(2);
            if !(flush(&mut chunk, &mut send)
                && send(line(serde_json::json!({"rate_hz": rate(every)}))))
            {
                return false;
            }
        }
        let size = if held <= FIRST_CHUNK_FRAMES {
            FIRST_CHUNK_FRAMES
        } else {
            CHUNK_FRAMES
        };
        if chunk.len >= size && !flush(&mut chunk, &mut send) {
            return false;
        }
    }
    let duration_s = f64::from(last_t_s as f32);
    flush(&mut chunk, &mut send)
        && send(line(serde_json::json!({
            "end": true,
            "duration_s": duration_s,
            "rate_hz": rate(every),
            "total_frames": held,
        })))
}

/// `value` as one NDJSON line: its JSON and `\n`.
fn ndjson_line(value: &impl serde::Serialize) -> Vec<u8> {
    let mut bytes = serde_json::to_vec(value).unwrap_or_default();
    bytes.push(b'\n');
    bytes
}

/// The session length a recorded station configuration asked for, s (`[session]
/// duration_s`, read leniently; 0 if absent).
fn expected_duration_s(config_toml: &str) -> f64 {
    let table: toml::Table = config_toml.parse().unwrap_or_default();
    table
        .get("session")
        .and_then(|s| s.get("duration_s"))
        .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or(0.0)
}

/// The patient's segment lengths `[upper arm, forearm]` (m) in a recorded station
/// configuration, read leniently: only `[arm.geometry]` is looked at, so a configuration
/// written by an older or newer station (renamed or unknown fields elsewhere) still replays;
/// a length absent or not a positive number is the default geometry's.
pub fn arm_lengths_m(config_toml: &str) -> [f64; 2] {
    let default = gyro_imu::arm::ArmGeometry::default();
    let table: toml::Table = config_toml.parse().unwrap_or_default();
    let geometry = table
        .get("arm")
        .and_then(|arm| arm.get("geometry"))
        .and_then(toml::Value::as_table);
    let length = |name: &str, default_m: f64| {
        geometry
            .and_then(|g| g.get(name))
            .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
            .filter(|m| m.is_finite() && *m > 0.0)
            .unwrap_or(default_m)
    };
    [
        length("upper_arm_m", default.upper_arm_m),
        length("forearm_m", default.forearm_m),
    ]
}

/// A replay's frames as columns by name (`None`: absent at that frame, or not finite).
#[derive(Default)]
struct Frames {
    columns: BTreeMap<String, Vec<Option<f32>>>,
    len: usize,
}

impl Frames {
    fn push(&mut self, rec: &TickRecord, lengths: [f64; 2]) {
        let mut values = live_pose(rec, lengths);
        values.push(("t_s".into(), rec.t_ns as f64 * 1e-9));
        values.push(("pct_in_lane".into(), rec.score.pct_in_lane));
        // Which exercise of the course runs: the replay's timeline marks where each starts.
        values.push(("exercise_index".into(), f64::from(rec.score.exercise_index)));
        if let Some(v) = &rec.vehicle {
            values.push(("lateral_m".into(), v.lateral_m));
        }
        let i = self.len;
        for (name, value) in values {
            let column = self.columns.entry(name).or_default();
            column.resize(i, None);
            column.push(value.is_finite().then_some(value as f32));
        }
        self.len += 1;
        for column in self.columns.values_mut() {
            column.resize(self.len, None);
        }
    }

    /// Halves the frame rate: keeps frames 0, 2, 4, ….
    #[cfg(test)]
    fn keep_every_other(&mut self) {
        for column in self.columns.values_mut() {
            let mut i = 0;
            column.retain(|_| {
                i += 1;
                i % 2 == 1
            });
        }
        self.len = self.len.div_ceil(2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ArmSample, StreamLimits, VehicleSample};

    #[test]
    fn the_live_pose_names_the_arm_only_when_there_is_one() {
        let mut rec = TickRecord::default();
        let names = |rec: &TickRecord| -> Vec<String> {
            live_pose(rec, [0.3, 0.33])
                .into_iter()
                .map(|(n, _)| n)
                .collect()
        };
        assert!(!names(&rec).iter().any(|n| n.starts_with("grip_m")));
        rec.arm = Some(ArmSample::default());
        rec.vehicle = Some(VehicleSample::default());
        let with_arm = names(&rec);
        for n in [
            "grip_m_x",
            "fore_axis_z",
            "upper_arm_m",
            "elbow_flexion_deg",
            "car_yaw_rad",
        ] {
            assert!(with_arm.iter().any(|m| m == n), "{n} in {with_arm:?}");
        }
        // Within netlink's limit of extra entries, with the live measures beside them.
        assert!(with_arm.len() <= 40, "{}", with_arm.len());
    }

    /// A recording of `seconds` at 1 kHz, the car on the road throughout.
    fn recording(seconds: u64) -> Vec<u8> {
        use crate::{RecordWriter, SessionMetadata, VehicleSample};
        let meta = SessionMetadata {
            loop_rate_hz: 1000.0,
            exercise: "sine-road".into(),
            config_toml: "[arm.geometry]\nupper_arm_m = 0.31\nforearm_m = 0.29\n\n[a_section_renamed_since]\nx = 1\n".into(),
            ..Default::default()
        };
        let mut w = RecordWriter::new(std::io::Cursor::new(Vec::new()), 0, &meta).unwrap();
        for tick in 0..seconds * 1000 {
            let mut rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                vehicle: Some(VehicleSample::default()),
                ..Default::default()
            };
            rec.wheel.angle_rad = (tick as f64 * 1e-3).sin();
            // A course of one exercise a second.
            rec.score.exercise_index = (tick / 1000) as u32;
            w.write_tick(&rec, tick % 100 == 0).unwrap();
        }
        w.finish().unwrap().into_inner()
    }

    fn frames(bytes: Vec<u8>, max_frames: usize) -> serde_json::Value {
        let stream =
            TickStream::from_bytes(bytes, StreamLimits::default(), &REPLAY_CHANNELS).unwrap();
        serde_json::from_slice(&replay_frames_of(stream, max_frames).unwrap()).unwrap()
    }

    #[test]
    fn a_replay_has_20_frames_a_second_of_every_drawn_value() {
        let r = frames(recording(3), MAX_REPLAY_FRAMES);
        assert_eq!(r["rate_hz"], 20.0);
        assert_eq!(r["exercise"], "sine-road");
        let columns = r["columns"].as_object().unwrap();
        for name in [
            "t_s",
            "wheel_angle_rad",
            "car_x_m",
            "lateral_m",
            "pct_in_lane",
        ] {
            assert_eq!(columns[name].as_array().unwrap().len(), 60, "{name}");
        }
        let index: Vec<f64> = columns["exercise_index"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(
            (index[0], index[19], index[20], index[59]),
            (0.0, 0.0, 1.0, 2.0)
        );
        let angle = columns["wheel_angle_rad"][20].as_f64().unwrap();
        assert!((angle - 1f64.sin()).abs() < 1e-3, "{angle}");
        assert!((r["duration_s"].as_f64().unwrap() - 2.95).abs() < 1e-6);
    }

    #[test]
    fn the_arm_lengths_are_read_from_a_configuration_of_any_version() {
        let r = frames(recording(1), MAX_REPLAY_FRAMES);
        assert_eq!(r["exercise"], "sine-road");
        assert_eq!(
            arm_lengths_m("[arm.geometry]\nupper_arm_m = 0.31\nforearm_m = 0.29\n[zz]\nq=1"),
            [0.31, 0.29]
        );
        let default = gyro_imu::arm::ArmGeometry::default();
        let defaults = [default.upper_arm_m, default.forearm_m];
        assert_eq!(arm_lengths_m("not toml at all ["), defaults);
        assert_eq!(
            arm_lengths_m("[arm.geometry]\nupper_arm_m = -1\n"),
            defaults
        );
    }

    /// The lines of [`replay_ndjson`] put together as the console does, in the shape of
    /// [`replay_frames_of`]'s answer; and how many lines of frames came.
    fn assembled(bytes: Vec<u8>, max_frames: usize) -> (serde_json::Value, usize) {
        let stream =
            TickStream::from_bytes(bytes, StreamLimits::default(), &REPLAY_CHANNELS).unwrap();
        let mut lines = Vec::new();
        assert!(replay_ndjson(stream, max_frames, |l| {
            assert_eq!(l.last(), Some(&b'\n'));
            lines.push(serde_json::from_slice::<serde_json::Value>(&l).unwrap());
            true
        }));
        let (mut columns, mut n, mut chunks) = (serde_json::Map::new(), 0, 0);
        let mut answer = serde_json::json!({"exercise": lines[0]["exercise"]});
        for line in &lines[1..] {
            if let Some(k) = line["frames"].as_u64() {
                chunks += 1;
                for (name, values) in line["columns"].as_object().unwrap() {
                    let column = columns.entry(name.clone()).or_insert(serde_json::json!([]));
                    let column = column.as_array_mut().unwrap();
                    column.resize(n, serde_json::Value::Null);
                    column.extend(values.as_array().unwrap().iter().cloned());
                }
                n += k as usize;
                for column in columns.values_mut() {
                    column
                        .as_array_mut()
                        .unwrap()
                        .resize(n, serde_json::Value::Null);
                }
            } else if line.get("end").is_some() {
                answer["rate_hz"] = line["rate_hz"].clone();
                answer["duration_s"] = line["duration_s"].clone();
                assert_eq!(line["total_frames"], n);
            } else {
                for column in columns.values_mut() {
                    let mut i = 0;
                    column.as_array_mut().unwrap().retain(|_| {
                        i += 1;
                        i % 2 == 1
                    });
                }
                n = n.div_ceil(2);
            }
        }
        answer["columns"] = serde_json::Value::Object(columns);
        (answer, chunks)
    }

    #[test]
    fn a_streamed_replay_puts_together_into_the_whole_answer_halvings_included() {
        for (seconds, max_frames) in [(3, MAX_REPLAY_FRAMES), (30, 100), (7, 25)] {
            let bytes = recording(seconds);
            let whole = frames(bytes.clone(), max_frames);
            let (streamed, chunks) = assembled(bytes, max_frames);
            assert_eq!(streamed, whole, "{seconds} s, at most {max_frames} frames");
            assert!(chunks >= 2, "the first second is sent on its own");
        }
    }

    #[test]
    fn a_long_replay_halves_its_frame_rate_to_stay_within_the_frame_limit() {
        // 30 s at 20 frames/s is 600 frames; at most 100: 2.5 frames/s, 75 frames.
        let r = frames(recording(30), 100);
        assert_eq!(r["rate_hz"], 2.5);
        let t = r["columns"]["t_s"].as_array().unwrap();
        assert_eq!(t.len(), 75);
        assert_eq!(t[1].as_f64().unwrap(), 0.4);
        assert!((r["duration_s"].as_f64().unwrap() - 29.6).abs() < 1e-4);
    }
}
