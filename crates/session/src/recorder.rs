//! The recorder thread: per-tick records → MCAP (through [`record`]), thinned summaries
//! → the session's observer (the therapist link, the screen), the arm calibration at the end
//! and the loop-timing statistics for the final report.
//!
//! The haptic thread never waits for it in real time.

use super::disk_space::{self, LowSpace};
use super::faults::{Disk, FillingFile};
use super::outcome::RecorderOutcome;
use super::{LiveSummary, SessionObserver};
use crate::timing::TimingStats;
use arm::calibration::{ArmLoopCollector, OnlineArmCalibration};
use measures::MeasureCollector;
use record::{
    ArmCalibrationSample, ArmSetup, MetricsSample, RecordWriter, SessionMetadata, TickRecord,
};
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Session time between two score messages and two therapist summaries, s.
pub const SUMMARY_EVERY_S: f64 = 0.1;

/// Wall time between two syncs of the recording to the disk (`fsync`), after a chunk closes:
/// a power cut loses at most about this much.
pub const SYNC_EVERY: Duration = Duration::from_secs(1);

/// A session's MCAP file being written.
pub struct McapRecorder {
    writer: RecordWriter<BufWriter<FillingFile>>,
    path: PathBuf,
    /// Session time an injected `disk-full` fault fills the disk at, ns.
    disk_full_at_ns: Option<u64>,
    /// The disk the file is on (filled by that fault).
    disk: Disk,
    /// The same open file, to sync it and measure its filesystem's free space.
    file: std::fs::File,
    /// Wall time between two syncs.
    sync_every: Duration,
    /// When the file was last synced.
    last_sync: Option<Instant>,
    /// Recording stops (the file finished) when fewer bytes than this are free, bytes.
    reserve_bytes: u64,
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
    /// A file is already there: a recording is never overwritten.
    #[error(
        "recording {path}: the file already exists, and a recording is never overwritten \
         (choose another path, or move the old file away)"
    )]
    Exists {
        /// The path asked for.
        path: String,
    },
    /// The MCAP library refused.
    #[error("recording {path}: {source}")]
    Mcap {
        /// The MCAP file.
        path: String,
        /// Why.
        source: mcap::McapError,
    },
    /// Free space on the recording's disk fell below the reserve: recording stops and the
    /// file is finished while there is room.
    #[error(transparent)]
    LowSpace(LowSpace),
}

