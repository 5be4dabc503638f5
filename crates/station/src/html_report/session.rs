//! One recorded session as the report shows it: its series in the units a therapist reads
//! (degrees, N·m, m), its movements and its measures.

use crate::session::measures::MeasureCollector;
use anyhow::Context;
use record::{ArmSetup, Recording};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A session read for the report.
pub struct SessionData {
    /// Its file.
    pub path: PathBuf,
    /// When it started, ns since the Unix epoch (the first message's log time).
    pub start_unix_ns: u64,
    /// Exercise (or the regimen's first) and seed, from the recording's metadata.
    pub exercise: String,
    /// The session's seed.
    pub seed: u64,
    /// Patient (pseudonym or id) from the recording's metadata.
    pub patient: String,
    /// The wheel's angle, (s, °).
    pub wheel_deg: Vec<(f64, f64)>,
    /// The target angle, (s, °).
    pub target_deg: Vec<(f64, f64)>,
    /// Lateral deviation from the lane centre, (s, m); empty without the road.
    pub lateral_m: Vec<(f64, f64)>,
    /// Torque commanded to the motor, (s, N·m).
    pub torque_nm: Vec<(f64, f64)>,
    /// Assist torque, (s, N·m).
    pub assist_nm: Vec<(f64, f64)>,
    /// Shoulder elevation and elbow flexion while tracked, (s, °).
    pub shoulder_deg: Vec<(f64, f64)>,
    /// Elbow flexion while tracked, (s, °).
    pub elbow_deg: Vec<(f64, f64)>,
    /// The wheel's speed (the measures' speed profile), (s, °/s).
    pub speed_deg_s: Vec<(f64, f64)>,
    /// The wheel's movements found at the session's end, (start s, end s).
    pub movements: Vec<(f64, f64)>,
    /// Every measure by name (the recording's `/metrics`).
    pub measures: BTreeMap<String, f64>,
}

/// Reads the recording at `path`.
pub fn read(path: &Path) -> anyhow::Result<SessionData> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let rec = Recording::from_bytes(&bytes)
        .with_context(|| format!("{} is not a readable recording", path.display()))?;
    let start_unix_ns = mcap::Summary::read(&bytes)
        .ok()
        .flatten()
        .and_then(|s| s.stats)
        .map_or(0, |s| s.message_start_time);
    let deg = f64::to_degrees;
    let wheel = |f: fn(&record::WheelSample) -> f64| {
        rec.wheel
            .iter()
            .map(|m| (m.t_s, f(&m.data)))
            .collect::<Vec<_>>()
    };
    let tracked = rec
        .arm
        .iter()
        .filter(|m| m.data.setup == ArmSetup::Tracking);
    let metrics = rec.metrics.last().map(|m| &m.data);
    let speed_deg_s = speed_profile(&rec);
    Ok(SessionData {
        path: path.to_path_buf(),
        start_unix_ns,
        exercise: rec.metadata.exercise.clone(),
        seed: rec.metadata.seed,
        patient: rec.metadata.patient_id.clone(),
        wheel_deg: wheel(|w| w.angle_rad.to_degrees()),
        target_deg: wheel(|w| w.target_rad.to_degrees()),
        lateral_m: rec
            .vehicle
            .iter()
            .map(|m| (m.t_s, m.data.lateral_m))
            .collect(),
        torque_nm: wheel(|w| w.commanded_nm),
        assist_nm: rec
            .assist
            .iter()
            .map(|m| (m.t_s, m.data.torque_nm))
            .collect(),
        shoulder_deg: tracked
            .clone()
            .map(|m| (m.t_s, deg(m.data.shoulder_elevation_rad)))
            .collect(),
        elbow_deg: tracked
            .map(|m| (m.t_s, deg(m.data.elbow_flexion_rad)))
            .collect(),
        speed_deg_s,
        movements: metrics.map_or_else(Vec::new, |m| {
            m.movements
                .iter()
                .map(|mv| (mv.start_s, mv.start_s + mv.duration_s))
                .collect()
        }),
        measures: metrics.map(|m| m.measures.clone()).unwrap_or_default(),
    })
}

/// The wheel's speed as the session's measures saw it (the exercise only, paused stretches
/// left out, a NaN between runs so the chart breaks there), in °/s: the recorded ticks run
/// through the station's own collector.
fn speed_profile(rec: &Recording) -> Vec<(f64, f64)> {
    let mut collector = MeasureCollector::new(rec.metadata.loop_rate_hz, rec.wheel.len() as u64);
    // The score (with the pause) is recorded every 100 ms: before its first message the
    // exercise was as that message says.
    let first = rec.score.first().map(|m| (m.tick, m.data));
    for mut tick in rec.ticks() {
        if let Some((_, score)) = first.filter(|(at, _)| tick.tick < *at) {
            tick.score = score;
        }
        collector.add(&tick);
    }
    let mut points = Vec::new();
    // In memory: the series cannot be lost.
    for run in collector.speed_series().unwrap_or_default() {
        if let Some(&(t, _)) = run.last() {
            points.extend(run.iter().map(|&(t, v)| (t, v.to_degrees())));
            points.push((t, f64::NAN));
        }
    }
    points
}
