//! A patient session: the haptic thread, the recorder thread and the therapist link, wired
//! together and torn down cleanly on every path.

pub mod arm;
pub mod course;
pub mod haptic;
pub mod plant;
pub mod record;
#[cfg(test)]
mod tests;

use crate::config::StationConfig;
use crate::recorder::{McapRecorder, RecorderOutcome, SUMMARY_EVERY_S};
use crate::timing::TimingStats;
use anyhow::Context;
use haptic::{HapticOutcome, Pacing};
use record::TickRecord;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// Capacity of the haptic → recorder ring, records (8 s at 1 kHz).
const RING_CAPACITY: usize = 8192;
/// The recorder closes a chunk this often so a killed process loses at most this much, s.
const FLUSH_EVERY_S: f64 = 1.0;

/// How to run a session.
#[derive(Clone, Debug)]
pub struct SessionOptions {
    /// Validated configuration.
    pub config: StationConfig,
    /// Real time or as fast as possible.
    pub pacing: Pacing,
    /// MCAP file to record to.
    pub record: Option<PathBuf>,
    /// Simulated body or real devices.
    pub body: BodyKind,
    /// The prescribed exercises; `None` repeats `config.session.exercise`.
    pub regimen: Option<crate::regimen::Regimen>,
    /// Give the haptic thread a core of its own (the caller keeps its other threads off it).
    pub isolate_core: bool,
}

/// Who holds the wheel in a session.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyKind {
    /// The simulated wheel, patient and IMUs.
    Simulated,
    /// The first real force-feedback wheel found, held by the patient.
    #[cfg(target_os = "linux")]
    RealWheel,
}

/// A live summary, produced every [`SUMMARY_EVERY_S`] of session time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LiveSummary {
    /// Sequence number, from 0.
    pub seq: u64,
    /// The tick it was taken at.
    pub record: TickRecord,
    /// Largest |commanded torque| so far, N·m.
    pub max_abs_torque_nm: f64,
    /// 99th percentile of the loop period error over the last second, µs.
    pub loop_p99_us: f64,
    /// Further metrics for the therapist (assist level, joint angles, …), name → value.
    pub extra: BTreeMap<String, f64>,
}

/// The result of a session.
#[derive(Debug)]
pub struct SessionReport {
    /// The haptic thread's account.
    pub haptic: HapticOutcome,
    /// The recorder's account.
    pub recorder: RecorderOutcome,
    /// The nominal loop rate, Hz.
    pub loop_rate_hz: f64,
    /// The MCAP file, if recording.
    pub record: Option<PathBuf>,
    /// Summaries produced.
    pub summaries: u64,
    /// The loop was paced in real time (wall-clock timing figures apply).
    pub real_time: bool,
    /// Exercises in the course (laps of one exercise, or the regimen's).
    pub exercises: usize,
    /// The simulated patient's true upper-arm and forearm lengths, m (simulation only).
    pub sim_arm_truth_m: Option<(f64, f64)>,
}

fn unix_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos() as u64)
        .unwrap_or(0)
}

/// Who watches a running session from the recorder thread (the therapist link, the patient's
/// screen). Both methods must return quickly and never block.
pub trait SessionObserver: Send {
    /// Every tick's record, in order.
    fn on_tick(&mut self, _record: &TickRecord) {}
    /// Every live summary (every [`SUMMARY_EVERY_S`] of session time).
    fn on_summary(&mut self, _summary: &LiveSummary) {}
}

/// What other threads (a signal handler, the patient's window) may ask of a running session.
#[derive(Debug, Default)]
pub struct Controls {
    /// End the session: the torque fades out and everything is recorded and delivered.
    pub stop: Arc<AtomicBool>,
    /// While set, the exercise is paused (see [`plant::Plant::set_paused`]).
    pub pause: AtomicBool,
}

