//! One recorded session as the report shows it: its series in the units a therapist reads
//! (degrees, N·m, m), its movements and its measures.

use super::charts::Thinner;
use anyhow::Context;
use measures::MeasureCollector;
use record::{ArmSetup, Channel, StreamLimits, TickRecord, TickStream};
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
    /// Each exercise's own results (empty in recordings made before they were recorded).
    pub exercises: Vec<record::ExerciseResult>,
    /// How the session ended, as its `Bye` said (empty when not recorded).
    pub end_reason: String,
    /// Whom the session was for in the clinic's words (absent when the station was not
    /// paired, and in older recordings).
    pub clinic: Option<record::ClinicNote>,
    /// The arm's segment lengths and fit the session's arm set-up found (absent without arm
    /// sensors).
    pub arm: Option<record::ArmCalibrationSample>,
    /// The exercises the regimen prescribed, by their short names (`sine-road`), when the
    /// recording holds a regimen (for recordings without per-exercise results).
    pub regimen_kinds: Vec<String>,
    /// The recording's format version.
    pub format_version: u32,
}

/// The channels the report reads besides `/wheel`.
const CHANNELS: [Channel; 6] = [
    Channel::Vehicle,
    Channel::Score,
    Channel::Assist,
    Channel::Arm,
    Channel::Metrics,
    Channel::ArmCalibration,
];

/// Reads the recording at `path`, front to back as a stream: what the charts draw is thinned
/// as it is read (`charts::Thinner`) and the speed profile's series is the measures' own (100 Hz),
/// so memory does not grow with the session's length but by some 12 MB an hour.
pub fn read(path: &Path) -> anyhow::Result<SessionData> {
    let unreadable = || format!("{} is not a readable recording", path.display());
    // The station's own file: the `/metrics` message of a long session may be large.
    let limits = StreamLimits {
        max_message_bytes: 16 << 20,
        ..StreamLimits::default()
    };
    let stream = TickStream::open_path(path, limits, &CHANNELS).with_context(unreadable)?;
    let meta = stream.metadata().clone();
    let mut lines: [Thinner; 7] = Default::default();
    let mut collector = MeasureCollector::new(meta.loop_rate_hz, 0);
    let deg = f64::to_degrees;
    // The file is decoded on a thread of its own while this one draws and measures what it
    // has decoded: the two take the time of the longer, not of both; a few batches of ticks
    // in between keep memory bounded.
    let (batches, received) = std::sync::mpsc::sync_channel::<Vec<TickRecord>>(4);
    let stream = std::thread::scope(|s| {
        let reader = std::thread::Builder::new()
            .name("report-read".into())
            .spawn_scoped(s, move || decode(stream, &batches))
            .context("cannot start the report's reading thread")?;
        for tick in received.into_iter().flatten() {
            let t = tick.t_ns as f64 * 1e-9;
            let w = &tick.wheel;
            lines[0].push((t, w.angle_rad.to_degrees()));
            lines[1].push((t, w.target_rad.to_degrees()));
            lines[3].push((t, w.commanded_nm));
            lines[4].push((t, tick.assist.torque_nm));
            if let Some(v) = &tick.vehicle {
                lines[2].push((t, v.lateral_m));
            }
            if let Some(a) = tick.arm.filter(|a| a.setup == ArmSetup::Tracking) {
                lines[5].push((t, deg(a.shoulder_elevation_rad)));
                lines[6].push((t, deg(a.elbow_flexion_rad)));
            }
            collector.add(&tick);
        }
        reader
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            .with_context(unreadable)
    })?;
    let metrics = stream.metrics().map(|m| &m.data);
    let [wheel, target, lateral, torque, assist, shoulder, elbow] = lines.map(Thinner::finish);
    Ok(SessionData {
        path: path.to_path_buf(),
        start_unix_ns: stream.first_log_ns().unwrap_or(0),
        exercise: meta.exercise.clone(),
        seed: meta.seed,
        patient: meta.patient_id.clone(),
        wheel_deg: wheel,
        target_deg: target,
        lateral_m: lateral,
        torque_nm: torque,
        assist_nm: assist,
        shoulder_deg: shoulder,
        elbow_deg: elbow,
        speed_deg_s: speed_profile(&mut collector),
        movements: metrics.map_or_else(Vec::new, |m| {
            m.movements
                .iter()
                .map(|mv| (mv.start_s, mv.start_s + mv.duration_s))
                .collect()
        }),
        measures: metrics.map(|m| m.measures.clone()).unwrap_or_default(),
        exercises: metrics.map(|m| m.exercises.clone()).unwrap_or_default(),
        end_reason: metrics.map(|m| m.end_reason.clone()).unwrap_or_default(),
        clinic: meta.clinic.clone(),
        arm: stream.arm_calibration().map(|c| c.data.clone()),
        regimen_kinds: regimen_kinds(meta.regimen_toml.as_deref()),
        format_version: meta.format_version,
    })
}

/// Ticks handed from the reading thread to the drawing one at a time.
const BATCH_TICKS: usize = 1024;

