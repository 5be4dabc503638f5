//! A patient session: the haptic thread, the recorder thread and the therapist link, wired
//! together and torn down cleanly on every path ([`run`]).
//!
//! # Module map
//!
//! - [`haptic`] is the 1 kHz loop driving a [`plant::Plant`] (wheel, patient, car, haptic
//!   chain, assist) through the exercises of [`course`]; [`recorder`] writes the records and
//!   thins summaries, syncing the file and watching the room left on its disk
//!   ([`disk_space`]), and hands back an [`outcome::RecorderOutcome`]; the `arm` crate turns
//!   the IMUs into joint angles and arm lengths (the haptic thread steps it, the recorder
//!   calibrates with it), the `measures` crate computes the movement measures the recorder
//!   feeds it; [`window`] runs the patient's window in a process of its own (restarted, the
//!   exercise paused, if it dies or hangs); [`signals`] turns SIGINT/SIGTERM into a stop
//!   request and [`Controls`] carries stop and pause to the loop; [`recorded`] is a body made
//!   of a recording's raw inputs (replay); [`faults`] injects faults into simulated sessions;
//!   [`words`] names exercises and instructions for the patient.
//! - [`config`]: the station's TOML, validated input (the `[[faults]]` a configuration names
//!   are `config::faults`, its `[arm]` section `arm::config`); [`assessment`]: when the standard assessment runs; [`settings`]
//!   and [`language`]: the patient's settings file and the language in force.
//! - [`timing`] (loop-timing percentiles), [`resident`] (the process's memory figures; the
//!   buffers made resident up front are `common::resident`), [`platform`] (where Linux and Windows differ),
//!   [`files`] (small files written whole, 0600).
//!
//! Threads (DESIGN.md): `haptic` (1 kHz, absolute deadlines, real-time priority where
//! granted) → wait-free ring → `recorder` (MCAP, summaries) → the therapist link's tokio
//! runtime and the window's triple buffer; the main thread answers the window process's pulls
//! from that buffer and watches it, the session runs on a `session` thread beside it.

pub mod assessment;
pub mod breaks;
pub mod buttons;
pub mod config;
mod controls;
pub mod course;
pub mod disk_space;
pub mod effort_check;
pub mod end_reason;
pub mod faults;
pub mod files;
pub mod haptic;
pub mod language;
pub mod live_road;
pub mod live_strength;
pub mod outcome;
pub mod plant;
pub mod platform;
#[cfg(test)]
mod prescription_tests;
pub mod recorded;
pub mod recorder;
pub mod resident;
pub mod settings;
pub mod signals;
#[cfg(test)]
mod tests;
pub mod timing;
#[cfg(test)]
mod trunk_cue_tests;
pub mod wheel_cards;
pub mod wheel_gestures;
pub mod window;
pub mod words;

use crate::config::StationConfig;
use anyhow::Context;
use clock::Clock;
use haptic::{HapticOutcome, Pacing};
use outcome::RecorderOutcome;
use record::{SessionMetadata, TickRecord};
use recorder::{McapRecorder, RecorderPlan, SUMMARY_EVERY_S, recorder_loop};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

pub use controls::{
    BreakKind, BreakNow, Controls, EndAnswer, EndAnswers, EndAnswersTaken, PauseChoice,
};

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
    pub regimen: Option<regimen::Regimen>,
    /// The difficulty the regimen runs at and why, when it adapts (recorded in the session's
    /// metadata; the regimen above is already the one at that difficulty).
    pub difficulty: Option<record::DifficultyNote>,
    /// Give the haptic thread a core of its own (the caller keeps its other threads off it).
    pub isolate_core: bool,
    /// The session's clock: the haptic thread's deadlines and the recording's start time
    /// (a mock clock runs a real-time session at once, with exact timing figures).
    pub clock: Clock,
}

impl SessionOptions {
    /// A simulated session of `config` as fast as possible: no recording, no regimen (the
    /// configured exercise), no difficulty, the real clock — what tests, examples and offline
    /// renders start from (`SessionOptions { record, ..SessionOptions::simulated(cfg) }`).
    pub fn simulated(config: StationConfig) -> Self {
        Self {
            config,
            pacing: Pacing::Max,
            record: None,
            body: BodyKind::Simulated,
            regimen: None,
            difficulty: None,
            isolate_core: false,
            clock: Clock::real(),
        }
    }
}

/// Who holds the wheel in a session.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyKind {
    /// The simulated wheel, patient and IMUs.
    Simulated,
    /// The first real force-feedback wheel found, held by the patient.
    #[cfg(any(target_os = "linux", windows))]
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