impl Controls {
    /// Controls around an existing stop flag (such as the one signal handlers set).
    pub fn with_stop(stop: Arc<AtomicBool>) -> Self {
        Self {
            stop,
            pause: AtomicBool::new(false),
        }
    }
}

/// Run a session until its exercise time reaches its duration, its course is done or
/// `controls.stop` is set; `observer` watches it from the recorder thread.
pub fn run(
    opts: &SessionOptions,
    controls: &Controls,
    observer: &mut dyn SessionObserver,
) -> anyhow::Result<SessionReport> {
    let cfg = &opts.config;
    cfg.validate()?;
    let rate = cfg.session.loop_rate_hz;
    let total_ticks = (cfg.session.duration_s * rate).round() as u64;
    let start_unix_ns = unix_ns();
    // Devices first: a session that cannot start must not leave an empty recording behind.
    let course = course::build(cfg, opts.regimen.as_ref())?;
    let exercises = course.len();
    let mut plant = match opts.body {
        BodyKind::Simulated => plant::Plant::new(
            cfg,
            plant::Body::simulated(cfg, opts.pacing == Pacing::RealTime)?,
            course,
        )?,
        #[cfg(target_os = "linux")]
        BodyKind::RealWheel => plant::Plant::new(cfg, plant::Body::first_real_wheel(cfg)?, course)?,
    };
    let recorder = match &opts.record {
        Some(path) => {
            let mut meta = BTreeMap::new();
            meta.insert("exercise".into(), cfg.session.exercise.clone());
            meta.insert("seed".into(), cfg.session.seed.to_string());
            meta.insert("patient_id".into(), cfg.session.patient_id.clone());
            meta.insert("loop_rate_hz".into(), rate.to_string());
            meta.insert(
                "config_toml".into(),
                toml::to_string(cfg).unwrap_or_default(),
            );
            // A session is replayable only with its course: record the regimen as well.
            if let Some(r) = &opts.regimen {
                meta.insert(
                    "regimen_toml".into(),
                    toml::to_string(r).unwrap_or_default(),
                );
            }
            Some(
                McapRecorder::create(path, start_unix_ns, &meta)
                    .context("cannot start recording")?,
            )
        }
        None => None,
    };
    let (mut producer, consumer) = rtrb::RingBuffer::<TickRecord>::new(RING_CAPACITY);
    let haptic_done = Arc::new(AtomicBool::new(false));
    let period_ns = (1e9 / rate).round() as u64;
    let summary_every = ((SUMMARY_EVERY_S * rate).round() as u64).max(1);
    let flush_every = ((FLUSH_EVERY_S * rate).round() as u64).max(1);
    let pacing = opts.pacing;
    let isolate_core = opts.isolate_core;
    let plan = RecorderPlan {
        period_ns,
        expected_ticks: total_ticks,
        summary_every,
        flush_every,
    };

    let (haptic, recorder_outcome, summaries) = std::thread::scope(|scope| -> anyhow::Result<_> {
        let done = haptic_done.clone();
        let rec_thread = std::thread::Builder::new()
            .name("recorder".into())
            .spawn_scoped(scope, move || {
                recorder_loop(consumer, recorder, &done, plan, observer)
            })
            .context("cannot start the recorder thread")?;
        let haptic_thread = std::thread::Builder::new()
            .name("haptic".into())
            .spawn_scoped(scope, move || {
                haptic::run(
                    &mut plant,
                    &mut producer,
                    total_ticks,
                    pacing,
                    isolate_core,
                    controls,
                )
            })
            .context("cannot start the haptic thread")?;
        let haptic = haptic_thread.join();
        haptic_done.store(true, Ordering::Release);
        let (rec, summaries) = rec_thread
            .join()
            .map_err(|_| anyhow::anyhow!("recorder thread panicked"))?;
        let haptic =
            haptic.map_err(|_| anyhow::anyhow!("haptic thread panicked (torque was zeroed)"))?;
        Ok((haptic, rec, summaries))
    })?;

    Ok(SessionReport {
        haptic,
        recorder: recorder_outcome,
        loop_rate_hz: rate,
        record: opts.record.clone(),
        summaries,
        real_time: opts.pacing == Pacing::RealTime,
        exercises,
        sim_arm_truth_m: (opts.body == BodyKind::Simulated).then_some((
            cfg.sim_arm.geometry.upper_arm_m,
            cfg.sim_arm.geometry.forearm_m,
        )),
    })
}