impl McapRecorder {
    /// Create `path` (never over an existing file) and register the channels.
    /// `start_unix_ns` anchors log times.
    pub fn create(
        path: &Path,
        start_unix_ns: u64,
        metadata: &SessionMetadata,
    ) -> Result<Self, RecorderError> {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|source| match source.kind() {
                std::io::ErrorKind::AlreadyExists => RecorderError::Exists {
                    path: path.display().to_string(),
                },
                _ => RecorderError::Io {
                    path: path.display().to_string(),
                    source,
                },
            })?;
        let disk = Disk::default();
        let handle = file.try_clone().map_err(|source| RecorderError::Io {
            path: path.display().to_string(),
            source,
        })?;
        // The new name reaches the disk with its directory (the file's own syncs do not carry
        // it), so a power cut keeps the recording findable.
        if let Ok(dir) = std::fs::File::open(disk_space::directory_of(path)) {
            let _ = dir.sync_all();
        }
        let writer = RecordWriter::new(
            BufWriter::new(FillingFile::new(file, disk.clone())),
            start_unix_ns,
            metadata,
        )
        .map_err(|source| RecorderError::Mcap {
            path: path.display().to_string(),
            source,
        })?;
        Ok(Self {
            writer,
            path: path.to_path_buf(),
            disk_full_at_ns: None,
            disk,
            file: handle,
            sync_every: SYNC_EVERY,
            last_sync: None,
            reserve_bytes: disk_space::RESERVE_BYTES,
        })
    }

    /// Sync the file to the disk after a chunk closes at most once per `every` of wall time
    /// (default [`SYNC_EVERY`]; `Duration::ZERO`: after every chunk, `Duration::MAX`: never).
    pub fn sync_every(mut self, every: Duration) -> Self {
        self.sync_every = every;
        self
    }

    /// Stop recording when fewer than `reserve_bytes` are free on the file's filesystem
    /// (default [`disk_space::RESERVE_BYTES`]), checked each time a chunk closes.
    pub fn keep_free(mut self, reserve_bytes: u64) -> Self {
        self.reserve_bytes = reserve_bytes;
        self
    }

    /// Fill the disk (an injected fault) at session time `at_ns`.
    pub fn fill_disk_at(mut self, at_ns: Option<u64>) -> Self {
        self.disk_full_at_ns = at_ns;
        self
    }

    /// The error, named by its cause: the file's I/O error under the MCAP library's (a full
    /// disk, a removed drive) is what the patient and the therapist are told, not "Record
    /// parse failed".
    fn err(&self, source: mcap::McapError) -> RecorderError {
        let path = self.path.display().to_string();
        match self.disk.last_error() {
            Some(source) => RecorderError::Io { path, source },
            None => RecorderError::Mcap { path, source },
        }
    }

    /// Record one tick on the per-tick channels, and the score when `with_score`.
    pub fn record(&mut self, rec: &TickRecord, with_score: bool) -> Result<(), RecorderError> {
        if self.disk_full_at_ns.is_some_and(|at| rec.t_ns >= at) {
            self.disk.fill();
        }
        self.writer
            .write_tick(rec, with_score)
            .map_err(|e| self.err(e))
    }

    /// Record the arm calibration fitted at the end of the session, stamped with the last tick.
    pub fn record_arm_calibration(
        &mut self,
        last: &TickRecord,
        calibration: &ArmCalibrationSample,
    ) -> Result<(), RecorderError> {
        self.writer
            .write_arm_calibration(last, calibration)
            .map_err(|e| self.err(e))
    }

    /// Record the session's movement measures, stamped with the last tick.
    pub fn record_metrics(
        &mut self,
        last: &TickRecord,
        metrics: &MetricsSample,
    ) -> Result<(), RecorderError> {
        self.writer
            .write_metrics(last, metrics)
            .map_err(|e| self.err(e))
    }

    /// Close the current chunk and flush it to the file, so a killed process loses at most
    /// what came after this call; sync the file to the disk if [`SYNC_EVERY`] has passed (a
    /// power cut loses at most that much more); then check the free space: below the reserve
    /// this returns [`RecorderError::LowSpace`] and the caller finishes the file.
    pub fn flush(&mut self) -> Result<(), RecorderError> {
        self.writer.flush().map_err(|e| self.err(e))?;
        if self.sync_every != Duration::MAX
            && self
                .last_sync
                .is_none_or(|t| t.elapsed() >= self.sync_every)
        {
            self.last_sync = Some(Instant::now());
            self.file.sync_data().map_err(|source| RecorderError::Io {
                path: self.path.display().to_string(),
                source,
            })?;
        }
        match disk_space::free_bytes_of(&self.file) {
            Ok(free) if free < self.reserve_bytes => Err(RecorderError::LowSpace(LowSpace {
                path: self.path.clone(),
                free_bytes: free,
                needed_bytes: self.reserve_bytes,
                planned_s: None,
            })),
            // Cannot measure: writing goes on, and a full disk still says so.
            _ => Ok(()),
        }
    }

    /// Write the summary section, sync the file to the disk and close it; returns its size in
    /// bytes.
    pub fn finish(self) -> Result<u64, RecorderError> {
        let Self { writer, path, .. } = self;
        let path = path.display().to_string();
        let file = match writer.finish() {
            Ok(sink) => sink.into_inner().map_err(|e| e.into_error()),
            Err(source) => return Err(RecorderError::Mcap { path, source }),
        };
        file.and_then(|f| f.file().sync_data().and_then(|()| f.file().metadata()))
            .map(|m| m.len())
            .map_err(|source| RecorderError::Io { path, source })
    }
}

/// What the live view shows besides the measures: the arm's configured lengths and each
/// exercise's road.
struct LiveScene {
    arm_lengths_m: [f64; 2],
    roads: Vec<Option<Box<dyn exercises::Road + Send>>>,
}