impl LiveSummary {
    /// The patient's own arm lengths (upper arm, elbow to grip, m) this summary carries once
    /// the session has measured them (`arm_calibrated` 1), for the screen's arm inset.
    pub fn measured_arm_lengths_m(&self) -> Option<[f64; 2]> {
        let x = |k: &str| self.extra.get(k).copied();
        (x("arm_calibrated") == Some(1.0))
            .then(|| Some([x("upper_arm_m")?, x("forearm_m")?]))
            .flatten()
    }
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

/// Who watches a running session from the recorder thread (the therapist link, the patient's
/// screen). Both methods must return quickly and never block.
pub trait SessionObserver: Send {
    /// Every tick's record, in order.
    fn on_tick(&mut self, _record: &TickRecord) {}
    /// Every live summary (every [`SUMMARY_EVERY_S`] of session time).
    fn on_summary(&mut self, _summary: &LiveSummary) {}
}

impl<T: SessionObserver + ?Sized> SessionObserver for &mut T {
    fn on_tick(&mut self, record: &TickRecord) {
        (**self).on_tick(record);
    }

    fn on_summary(&mut self, summary: &LiveSummary) {
        (**self).on_summary(summary);
    }
}

/// Nobody watches (a replay, a benchmark).
impl SessionObserver for () {}

/// Tells the log and the live summaries when the wheel is away (unplugged, within the replug
/// grace) and how often it came back, from what the haptic thread leaves in [`Controls`] (its
/// state now: at `--speed max` it runs up to the recorder ring ahead of the tick watched).
struct WheelWatch<'a, O> {
    controls: &'a Controls,
    inner: O,
    away: bool,
    /// Force commands the wheel refused by the last tick watched (its `/wheel` record).
    write_failures: u64,
}

impl<O: SessionObserver> SessionObserver for WheelWatch<'_, O> {
    fn on_tick(&mut self, record: &TickRecord) {
        if record.wheel.write_failures > self.write_failures {
            if self.write_failures == 0 {
                tracing::warn!(
                    tick = record.tick,
                    "the wheel refused a force command (counted; a run over {} ms stops the session)",
                    plant::MAX_REFUSED_WRITES_NS / 1_000_000
                );
            }
            self.write_failures = record.wheel.write_failures;
        }
        let away = self.controls.wheel_away.load(Ordering::Relaxed);
        if away != self.away {
            self.away = away;
            if away {
                tracing::warn!(
                    tick = record.tick,
                    "the wheel is gone (unplugged?): the exercise is paused at zero torque until it is back"
                );
            } else {
                tracing::info!(
                    tick = record.tick,
                    "the wheel is back: the exercise resumes with a soft start"
                );
            }
        }
        self.inner.on_tick(record);
    }

    fn on_summary(&mut self, summary: &LiveSummary) {
        let mut summary = summary.clone();
        summary
            .extra
            .insert("wheel_unplugged".to_owned(), f64::from(u8::from(self.away)));
        let replugs = self.controls.wheel_replugs.load(Ordering::Relaxed);
        summary
            .extra
            .insert("wheel_replugs".to_owned(), f64::from(replugs));
        summary.extra.insert(
            "wheel_write_failures".to_owned(),
            self.write_failures as f64,
        );
        self.inner.on_summary(&summary);
    }
}

/// Two observers, told in order.
impl<A: SessionObserver, B: SessionObserver> SessionObserver for (A, B) {
    fn on_tick(&mut self, record: &TickRecord) {
        self.0.on_tick(record);
        self.1.on_tick(record);
    }

    fn on_summary(&mut self, summary: &LiveSummary) {
        self.0.on_summary(summary);
        self.1.on_summary(summary);
    }
}

/// Run a session until its exercise time reaches its duration, its course is done or
/// `controls.stop` is set; `observer` watches it from the recorder thread.
pub fn run(
    opts: &SessionOptions,
    controls: &Controls,
    observer: &mut dyn SessionObserver,
) -> anyhow::Result<SessionReport> {
    run_body(opts, controls, observer, None)
}

/// Run a session as [`run`] does, around `body` (a recording's raw inputs for a replay, a
/// wheel opened by the caller) instead of the one `opts.body` names; `facts` describe it in
/// the new recording (`None`: a body of the kind `opts.body` names).
pub fn run_with_body(
    opts: &SessionOptions,
    controls: &Controls,
    observer: &mut dyn SessionObserver,
    body: plant::Body,
    facts: Option<record::BodyFacts>,
) -> anyhow::Result<SessionReport> {
    run_body(opts, controls, observer, Some((body, facts)))
}