/// Reads `stream` to its end, handing its ticks to `batches` [`BATCH_TICKS`] at a time (each
/// tick's score as the measures take it); gives the stream back for what it read last (the
/// measures, the calibration), or the first error. Stops early when the receiver has gone.
fn decode<R: std::io::Read>(
    mut stream: TickStream<R>,
    batches: &std::sync::mpsc::SyncSender<Vec<TickRecord>>,
) -> Result<TickStream<R>, record::ReadError> {
    let mut batch = Vec::with_capacity(BATCH_TICKS);
    while let Some(tick) = stream.next() {
        let mut tick = tick?;
        // The score (with the pause) is recorded every 100 ms: before its first message the
        // exercise was as that message says.
        if let Some(first) = stream.first_score().filter(|f| tick.tick < f.tick) {
            tick.score = first.data;
        }
        batch.push(tick);
        if batch.len() == BATCH_TICKS {
            let full = std::mem::replace(&mut batch, Vec::with_capacity(BATCH_TICKS));
            if batches.send(full).is_err() {
                return Ok(stream);
            }
        }
    }
    if !batch.is_empty() {
        // The receiver reads to the end; if it has gone, there is no one to tell.
        let _ = batches.send(batch);
    }
    Ok(stream)
}

/// The short names of the exercises of a recorded regimen, in order (none without one, or
/// when it cannot be read).
fn regimen_kinds(toml: Option<&str>) -> Vec<String> {
    toml.and_then(|t| regimen::Regimen::from_recorded(t, "the recording's regimen").ok())
        .map(|(r, _)| {
            r.exercises
                .iter()
                .flat_map(regimen::RegimenEntry::expand)
                .map(|e| e.exercise.name())
                .collect()
        })
        .unwrap_or_default()
}

/// The wheel's speed as the session's measures saw it (the exercise only, paused stretches
/// left out, a NaN between runs so the chart breaks there), in °/s, thinned: the recorded
/// ticks run through the station's own collector (`collector`, fed every tick).
fn speed_profile(collector: &mut MeasureCollector) -> Vec<(f64, f64)> {
    let mut points = Thinner::default();
    // In memory: the series cannot be lost.
    for run in collector.speed_series().unwrap_or_default() {
        if let Some(&(t, _)) = run.last() {
            for &(t, v) in &run {
                points.push((t, v.to_degrees()));
            }
            points.push((t, f64::NAN));
        }
    }
    points.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use record::{RecordWriter, SessionMetadata};
    use std::time::{Duration, Instant};

    /// `seconds` of a session at 1 kHz written to `path` by the recorder's writer (a chunk a
    /// second, a score every 100 ms, the wheel moving).
    fn write_session(path: &Path, seconds: u64) {
        let meta = SessionMetadata {
            loop_rate_hz: 1000.0,
            ..Default::default()
        };
        let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
        let mut w = RecordWriter::new(file, 0, &meta).unwrap();
        for tick in 0..seconds * 1000 {
            let t = tick as f64 * 1e-3;
            let mut rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                ..Default::default()
            };
            rec.wheel.angle_rad = (0.7 * t).sin();
            rec.wheel.target_rad = (0.7 * t + 0.1).sin();
            rec.wheel.commanded_nm = 0.3 * (2.0 * t).cos();
            rec.assist.torque_nm = 0.1 * t.sin();
            w.write_tick(&rec, tick % 100 == 0).unwrap();
            if tick % 1000 == 999 {
                w.flush().unwrap();
            }
        }
        w.finish().unwrap();
    }

    /// The wall time of `f`.
    fn timed(f: impl FnOnce()) -> Duration {
        let start = Instant::now();
        f();
        start.elapsed()
    }

    #[test]
    fn reading_a_session_for_the_report_takes_little_more_than_decoding_it() {
        let path = std::env::temp_dir().join(format!("report-read-{}.mcap", std::process::id()));
        write_session(&path, 60);
        let limits = StreamLimits::default();
        let decode_only = || {
            let stream = TickStream::open_path(&path, limits, &CHANNELS).unwrap();
            assert_eq!(stream.map(Result::unwrap).count(), 60_000);
        };
        // Alternated, so that a stretch of load elsewhere falls on both; the fastest of each
        // is the one least disturbed by the machine's other work.
        let (mut plain, mut report) = (Duration::MAX, Duration::MAX);
        for _ in 0..3 {
            plain = plain.min(timed(decode_only));
            report = report.min(timed(|| {
                let read = read(&path).unwrap();
                assert!(!read.wheel_deg.is_empty());
            }));
        }
        std::fs::remove_file(&path).unwrap();
        let ratio = report.as_secs_f64() / plain.as_secs_f64();
        println!(
            "60 s: decoded in {:.3} s, read for the report in {:.3} s: {ratio:.2}×",
            plain.as_secs_f64(),
            report.as_secs_f64()
        );
        // The charts and the measures are drawn from the ticks on one thread while another
        // decodes them: the read takes the longer of the two, the decoding here.
        assert!(
            ratio < 2.0,
            "the report's read took {ratio:.2}× the decoding alone (expected < 2×)"
        );
    }
}