/// The session's measure collector: a recorded session spills the measures' series to the
/// recording's disk, so that its memory stays flat however long it runs.
fn collector(
    mcap: Option<&McapRecorder>,
    period_ns: u64,
    expected_ticks: u64,
    target_steps: Vec<exercises::TargetSteps>,
    apart: Vec<bool>,
) -> MeasureCollector {
    let rate_hz = 1e9 / period_ns as f64;
    match mcap {
        Some(m) => MeasureCollector::spilling_in(disk_space::directory_of(&m.path), rate_hz),
        None => MeasureCollector::new(rate_hz, expected_ticks),
    }
    .with_target_steps(target_steps)
    .with_apart(apart)
}

/// Metrics for the therapist beyond the fixed summary fields: safety, assistance and the live
/// movement measures so far.
/// The arm is drawn with the configured lengths until the online calibration converges, then
/// with its lengths (`arm_calibrated` 1, `arm_calibrated_at_s` when).
fn summary_extra(
    out: &RecorderOutcome,
    measures: &MeasureCollector,
    online: &OnlineArmCalibration,
    scene: &LiveScene,
) -> BTreeMap<String, f64> {
    let LiveScene {
        arm_lengths_m,
        roads,
    } = scene;
    let arm_lengths_m = *arm_lengths_m;
    let mut extra = measures.live();
    extra.extend(super::live_strength::extra(&out.last.score));
    extra.extend(out.safety_and_assist());
    if let Some(t) = out.recording_stopped_s {
        extra.insert("recording_stopped_s".into(), t);
    }
    let lengths = online.lengths_m().unwrap_or(arm_lengths_m);
    extra.extend(record::view::live_pose(&out.last, lengths));
    if out.last.arm.is_some() {
        let at = online.at_convergence().map(|c| c.converged_at_s);
        extra.insert("arm_calibrated".into(), f64::from(u8::from(at.is_some())));
        if let Some(at) = at {
            extra.insert("arm_calibrated_at_s".into(), at);
        }
    }
    let road = roads.get(out.last.score.exercise_index as usize);
    if let (Some(car), Some(Some(road))) = (&out.last.vehicle, road) {
        extra.extend(super::live_road::road_around(road.as_ref(), car));
    }
    extra
}

/// Logs what changes in a session from the recorded ticks (pauses, the arm set-up's steps),
/// so that the haptic thread itself never writes a log line.
#[derive(Default)]
struct ChangeLog {
    paused: bool,
    arm_step: Option<ArmSetup>,
}

impl ChangeLog {
    fn observe(&mut self, rec: &TickRecord) {
        if rec.score.paused != self.paused {
            self.paused = rec.score.paused;
            tracing::info!(
                tick = rec.tick,
                paused = self.paused,
                "exercise paused or resumed"
            );
        }
        if let Some(arm) = &rec.arm
            && self.arm_step != Some(arm.setup)
        {
            tracing::info!(
                tick = rec.tick,
                from = ?self.arm_step,
                to = ?arm.setup,
                "arm sensing"
            );
            self.arm_step = Some(arm.setup);
        }
    }
}

/// The recorder thread's fixed settings.
pub(super) struct RecorderPlan {
    /// Nominal loop period, ns.
    pub(super) period_ns: u64,
    /// Ticks the session should run (for preallocation).
    pub(super) expected_ticks: u64,
    /// Ticks between summaries.
    pub(super) summary_every: u64,
    /// Ticks between MCAP chunk flushes.
    pub(super) flush_every: u64,
    /// Upper-arm and forearm lengths the station was set up with, m (for the live view).
    pub(super) arm_lengths_m: [f64; 2],
    /// Each exercise's road in the course (`None`: the dial task), for the road around the car
    /// in the live summaries.
    pub(super) roads: Vec<Option<Box<dyn exercises::Road + Send>>>,
    /// Which of each exercise's target changes are steps, for the measures.
    pub(super) target_steps: Vec<exercises::TargetSteps>,
    /// Which exercises are measured apart from the session (the standard assessment's
    /// parts), by index in the course.
    pub(super) apart: Vec<bool>,
    /// The trunk excursion counted as compensating, deg (`[arm] trunk_threshold_deg`).
    pub(super) trunk_threshold_deg: f64,
    /// Which exercises, by index in the course, cue the patient to sit up (their cues are
    /// counted in the measures).
    pub(super) trunk_cued: Vec<bool>,
}