/// Metrics for the therapist beyond the fixed summary fields: safety and assistance so far.
fn summary_extra(out: &RecorderOutcome) -> BTreeMap<String, f64> {
    let ticks = out.records.max(1) as f64;
    let mut extra = BTreeMap::new();
    extra.insert(
        "clipped_pct".into(),
        100.0 * out.clipped_ticks as f64 / ticks,
    );
    extra.insert("watchdog_fault_ticks".into(), out.fault_ticks as f64);
    if let Some(arm) = &out.last.arm {
        extra.insert(
            "shoulder_elevation_deg".into(),
            arm.shoulder_elevation_rad.to_degrees(),
        );
        extra.insert(
            "elbow_flexion_deg".into(),
            arm.elbow_flexion_rad.to_degrees(),
        );
    }
    if out.assist_ticks > 0 {
        let n = out.assist_ticks as f64;
        extra.insert("assist_level_mean".into(), out.assist_level_sum / n);
        extra.insert(
            "assist_rms_error_deg".into(),
            (out.assist_error_sq_sum / n).sqrt().to_degrees(),
        );
        extra.insert(
            "assist_saturated_pct".into(),
            100.0 * out.assist_saturated_ticks as f64 / n,
        );
    }
    extra
}

/// Logs what changes in a session from the recorded ticks (pauses, the arm set-up's steps),
/// so that the haptic thread itself never writes a log line.
#[derive(Default)]
struct ChangeLog {
    paused: bool,
    arm_step: Option<record::ArmSetup>,
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
struct RecorderPlan {
    /// Nominal loop period, ns.
    period_ns: u64,
    /// Ticks the session should run (for preallocation).
    expected_ticks: u64,
    /// Ticks between summaries.
    summary_every: u64,
    /// Ticks between MCAP chunk flushes.
    flush_every: u64,
}

fn recorder_loop(
    mut consumer: rtrb::Consumer<TickRecord>,
    mut mcap: Option<McapRecorder>,
    haptic_done: &AtomicBool,
    plan: RecorderPlan,
    observer: &mut dyn SessionObserver,
) -> (RecorderOutcome, u64) {
    let RecorderPlan {
        period_ns,
        expected_ticks,
        summary_every,
        flush_every,
    } = plan;
    let mut out = RecorderOutcome {
        timing: TimingStats::new(period_ns, expected_ticks as usize + 1000),
        ..Default::default()
    };
    let mut seq = 0u64;
    let mut arm_loop = crate::arm_calibration::ArmLoopCollector::new(1e9 / period_ns as f64);
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
                // Keep the session running; report the first recording error once at the end.
                out.error.get_or_insert_with(|| e.to_string());
                mcap = None;
            }
        }
        if summary_tick {
            observer.on_summary(&LiveSummary {
                seq,
                record: rec,
                max_abs_torque_nm: out.max_abs_torque_nm,
                loop_p99_us: out.timing.recent_period_error_p99_us(1000),
                extra: summary_extra(&out),
            });
            seq += 1;
        }
    }
    if !arm_loop.is_empty() || out.last.arm.is_some() {
        let fitted = arm_loop
            .calibrate()
            .map(|c| crate::arm_calibration::ArmCalibrationSample::from(&c))
            .map_err(|e| e.to_string());
        if let (Ok(c), Some(m)) = (&fitted, mcap.as_mut())
            && let Err(e) = m.record_arm_calibration(&out.last, c)
        {
            out.error.get_or_insert_with(|| e.to_string());
        }
        out.arm_calibration = Some(fitted);
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