/// What the recording says about who held the wheel in a session of `cfg` on `kind`.
fn body_facts(cfg: &StationConfig, kind: BodyKind, plant: &plant::Plant) -> record::BodyFacts {
    use record::raw::{ArmFacts, BodyKindName};
    let wheel = plant.wheel_facts();
    let (name, arm) = match kind {
        BodyKind::Simulated => (
            BodyKindName::Simulated,
            Some(ArmFacts {
                guided: cfg.arm.sim_mounting == arm::MountingMode::Guided,
                geometry: cfg.sim_arm.geometry,
                swivel_rad: cfg.sim_arm.swivel_mean_rad,
            }),
        ),
        #[cfg(any(target_os = "linux", windows))]
        BodyKind::RealWheel => (
            BodyKindName::Real,
            plant.range_of_motion_rad().map(|_| ArmFacts {
                guided: true,
                geometry: cfg.arm.geometry,
                swivel_rad: cfg.arm.swivel_rad,
            }),
        ),
    };
    record::BodyFacts {
        kind: name,
        wheel_profile: wheel.profile.clone(),
        wheel_max_torque_nm: wheel.max_torque_nm,
        encoder_step_rad: wheel.encoder_step_rad,
        arm,
        replug_grace_ns: Some(plant.replug_grace_ns()),
    }
}

/// The recorder's account with the session's rests in its measures (time, s, and how many),
/// so they reach the hub with them.
fn with_rests(mut outcome: RecorderOutcome, haptic: &HapticOutcome) -> RecorderOutcome {
    let named = &mut outcome.measures.named;
    named.insert("rest_s".to_owned(), haptic.rest_s);
    named.insert("rests".to_owned(), f64::from(haptic.rests));
    outcome
}

/// The session's recording, created with its metadata (none without `opts.record`).
fn start_recording(
    opts: &SessionOptions,
    start_unix_ns: u64,
    facts: record::BodyFacts,
) -> anyhow::Result<Option<McapRecorder>> {
    let cfg = &opts.config;
    let rate = cfg.session.loop_rate_hz;
    Ok(match &opts.record {
        Some(path) => {
            // Room for the whole planned recording, or no session.
            disk_space::ensure_room(path, cfg.session.duration_s)?;
            let meta = SessionMetadata {
                exercise: cfg.session.exercise.clone(),
                seed: cfg.session.seed,
                patient_id: cfg.session.patient_id.clone(),
                loop_rate_hz: rate,
                config_toml: toml::to_string(cfg).unwrap_or_default(),
                // A session is replayable only with its course: record the regimen as well.
                regimen_toml: opts
                    .regimen
                    .as_ref()
                    .map(|r| toml::to_string(r).unwrap_or_default()),
                body: Some(facts),
                format_version: record::types::FORMAT_VERSION,
                difficulty: opts.difficulty.clone(),
                clinic: cfg.session.clinic.clone(),
            };
            Some(
                McapRecorder::create(path, start_unix_ns, &meta)
                    .context("cannot start recording")?
                    .fill_disk_at(faults::disk_full_at_ns(&cfg.faults)),
            )
        }
        None => None,
    })
}

/// Write every slot of the haptic → recorder ring once (then empty it) before the loop
/// starts: its memory is otherwise first touched by the haptic thread, a page fault on the
/// 1 kHz thread every few ticks through the ring's first lap (2 000 minor faults in its first
/// 8 s, measured with `telerehab bench loop`; none after).
fn prefault_ring(
    producer: &mut rtrb::Producer<TickRecord>,
    consumer: &mut rtrb::Consumer<TickRecord>,
) {
    while producer.push(TickRecord::default()).is_ok() {}
    while consumer.pop().is_ok() {}
}

/// The safety claim of a session, in N·m at the motor, in the log (loudly when the wheel's
/// rating is unknown).
fn log_ceiling(plant: &plant::Plant) {
    let ceiling = plant.ceiling();
    if ceiling.assumed {
        tracing::warn!("{ceiling}");
    } else {
        tracing::info!("{ceiling}");
    }
}