/// What the haptic thread leaves the recorder when it ends, for the recording's `/metrics`:
/// why the loop ended and each exercise's own scores.
#[derive(Debug, Default)]
pub struct SessionEnding {
    /// [`super::end_reason::ended_by`] of the haptic thread's outcome.
    pub reason: String,
    /// Each exercise's own scores, of the exercises started.
    pub scores: Vec<measures::ExerciseScores>,
}

/// The session's arm calibration at its end (with the one during the session, if it
/// converged), into `out` and the recording.
fn finish_arm_calibration(
    out: &mut RecorderOutcome,
    arm_loop: &ArmLoopCollector,
    online_arm: &OnlineArmCalibration,
    mcap: Option<&mut McapRecorder>,
) {
    if arm_loop.is_empty() && out.last.arm.is_none() {
        return;
    }
    let online = online_arm.at_convergence().cloned();
    let fitted = arm_loop
        .calibrate()
        .map(|c| ArmCalibrationSample {
            online: online.clone(),
            ..ArmCalibrationSample::from(&c)
        })
        .map_err(|e| e.to_string());
    out.online_arm_calibration = online;
    if let (Ok(c), Some(m)) = (&fitted, mcap)
        && let Err(e) = m.record_arm_calibration(&out.last, c)
    {
        out.error.get_or_insert_with(|| e.to_string());
    }
    out.arm_calibration = Some(fitted);
}

