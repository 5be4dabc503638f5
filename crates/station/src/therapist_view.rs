//! What the therapist's console draws of a session, live and replayed: the same named numbers
//! per instant (`live_pose`), sent in every live summary's `extra` and, for a replay, read
//! from the session's recording at [`REPLAY_RATE_HZ`] (`replay_frames`, which the hub calls
//! for `GET /api/sessions/{id}/replay`).

use crate::config::StationConfig;
use crate::record::{Recording, TickRecord};
use std::collections::BTreeMap;
use std::path::Path;

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

/// The recording at `path` as the console's replay draws it: `{"rate_hz", "duration_s",
/// "columns": {name: [value or null, …]}}`, one entry per frame at [`REPLAY_RATE_HZ`], the
/// names of [`live_pose`] plus `t_s`, `lateral_m` and `pct_in_lane`.
pub fn replay_frames(path: &Path) -> Result<serde_json::Value, String> {
    let recording = Recording::open(path).map_err(|e| e.to_string())?;
    let meta = &recording.metadata;
    let config = StationConfig::from_toml(&meta.config_toml, "the recording's configuration")
        .map_err(|e| e.to_string())?;
    let lengths = [
        config.arm.geometry.upper_arm_m,
        config.arm.geometry.forearm_m,
    ];
    let every = ((meta.loop_rate_hz / REPLAY_RATE_HZ).round() as usize).max(1);
    let frames: Vec<TickRecord> = recording.ticks().step_by(every).collect();
    let mut columns: BTreeMap<String, Vec<Option<f64>>> = BTreeMap::new();
    for (i, rec) in frames.iter().enumerate() {
        let mut values = live_pose(rec, lengths);
        values.push(("t_s".into(), rec.t_ns as f64 * 1e-9));
        values.push(("pct_in_lane".into(), rec.score.pct_in_lane));
        if let Some(v) = &rec.vehicle {
            values.push(("lateral_m".into(), v.lateral_m));
        }
        for (name, value) in values {
            let column = columns.entry(name).or_insert_with(|| vec![None; i]);
            column.resize(i, None);
            column.push(value.is_finite().then_some(value));
        }
    }
    for column in columns.values_mut() {
        column.resize(frames.len(), None);
    }
    let duration_s = frames.last().map_or(0.0, |r| r.t_ns as f64 * 1e-9);
    Ok(serde_json::json!({
        "rate_hz": meta.loop_rate_hz / every as f64,
        "duration_s": duration_s,
        "exercise": meta.exercise,
        "columns": columns,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{ArmSample, VehicleSample};

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
}