fn run_body(
    opts: &SessionOptions,
    controls: &Controls,
    observer: &mut dyn SessionObserver,
    given: Option<(plant::Body, Option<record::BodyFacts>)>,
) -> anyhow::Result<SessionReport> {
    let cfg = &opts.config;
    cfg.validate()?;
    let rate = cfg.session.loop_rate_hz;
    let total_ticks = (cfg.session.duration_s * rate).round() as u64;
    let start_unix_ns = opts.clock.unix_ns();
    // Devices first: a session that cannot start must not leave an empty recording behind.
    let course = course::build(cfg, opts.regimen.as_ref())?;
    let exercises = course.len();
    // What the recorder needs of the exercises, taken before the plant owns the course.
    let target_steps = course
        .iter()
        .map(|s| s.exercise.target_steps().clone())
        .collect();
    // The standard assessment's parts have their own results, apart from the session's.
    let apart = course
        .iter()
        .map(|s| exercises::assessment::is_assessment_name(&s.exercise.name))
        .collect();
    // The exercises that cue the patient to sit up (never the assessment's: `course::build`).
    let trunk_cued = course.iter().map(|s| s.trunk_cue_deg.is_some()).collect();
    let (given_body, given_facts) = given.unzip();
    let mut plant = match (given_body, opts.body) {
        (Some(body), _) => plant::Plant::new(cfg, body, course)?,
        (None, BodyKind::Simulated) => plant::Plant::new(
            cfg,
            plant::Body::simulated(cfg, opts.pacing == Pacing::RealTime, opts.clock.clone())?,
            course,
        )?,
        #[cfg(any(target_os = "linux", windows))]
        (None, BodyKind::RealWheel) => plant::Plant::new(
            cfg,
            plant::Body::first_real_wheel(cfg, opts.clock.clone())?,
            course,
        )?,
    };
    let facts = given_facts
        .flatten()
        .unwrap_or_else(|| body_facts(cfg, opts.body, &plant));
    log_ceiling(&plant);
    let recorder = start_recording(opts, start_unix_ns, facts)?;
    let (mut producer, mut consumer) = rtrb::RingBuffer::<TickRecord>::new(RING_CAPACITY);
    prefault_ring(&mut producer, &mut consumer);
    let haptic_done = Arc::new(AtomicBool::new(false));
    let period_ns = (1e9 / rate).round() as u64;
    let summary_every = ((SUMMARY_EVERY_S * rate).round() as u64).max(1);
    let flush_every = ((FLUSH_EVERY_S * rate).round() as u64).max(1);
    let pacing = opts.pacing;
    let isolate_core = opts.isolate_core;
    let clock = &opts.clock;
    let plan = RecorderPlan {
        period_ns,
        expected_ticks: total_ticks,
        summary_every,
        flush_every,
        arm_lengths_m: [cfg.arm.geometry.upper_arm_m, cfg.arm.geometry.forearm_m],
        trunk_threshold_deg: cfg.arm.trunk_threshold_deg,
        trunk_cued,
        roads: course::roads(cfg, opts.regimen.as_ref())?,
        target_steps,
        apart,
    };

    let ending = std::sync::OnceLock::new();
    let (haptic, recorder_outcome, summaries) = std::thread::scope(|scope| -> anyhow::Result<_> {
        let done = haptic_done.clone();
        let ending = &ending;
        let rec_thread = std::thread::Builder::new()
            .name("recorder".into())
            .spawn_scoped(scope, move || {
                let mut watched = WheelWatch {
                    controls,
                    inner: observer,
                    away: false,
                    write_failures: 0,
                };
                recorder_loop(consumer, recorder, &done, plan, &mut watched, ending)
            })
            .context("cannot start the recorder thread")?;
        let haptic_thread = std::thread::Builder::new()
            .name("haptic".into())
            .spawn_scoped(scope, move || {
                let mut outcome = haptic::run(
                    &mut plant,
                    &mut producer,
                    total_ticks,
                    pacing,
                    isolate_core,
                    controls,
                    clock,
                );
                outcome.arm_failure = plant.arm_failure().map(ToString::to_string);
                outcome
            })
            .context("cannot start the haptic thread")?;
        let haptic = haptic_thread.join();
        if let Ok(h) = &haptic {
            let _ = ending.set(recorder::SessionEnding {
                reason: end_reason::ended_by(h),
                scores: h.exercise_scores.clone(),
            });
        }
        haptic_done.store(true, Ordering::Release);
        let (rec, summaries) = rec_thread
            .join()
            .map_err(|_| anyhow::anyhow!("recorder thread panicked"))?;
        let haptic =
            haptic.map_err(|_| anyhow::anyhow!("haptic thread panicked (torque was zeroed)"))?;
        Ok((haptic, rec, summaries))
    })?;

    let recorder_outcome = with_rests(recorder_outcome, &haptic);
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