pub(super) fn recorder_loop(
    mut consumer: rtrb::Consumer<TickRecord>,
    mut mcap: Option<McapRecorder>,
    haptic_done: &AtomicBool,
    plan: RecorderPlan,
    observer: &mut dyn SessionObserver,
    ending: &std::sync::OnceLock<SessionEnding>,
) -> (RecorderOutcome, u64) {
    let RecorderPlan {
        period_ns,
        expected_ticks,
        summary_every,
        flush_every,
        arm_lengths_m,
        roads,
        target_steps,
        apart,
        trunk_threshold_deg,
        trunk_cued,
    } = plan;
    let scene = LiveScene {
        arm_lengths_m,
        roads,
    };
    let mut out = RecorderOutcome {
        timing: TimingStats::new(period_ns),
        ..Default::default()
    };
    let mut seq = 0u64;
    let mut arm_loop = ArmLoopCollector::new(1e9 / period_ns as f64);
    let mut online_arm = OnlineArmCalibration::new(1e9 / period_ns as f64);
    let mut measures = collector(
        mcap.as_ref(),
        period_ns,
        expected_ticks,
        target_steps,
        apart,
    )
    .with_trunk_threshold_deg(trunk_threshold_deg)
    .with_trunk_cued(trunk_cued);
    let mut changes = ChangeLog::default();
    loop {
        let rec = match consumer.pop() {
            Ok(r) => r,
            Err(_) => {
                if haptic_done.load(Ordering::Acquire) && consumer.is_empty() {
                    break;
                }
                std::thread::sleep(Duration::from_micros(500));
                continue;
            }
        };
        out.add(&rec);
        arm_loop.add(&rec);
        online_arm.add(&rec, &arm_loop);
        measures.add(&rec);
        changes.observe(&rec);
        observer.on_tick(&rec);
        let summary_tick = rec.tick % summary_every == 0 && rec.tick > 0;
        if let Some(m) = mcap.as_mut() {
            let res = m.record(&rec, summary_tick).and_then(|()| {
                if rec.tick % flush_every == flush_every - 1 {
                    m.flush()
                } else {
                    Ok(())
                }
            });
            if let Err(e) = res {
                // Keep the session running; say at once that recording stopped (the log, the
                // live summaries' `recording_stopped_s` for the hub and its console) and
                // report the error at the end.
                tracing::warn!(t_s = rec.t_ns as f64 * 1e-9, "recording stopped: {e}");
                out.recording_stopped_s = Some(rec.t_ns as f64 * 1e-9);
                out.error.get_or_insert_with(|| e.to_string());
                // Low on space, not out of it: finish the file while there is room, so it
                // reads without `telerehab recover`.
                if let (RecorderError::LowSpace(_), Some(m)) = (&e, mcap.take()) {
                    match m.finish() {
                        Ok(bytes) => out.mcap_bytes = Some(bytes),
                        Err(e) => tracing::warn!("cannot finish the recording: {e}"),
                    }
                }
                mcap = None;
            }
        }
        if summary_tick {
            observer.on_summary(&LiveSummary {
                seq,
                record: rec,
                max_abs_torque_nm: out.max_abs_torque_nm,
                loop_p99_us: out.timing.recent_period_error_p99_us(1000),
                extra: summary_extra(&out, &measures, &online_arm, &scene),
            });
            seq += 1;
        }
    }
    finish_arm_calibration(&mut out, &arm_loop, &online_arm, mcap.as_mut());
    out.measures = measures.finish(out.session_figures(measures.tick_s()));
    let ending = ending.get();
    out.exercises = measures.exercise_results(
        ending.map_or(&[][..], |e| e.scores.as_slice()),
        crate::words::plain_name,
    );
    measures::strength_of_exercises(&mut out.measures.named, &out.exercises);
    measures::sweep_of_exercises(&mut out.measures.named, &out.exercises);
    let sample = MetricsSample {
        exercises: out.exercises.clone(),
        end_reason: ending.map_or_else(String::new, |e| {
            super::end_reason::with_recording(e.reason.clone(), &out)
        }),
        ..measures.sample(&out.measures)
    };
    if let Some(m) = mcap.as_mut()
        && let Err(e) = m.record_metrics(&out.last, &sample)
    {
        out.error.get_or_insert_with(|| e.to_string());
    }
    if let Some(m) = mcap {
        match m.finish() {
            Ok(bytes) => out.mcap_bytes = Some(bytes),
            Err(e) => {
                out.error.get_or_insert_with(|| e.to_string());
            }
        }
    }
    (out, seq)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Watches the live summaries for `recording_stopped_s`.
    #[derive(Default)]
    struct Summaries(Vec<Option<f64>>);

    impl SessionObserver for Summaries {
        fn on_summary(&mut self, s: &LiveSummary) {
            self.0.push(s.extra.get("recording_stopped_s").copied());
        }
    }

    #[test]
    fn a_recorder_low_on_space_stops_at_a_chunk_and_leaves_a_finished_readable_file() {
        use record::Recording;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("low.mcap");
        // Whatever is free on this disk is below a reserve of every byte there could be: the
        // first chunk's check (a real statvfs) stops the recording.
        let recorder = McapRecorder::create(&path, 0, &SessionMetadata::default())
            .unwrap()
            .keep_free(u64::MAX);
        let (mut producer, consumer) = rtrb::RingBuffer::new(4096);
        for tick in 0..2500u64 {
            let rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                ..Default::default()
            };
            producer.push(rec).unwrap();
        }
        let plan = RecorderPlan {
            period_ns: 1_000_000,
            expected_ticks: 2500,
            summary_every: 100,
            flush_every: 1000,
            arm_lengths_m: [0.3, 0.25],
            trunk_threshold_deg: arm::DEFAULT_TRUNK_THRESHOLD_DEG,
            trunk_cued: Vec::new(),
            roads: Vec::new(),
            target_steps: Vec::new(),
            apart: Vec::new(),
        };
        let mut summaries = Summaries::default();
        let done = AtomicBool::new(true);
        let (out, _) = recorder_loop(
            consumer,
            Some(recorder),
            &done,
            plan,
            &mut summaries,
            &Default::default(),
        );
        assert_eq!(out.records, 2500, "the session went on");
        let at_s = out.recording_stopped_s.unwrap();
        assert!((at_s - 0.999).abs() < 1e-9, "stopped at {at_s} s");
        let err = out.error.unwrap();
        assert!(err.contains("stopped before the disk filled up"), "{err}");
        assert!(err.contains(path.to_str().unwrap()), "{err}");
        // Said at once: every summary from the stop on carries it, none before.
        let stopped: Vec<_> = summaries.0.iter().map(Option::is_some).collect();
        assert_eq!(stopped.iter().filter(|s| !**s).count(), 9, "{stopped:?}");
        assert!(stopped[9..].iter().all(|s| *s));
        // Finished: it reads without recover, every tick up to the stop and none after.
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(out.mcap_bytes, Some(bytes.len() as u64));
        assert!(mcap::Summary::read(&bytes).unwrap().is_some());
        let ticks: Vec<u64> = Recording::open(&path)
            .unwrap()
            .wheel
            .iter()
            .map(|w| w.tick)
            .collect();
        assert_eq!(ticks, (0..1000).collect::<Vec<_>>());
    }
}
