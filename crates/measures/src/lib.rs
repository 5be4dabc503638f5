//! A session's measures from its ticks: the recorder thread (and a report reading a
//! recording) feeds every tick to a [`MeasureCollector`], which keeps the cheap live measures
//! up to date for the summaries and, at the end, computes the whole session's measures
//! (`metrics` crate: movements, SPARC, LDLJ, peak speed, movement time, speed peaks, ranges of
//! motion, time active, reactions to the target's steps) and names them, with the work of the
//! hand and of the assistance and the figures the recorder tallied (time, scores, pauses,
//! assistance: `session::outcome`), for the recording's `/metrics` channel and the hub; and
//! each exercise's own results from its [`ExerciseScores`].
//!
//! The measures sample the session at [`MEASURE_RATE_HZ`]: the wheel angle is averaged over
//! each block of ticks (a boxcar against aliasing; arm movement lies below ~5 Hz and SPARC
//! looks no higher than 10 Hz), which keeps an hour's series at 2.9 MB per signal instead of
//! 29 MB. Only the exercise is measured: ticks with the exercise paused (the arm procedure at
//! the start, the patient's pauses) are left out, each stretch between pauses a run of its own
//! (no speed is taken across a pause). Joint angles are taken while the arm sensing is
//! tracking; the trunk's measures while a sternum IMU is tracked ([`trunk`]).
//!
//! The series wait for the end of the session in a [`SeriesStore`]: a recorded session spills
//! them to a temporary file on the recording's disk, so that its resident memory stays flat
//! however long it runs ([`series`]). Below the session: it reads ticks as the `record` crate
//! types them, no thread, clock or device; its only I/O is that temporary file.

use exercises::TargetSteps;
use metrics::{
    DirectedStep, LiveMeasures, MetricError, ResponseParams, SessionMeasures, SessionParams,
    TargetStep, directed_step_responses, session_measures_of_runs, step_responses,
};
use record::{
    ArmSetup, ExerciseResult, MetricsSample, MovementSample, TickRecord, Watchdog, WheelSample,
};
use std::collections::BTreeMap;
use std::path::Path;
use trunk::TrunkTally;

pub mod series;
pub mod trunk;

use series::SeriesSample;
pub use series::{SeriesLost, SeriesStore};

/// A session's measures at its end.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Measures {
    /// The movement analysis; `None` when it could not be made ([`Self::error`] says why).
    pub session: Option<SessionMeasures>,
    /// Every measure by name, the unit in the name, finite values only: what the recording's
    /// `/metrics` channel holds and the hub stores.
    pub named: BTreeMap<String, f64>,
    /// Why the movement analysis is missing.
    pub error: Option<String>,
}

/// One exercise's own scores at the end of a session (what the recorder names and records
/// as its results; the session's haptic thread scores them).
#[derive(Clone, Debug, PartialEq)]
pub struct ExerciseScores {
    /// Its place in the course, from 0.
    pub index: u32,
    /// The regimen's short name (`sine-road`).
    pub kind: String,
    /// Its prescribed duration, s.
    pub prescribed_s: f64,
    /// Its driving scores (a road exercise).
    pub driving: Option<exercises::DrivingSummary>,
    /// Its dial scores (the dial task).
    pub dial: Option<exercises::DialSummary>,
    /// Its strength results (the strength test).
    pub strength: Option<exercises::StrengthSummary>,
    /// The haptic sweep's level it ran (a level of a haptic sweep).
    pub sweep: Option<exercises::SweepLevel>,
    /// Exercise time it took, s, when it ran to its end (`None`: the session ended first).
    pub completion_time_s: Option<f64>,
}

/// Rate of the measures' series, Hz.
pub const MEASURE_RATE_HZ: f64 = 100.0;

/// A change of the target by at least this much from one tick to the next is a step of the
/// target (a dial step jumps by twice its amplitude in one tick; a continuous target moving
/// this fast in 1 ms would turn at 50 rad/s), rad.
pub const TARGET_STEP_MIN_RAD: f64 = 0.05;

/// A lane shift's response is looked for from this long before the car reaches it: the
/// patient sees the shift coming on the road ahead and may steer before getting there (the
/// simulated patient, steered by a driver looking 0.6 s ahead, starts some 0.4 s early), s.
pub const LANE_SHIFT_LEAD_S: f64 = 2.0;

/// The most target steps kept (a step every 2 s for over 5 hours), so memory stays bounded.
const MAX_TARGET_STEPS: usize = 10_000;

/// The joints measured, in the order of [`LiveMeasures`]' samples.
const JOINTS: [&str; 2] = ["shoulder_elevation", "elbow_flexion"];

/// Collects a session's series and running measures, tick by tick.
#[derive(Debug)]
pub struct MeasureCollector {
    /// Ticks averaged into one sample.
    ticks_per_sample: u64,
    /// One tick, s.
    tick_s: f64,
    /// Sum and count of the finite wheel angles of the current block, rad.
    block_sum_rad: f64,
    block_ticks: u64,
    block_finite: u64,
    /// Session time of the current block's first tick, s.
    block_t_s: f64,
    /// The series at [`MEASURE_RATE_HZ`] of the exercise's ticks only: wheel angle, its
    /// session time, the joint angles.
    series: SeriesStore,
    /// Where each run (a stretch of exercise between pauses) starts in the series.
    runs: Vec<usize>,
    /// The last sample went into the current run (no pause since).
    in_run: bool,
    /// The current run's last wheel angle, rad (0 before its first sample).
    run_last_rad: f64,
    live: LiveMeasures,
    /// Positive work of the assist torque on the wheel, J.
    assist_work_j: f64,
    /// Positive work of the patient's hand on the wheel, J, from the hand's torque as
    /// estimated on every wheel (`assist::effort`; the simulation's true torque is only its
    /// check). `None` for recordings made before the estimate.
    patient_work_j: Option<f64>,
    /// The wheel's velocity of the last ticks, oldest first (rad/s): the hand's estimate is
    /// of `assist::HAND_ESTIMATE_LAG_S` before its tick, and its power is taken with the
    /// velocity of that time.
    recent_vel_rad_s: std::collections::VecDeque<f64>,
    /// That lag in ticks.
    hand_lag_ticks: usize,
    /// The exercise of each run (parallel to `runs`): a run never spans two exercises.
    run_exercise: Vec<u32>,
    /// The exercise of the last tick taken.
    exercise_now: u32,
    /// Each exercise's own tallies, by its index in the course.
    tallies: Vec<ExerciseTally>,
    /// The steps of the target, in time order, at most [`MAX_TARGET_STEPS`].
    target_steps: Vec<NotedStep>,
    /// The last tick's target, rad (`None` at the start of an exercise).
    last_target_rad: Option<f64>,
    /// Which of each exercise's target changes are steps, by its index in the course; empty
    /// when not told (every jump of the target is then a step).
    steps_of: Vec<TargetSteps>,
    /// Which exercises, by index in the course, are measured apart from the session (the
    /// standard assessment's parts): their runs and steps are left out of the session's
    /// measures, so that exercise trends never mix them in; their own results stay.
    apart: Vec<bool>,
    /// The next lane shift of the exercise in progress to meet, and the car's distance along
    /// its road at the last tick, m (`None` at the start of an exercise).
    next_shift: usize,
    last_s_m: Option<f64>,
    /// The trunk's excursions, when a sternum IMU is worn.
    trunk: TrunkTally,
}

/// A step of the target as noted: the index into the series of the sample it falls in, the
/// exercise whose tick it came on (a step on an exercise's last tick falls in the sample of
/// the next one's first: it is no step of the next exercise), and the step.
#[derive(Clone, Copy, Debug, PartialEq)]
struct NotedStep {
    index: usize,
    exercise: u32,
    cue: Cue,
}

/// A step the wheel is to respond to.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cue {
    /// The target jumped to this angle, rad.
    Jump(f64),
    /// The lane shifted; the wheel must first turn this way (±1).
    Shift(f64),
}

/// What a response to a step gives, of either kind of step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Reaction {
    /// The target was on the patient's left (a dial target at a positive angle, a lane
    /// change to the left): the report splits by side for a neglected side.
    left: bool,
    /// Only to an unpredictable step (a dial target's random jump): a lane shift is seen
    /// coming, so the time to meet it is no reaction time ([`metrics::robot`]).
    reaction_time_s: Option<f64>,
    /// To a predictable cue (a lane shift), whether the turn started sooner than the shortest
    /// reaction after it ([`metrics::MIN_REACTION_TIME_S`]); `None` for an unpredictable step
    /// or when the wheel did not move.
    anticipated: Option<bool>,
    initial_direction_error_deg: Option<f64>,
    path_length_ratio: Option<f64>,
    /// An unpredictable step's response as one movement from rest to rest
    /// ([`metrics::StepResponse::movement`]).
    movement: Option<metrics::Movement>,
}

/// What the collector counts of one exercise, tick by tick.
#[derive(Clone, Debug, Default)]
struct ExerciseTally {
    /// Ticks the exercise ran (not paused).
    active_ticks: u64,
    /// Sum of the squared wheel tracking error (ideal angle − wheel angle) and its ticks, rad².
    tracking_sq_rad2: f64,
    tracking_ticks: u64,
    /// Smallest and largest shoulder elevation and elbow flexion while tracked, rad.
    joint_min_rad: [f64; 2],
    joint_max_rad: [f64; 2],
}

impl ExerciseTally {
    fn new() -> Self {
        Self {
            joint_min_rad: [f64::INFINITY; 2],
            joint_max_rad: [f64::NEG_INFINITY; 2],
            ..Self::default()
        }
    }
}

impl MeasureCollector {
    /// A collector for a loop at `loop_rate_hz` expected to run `expected_ticks`, its series
    /// in memory (no recording directory to spill them to: a session not recorded, a
    /// recording already read).
    pub fn new(loop_rate_hz: f64, expected_ticks: u64) -> Self {
        let samples = (expected_ticks / ticks_per_sample(loop_rate_hz)) as usize + 1;
        Self::with_series(loop_rate_hz, SeriesStore::in_memory(samples))
    }

    /// A collector for a loop at `loop_rate_hz`, its series spilled to a temporary file in
    /// `dir`, the recording's directory (in memory when no file can be made there).
    pub fn spilling_in(dir: &Path, loop_rate_hz: f64) -> Self {
        Self::with_series(loop_rate_hz, SeriesStore::spilled_in(dir))
    }

    /// The hand's positive work on the wheel this tick: its estimated torque (of
    /// `assist::HAND_ESTIMATE_LAG_S` ago) times the wheel's velocity of that time.
    fn add_patient_work(&mut self, w: &WheelSample) {
        let lag = self.hand_lag_ticks;
        if self.recent_vel_rad_s.len() > lag {
            self.recent_vel_rad_s.pop_front();
        }
        self.recent_vel_rad_s.push_back(w.velocity_rad_s);
        let then_rad_s = self.recent_vel_rad_s[0];
        if let Some(hand_nm) = w.hand_est_nm.filter(|h| h.is_finite()) {
            let work = self.patient_work_j.get_or_insert(0.0);
            if self.recent_vel_rad_s.len() > lag && then_rad_s.is_finite() {
                *work += (hand_nm * then_rad_s).max(0.0) * self.tick_s;
            }
        }
    }

    /// A collector for a loop at `loop_rate_hz` keeping its series in `series`.
    pub fn with_series(loop_rate_hz: f64, series: SeriesStore) -> Self {
        let per_sample = ticks_per_sample(loop_rate_hz);
        let fs = loop_rate_hz / per_sample as f64;
        Self {
            ticks_per_sample: per_sample,
            tick_s: 1.0 / loop_rate_hz,
            block_sum_rad: 0.0,
            block_ticks: 0,
            block_finite: 0,
            block_t_s: 0.0,
            series,
            runs: Vec::new(),
            in_run: false,
            run_last_rad: 0.0,
            live: LiveMeasures::new(fs, &JOINTS, &SessionParams::default())
                .expect("the default parameters and a positive rate are valid"),
            assist_work_j: 0.0,
            patient_work_j: None,
            recent_vel_rad_s: std::collections::VecDeque::new(),
            hand_lag_ticks: (assist::HAND_ESTIMATE_LAG_S * loop_rate_hz).round() as usize,
            run_exercise: Vec::new(),
            exercise_now: 0,
            tallies: Vec::new(),
            target_steps: Vec::new(),
            last_target_rad: None,
            steps_of: Vec::new(),
            apart: Vec::new(),
            next_shift: 0,
            last_s_m: None,
            trunk: TrunkTally::default(),
        }
    }

    /// The same collector counting the trunk beyond `threshold_deg` (`[arm]
    /// trunk_threshold_deg`) as compensating; 10° when not told.
    #[must_use]
    pub fn with_trunk_threshold_deg(mut self, threshold_deg: f64) -> Self {
        self.trunk = TrunkTally::new(threshold_deg);
        self
    }

    /// The same collector told which exercises (by index in the course) cue the patient to
    /// sit up (the regimen's `[trunk] cue_deg`; never the standard assessment): their cues are
    /// counted as `trunk_cues`. Call after [`Self::with_trunk_threshold_deg`].
    pub fn with_trunk_cued(mut self, cued: Vec<bool>) -> Self {
        self.trunk = std::mem::take(&mut self.trunk).with_cued(cued);
        self
    }

    /// The same collector told which of each exercise's target changes are steps to respond
    /// to (by its index in the course; `exercises::Exercise::target_steps`): the stepping dial's
    /// jumps and the lane change's shifts, not the strength test's side changes. Without it
    /// every jump of the target is a step.
    #[must_use]
    pub fn with_target_steps(mut self, steps_of: Vec<TargetSteps>) -> Self {
        self.steps_of = steps_of;
        self
    }

    /// The same collector told which exercises (by index in the course) are measured apart
    /// from the session: the standard assessment's parts (`exercises::assessment`).
    #[must_use]
    pub fn with_apart(mut self, apart: Vec<bool>) -> Self {
        self.apart = apart;
        self
    }

    /// Whether exercise `index` is measured apart from the session.
    fn is_apart(&self, index: u32) -> bool {
        self.apart.get(index as usize).copied().unwrap_or(false)
    }

    /// The tally of exercise `index`, made on its first tick.
    fn tally(&mut self, index: u32) -> &mut ExerciseTally {
        let i = index as usize;
        if self.tallies.len() <= i {
            self.tallies.resize(i + 1, ExerciseTally::new());
        }
        &mut self.tallies[i]
    }

    /// Sampling rate of the series, Hz.
    pub fn fs_hz(&self) -> f64 {
        1.0 / (self.tick_s * self.ticks_per_sample as f64)
    }

    /// Takes one tick (nothing of it while the exercise is paused).
    pub fn add(&mut self, rec: &TickRecord) {
        if rec.score.paused {
            if self.in_run {
                self.live.break_signal();
            }
            (self.block_sum_rad, self.block_ticks, self.block_finite) = (0.0, 0, 0);
            self.in_run = false;
            return;
        }
        let exercise = rec.score.exercise_index;
        let changed = exercise != self.exercise_now;
        if changed {
            // A run never spans two exercises: each is measured over its own span.
            (self.block_sum_rad, self.block_ticks, self.block_finite) = (0.0, 0, 0);
            self.in_run = false;
            self.exercise_now = exercise;
            (self.next_shift, self.last_s_m) = (0, None);
        }
        let w = &rec.wheel;
        // The session's fade-out is no exercise's own time.
        let stopping = matches!(w.watchdog, Watchdog::Stopping | Watchdog::Stopped);
        self.note_steps(rec, changed || stopping);
        if !stopping {
            let moving = self.live.moving();
            self.trunk
                .add(rec.arm.as_ref(), exercise, moving, self.tick_s);
        }
        let tally = self.tally(exercise);
        let tracking_rad = w.target_rad - w.angle_rad;
        if !stopping {
            tally.active_ticks += 1;
            // An exercise's first tick runs before the card between two exercises, with the
            // wheel where the last one left it: no tracking error of the new one's.
            if tracking_rad.is_finite() && !changed {
                tally.tracking_sq_rad2 += tracking_rad * tracking_rad;
                tally.tracking_ticks += 1;
            }
        }
        if w.velocity_rad_s.is_finite() && rec.assist.active && rec.assist.torque_nm.is_finite() {
            self.assist_work_j += (rec.assist.torque_nm * w.velocity_rad_s).max(0.0) * self.tick_s;
        }
        self.add_patient_work(w);
        if self.block_ticks == 0 {
            self.block_t_s = rec.t_ns as f64 * 1e-9;
        }
        if w.angle_rad.is_finite() {
            self.block_sum_rad += w.angle_rad;
            self.block_finite += 1;
        }
        self.block_ticks += 1;
        if self.block_ticks < self.ticks_per_sample {
            return;
        }
        if !self.in_run {
            self.runs.push(self.series.len());
            self.run_exercise.push(self.exercise_now);
            self.in_run = true;
            self.run_last_rad = 0.0;
        }
        // A block without a finite reading holds the run's last sample, keeping the time base.
        let angle = if self.block_finite > 0 {
            self.block_sum_rad / self.block_finite as f64
        } else {
            self.run_last_rad
        };
        (self.block_sum_rad, self.block_ticks, self.block_finite) = (0.0, 0, 0);
        self.run_last_rad = angle;
        let joints = match &rec.arm {
            Some(arm) if arm.setup == ArmSetup::Tracking => {
                [arm.shoulder_elevation_rad, arm.elbow_flexion_rad]
            }
            _ => [f64::NAN; 2],
        };
        if joints.iter().all(|j| j.is_finite()) {
            let tally = self.tally(exercise);
            for (k, j) in joints.iter().enumerate() {
                tally.joint_min_rad[k] = tally.joint_min_rad[k].min(*j);
                tally.joint_max_rad[k] = tally.joint_max_rad[k].max(*j);
            }
        }
        // Joints kept when both are finite.
        self.series.push(SeriesSample {
            wheel_rad: angle,
            t_s: self.block_t_s,
            joints_rad: Some(joints),
        });
        // Same joint count as given to `new`: cannot fail.
        let _ = self.live.update(angle, &joints);
    }

    /// Notes the steps between the last tick and this one of the exercise in progress, as it
    /// has them (none across a change of exercise or in the fade-out: `skip`).
    fn note_steps(&mut self, rec: &TickRecord, skip: bool) {
        let exercise = rec.score.exercise_index as usize;
        if self.steps_of.is_empty() {
            self.note_target(rec.wheel.target_rad, skip);
            return;
        }
        match self.steps_of.get(exercise) {
            Some(TargetSteps::Jumps) => self.note_target(rec.wheel.target_rad, skip),
            Some(TargetSteps::LaneShifts(_)) => self.note_lane_shift(rec, skip),
            _ => {}
        }
    }

    /// Whether exercise `index`'s steps are jumps of the target (every exercise's when not
    /// told: [`Self::with_target_steps`]).
    fn steps_are_jumps(&self, index: u32) -> bool {
        self.steps_of.is_empty()
            || matches!(self.steps_of.get(index as usize), Some(TargetSteps::Jumps))
    }

    /// Notes a step of the exercise in progress at the sample the tick falls in.
    fn note(&mut self, cue: Cue) {
        self.target_steps.push(NotedStep {
            index: self.series.len(),
            exercise: self.exercise_now,
            cue,
        });
    }

    /// Notes a jump of the target between the last tick and this one (none when `skip`).
    fn note_target(&mut self, target_rad: f64, skip: bool) {
        if !target_rad.is_finite() {
            return;
        }
        if let Some(last) = self.last_target_rad.filter(|_| !skip)
            && (target_rad - last).abs() >= TARGET_STEP_MIN_RAD
            && self.target_steps.len() < MAX_TARGET_STEPS
        {
            self.note(Cue::Jump(target_rad));
        }
        self.last_target_rad = Some(target_rad);
    }

    /// The next lane shift to meet of `exercise`, if it is a lane change with one left.
    fn lane_shift(&self, exercise: usize) -> Option<exercises::LaneShift> {
        match self.steps_of.get(exercise) {
            Some(TargetSteps::LaneShifts(shifts)) => shifts.get(self.next_shift).copied(),
            _ => None,
        }
    }

    /// Notes the lane shifts the car reached between the last tick and this one (none when
    /// `skip`; those passed before the first tick of the exercise are none either).
    fn note_lane_shift(&mut self, rec: &TickRecord, skip: bool) {
        let Some(s_m) = rec.vehicle.map(|v| v.s_m).filter(|s| s.is_finite()) else {
            return;
        };
        let exercise = rec.score.exercise_index as usize;
        while let Some(shift) = self.lane_shift(exercise).filter(|sh| sh.s_m <= s_m) {
            let reached = self.last_s_m.is_some_and(|last| last < shift.s_m);
            if reached && !skip && self.target_steps.len() < MAX_TARGET_STEPS {
                self.note(Cue::Shift(shift.direction));
            }
            self.next_shift += 1;
        }
        self.last_s_m = Some(s_m);
    }

    /// The wheel's responses to the target's steps, run by run, of exercise `only` or of all;
    /// empty before [`Self::finish`] (the series not in memory).
    fn responses(&self, only: Option<u32>) -> Vec<Reaction> {
        let Some(series) = self.series.loaded() else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for (r, &e) in self.runs().zip(&self.run_exercise) {
            let left_out = match only {
                Some(o) => o != e,
                None => self.is_apart(e),
            };
            if left_out || r.len() < 2 {
                continue;
            }
            let in_run = || {
                self.target_steps
                    .iter()
                    .filter(|s| s.exercise == e && r.contains(&s.index))
            };
            let shifts: Vec<DirectedStep> = in_run()
                .filter_map(|s| match s.cue {
                    Cue::Shift(direction) => Some(DirectedStep {
                        index: s.index - r.start,
                        direction,
                    }),
                    Cue::Jump(_) => None,
                })
                .collect();
            let mut steps: Vec<TargetStep> = in_run()
                .filter_map(|s| match s.cue {
                    Cue::Jump(target_rad) => Some(TargetStep {
                        index: s.index - r.start,
                        target_rad,
                    }),
                    Cue::Shift(_) => None,
                })
                .collect();
            let angle = &series.wheel_rad[r.clone()];
            // Two steps in one sample: the first one's window is empty, the later one counts.
            steps.dedup_by(|later, first| {
                later.index == first.index && {
                    *first = *later;
                    true
                }
            });
            let params = ResponseParams::default();
            if let Ok(rs) = step_responses(angle, self.fs_hz(), &steps, &params) {
                out.extend(rs.into_iter().map(|r| Reaction {
                    left: r.step.target_rad > 0.0,
                    reaction_time_s: r.reaction_time_s,
                    anticipated: None,
                    initial_direction_error_deg: r.initial_direction_error_deg,
                    path_length_ratio: r.path_length_ratio,
                    movement: r.movement,
                }));
            }
            // Two shifts in one sample (none on a real road) would be out of order: the first kept.
            let mut shifts = shifts;
            shifts.dedup_by_key(|s| s.index);
            let fs_hz = self.fs_hz();
            if let Ok(rs) =
                directed_step_responses(angle, fs_hz, &shifts, LANE_SHIFT_LEAD_S, &params)
            {
                out.extend(rs.into_iter().map(|r| Reaction {
                    left: r.step.direction > 0.0,
                    reaction_time_s: None,
                    anticipated: r.anticipated(),
                    initial_direction_error_deg: r.initial_direction_error_deg,
                    path_length_ratio: None,
                    movement: None,
                }));
            }
        }
        out
    }

    /// The live measures for a summary, name → value (unit in the name).
    pub fn live(&self) -> BTreeMap<String, f64> {
        let l = &self.live;
        let mut m = BTreeMap::from([
            ("movements".to_owned(), l.movements() as f64),
            ("active_s".to_owned(), l.active_s()),
            ("wheel_speed_deg_s".to_owned(), l.speed_rad_s().to_degrees()),
            (
                "peak_speed_deg_s".to_owned(),
                l.session_peak_speed_rad_s().to_degrees(),
            ),
            (
                "wheel_rom_deg".to_owned(),
                l.wheel_range().range.to_degrees(),
            ),
        ]);
        for j in l.joints().iter().filter(|j| j.min <= j.max) {
            m.insert(format!("{}_rom_deg", j.name), j.range.to_degrees());
        }
        m
    }

    /// One tick of the loop, s.
    pub fn tick_s(&self) -> f64 {
        self.tick_s
    }

    /// The session's measures, with `figures`: the session's time, scores, pauses and
    /// assistance as the recorder tallied them, by name (`session::outcome`); the series are
    /// read back whole for the analysis (and kept in memory for [`Self::sample`]).
    pub fn finish(&mut self, figures: BTreeMap<String, f64>) -> Measures {
        let analysed = if self.series.len() < 2 {
            Err(format!(
                "the exercise ran too briefly to measure ({} samples at {} Hz)",
                self.series.len(),
                self.fs_hz()
            ))
        } else {
            let fs_hz = self.fs_hz();
            let runs: Vec<_> = self
                .runs()
                .zip(&self.run_exercise)
                .filter(|(_, e)| !self.is_apart(**e))
                .map(|(r, _)| r)
                .collect();
            self.series
                .load()
                .map_err(|e| e.to_string())
                .and_then(|series| {
                    let joints: Vec<(&str, &[f64])> = [
                        (JOINTS[0], series.shoulder_elevation_rad.as_slice()),
                        (JOINTS[1], series.elbow_flexion_rad.as_slice()),
                    ]
                    .into_iter()
                    .filter(|(_, x)| !x.is_empty())
                    .collect();
                    let runs: Vec<&[f64]> =
                        runs.into_iter().map(|r| &series.wheel_rad[r]).collect();
                    session_measures_of_runs(&runs, fs_hz, &joints, &SessionParams::default())
                        .map_err(|e: MetricError| e.to_string())
                })
        };
        let mut named = BTreeMap::new();
        if let Ok(s) = &analysed {
            name_movement_measures(&mut named, s);
            name_step_responses(&mut named, &self.responses(None));
        }
        named.extend(figures);
        self.name_work(&mut named);
        self.trunk.name_session(&mut named);
        named.retain(|_, v| v.is_finite());
        let (session, error) = match analysed {
            Ok(s) => (Some(s), None),
            Err(e) => (None, Some(e)),
        };
        Measures {
            session,
            named,
            error,
        }
    }

    /// Each run's samples, as index ranges into the series.
    fn runs(&self) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
        let ends = self.runs.iter().skip(1).copied().chain([self.series.len()]);
        self.runs.iter().zip(ends).map(|(&a, b)| a..b)
    }

    /// The wheel's speed as the measures see it, run by run, (session time s, rad/s): each
    /// run's speed profile ([`metrics::speed_profile`]), the exercise's samples only (the
    /// series read back whole, as [`Self::finish`] does).
    pub fn speed_series(&mut self) -> Result<Vec<Vec<(f64, f64)>>, SeriesLost> {
        let lowpass_hz = SessionParams::default().lowpass_hz;
        let fs_hz = self.fs_hz();
        let runs: Vec<_> = self.runs().collect();
        let series = self.series.load()?;
        Ok(runs
            .into_iter()
            .map(|r| {
                let speed = metrics::speed_profile(&series.wheel_rad[r.clone()], fs_hz, lowpass_hz);
                series.t_s[r].iter().copied().zip(speed).collect()
            })
            .collect())
    }

    /// Each exercise's own results after [`Self::finish`]: the haptic thread's `scores` of
    /// each exercise started, with its active time, its wheel tracking error and the movement
    /// measures over its own runs (joint ranges while tracked); `name` gives the patient's
    /// name of a kind.
    pub fn exercise_results(
        &self,
        scores: &[ExerciseScores],
        name: impl Fn(&str) -> String,
    ) -> Vec<ExerciseResult> {
        scores
            .iter()
            .map(|s| {
                let mut named = BTreeMap::new();
                let tally = self.tallies.get(s.index as usize);
                if let Some(m) = self.exercise_measures(s.index) {
                    name_movement_measures(&mut named, &m);
                    let responses = self.responses(Some(s.index));
                    name_step_responses(&mut named, &responses);
                    if self.steps_are_jumps(s.index) {
                        name_step_movements(&mut named, &responses);
                    }
                }
                if let Some(t) = tally {
                    for (k, joint) in JOINTS.iter().enumerate() {
                        if t.joint_min_rad[k] <= t.joint_max_rad[k] {
                            let range = t.joint_max_rad[k] - t.joint_min_rad[k];
                            named.insert(format!("{joint}_rom_deg"), range.to_degrees());
                        }
                    }
                    if t.tracking_ticks > 0 {
                        let rms = (t.tracking_sq_rad2 / t.tracking_ticks as f64).sqrt();
                        named.insert("tracking_rms_error_deg".to_owned(), rms.to_degrees());
                    }
                }
                self.trunk.name_exercise(s.index, &mut named);
                name_exercise_scores(&mut named, s);
                named.retain(|_, v| v.is_finite());
                ExerciseResult {
                    index: s.index,
                    kind: s.kind.clone(),
                    name: match s.sweep {
                        Some(l) => sweep_level_name(&name(&s.kind), l),
                        None => name(&s.kind),
                    },
                    prescribed_s: s.prescribed_s,
                    active_s: tally.map_or(0.0, |t| t.active_ticks as f64 * self.tick_s),
                    scores: named,
                }
            })
            .collect()
    }

    /// The movement analysis of exercise `index`'s runs alone (none before [`Self::finish`],
    /// or when it ran too briefly).
    fn exercise_measures(&self, index: u32) -> Option<SessionMeasures> {
        let series = self.series.loaded()?;
        let runs: Vec<&[f64]> = self
            .runs()
            .zip(&self.run_exercise)
            .filter(|(r, e)| **e == index && !r.is_empty())
            .map(|(r, _)| &series.wheel_rad[r])
            .collect();
        if runs.iter().map(|r| r.len()).sum::<usize>() < 2 {
            return None;
        }
        session_measures_of_runs(&runs, self.fs_hz(), &[], &SessionParams::default()).ok()
    }

    /// The measures as the `/metrics` channel records them (movement times in session time),
    /// `m` from [`Self::finish`].
    pub fn sample(&self, m: &Measures) -> MetricsSample {
        // In memory after `finish` (which has no movements when the series are lost).
        let t_s = self.series.loaded().map_or(&[][..], |s| s.t_s.as_slice());
        MetricsSample {
            measures: m.named.clone(),
            fs_hz: self.fs_hz(),
            movements: m
                .session
                .iter()
                .flat_map(|s| &s.movements)
                .map(|mv| MovementSample {
                    start_s: t_s.get(mv.start_index).copied().unwrap_or(mv.start_s),
                    ..MovementSample::from(mv)
                })
                .collect(),
            error: m.error.clone().unwrap_or_default(),
            exercises: Vec::new(),
            end_reason: String::new(),
        }
    }

    /// The work of the assistance and of the patient's hand on the wheel.
    fn name_work(&self, named: &mut BTreeMap<String, f64>) {
        named.insert("assist_work_j".to_owned(), self.assist_work_j);
        if let Some(patient) = self.patient_work_j {
            named.insert("patient_work_j".to_owned(), patient);
            let total = patient + self.assist_work_j;
            if total > 0.0 {
                named.insert(
                    "patient_work_pct".to_owned(),
                    (100.0 * patient / total).min(100.0),
                );
            }
        }
    }
}

/// An exercise's own scores by name: lane keeping, time in lane, heading error and cones of
/// a road; the dial's mean absolute (the thesis's Appendix E measure) and RMS angle error;
/// the time it took when it ran to its end.
fn name_exercise_scores(named: &mut BTreeMap<String, f64>, s: &ExerciseScores) {
    let mut put = |name: &str, v: f64| {
        named.insert(name.to_owned(), v);
    };
    if let Some(d) = &s.driving {
        put("rms_lateral_m", d.rms_lateral_m);
        put("max_lateral_m", d.max_lateral_m);
        put("pct_in_lane", d.pct_in_lane);
        put("heading_rms_error_deg", d.rms_heading_error_deg);
        put("heading_max_error_deg", d.max_heading_error_deg);
        put("cone_hits", f64::from(d.cone_hits));
        put("road_exits", f64::from(d.road_exits));
    }
    if let Some(d) = &s.dial {
        put("dial_mean_abs_error_deg", d.mean_abs_error_deg);
        put("dial_rms_error_deg", d.rms_error_deg);
        put("dial_max_abs_error_deg", d.max_abs_error_deg);
    }
    if let Some(st) = &s.strength {
        for (side, r) in [("left", st.left), ("right", st.right)] {
            if let Some(r) = r {
                put(&format!("strength_peak_{side}_nm"), r.peak_nm);
                put(&format!("strength_sustained_{side}_nm"), r.sustained_nm);
                put(&format!("strength_{side}_s"), r.duration_s);
                let at_ceiling = r.stop == exercises::StrengthStop::Ceiling;
                put(
                    &format!("strength_{side}_at_ceiling"),
                    f64::from(u8::from(at_ceiling)),
                );
            }
        }
    }
    if let Some(l) = s.sweep {
        put(&l.parameter.level_measure(), l.level);
    }
    if let Some(t) = s.completion_time_s {
        put("completion_time_s", t);
    }
}

/// A haptic sweep level's name as the patient and the report read it: the exercise's, the
/// parameter and its level with the unit ("Haptic sweep: spring 0.4 N·m/rad").
fn sweep_level_name(plain: &str, l: exercises::SweepLevel) -> String {
    let level = format!("{:.4}", l.level);
    let level = level.trim_end_matches('0').trim_end_matches('.');
    format!(
        "{plain}: {} {level} {}",
        l.parameter.name(),
        l.parameter.unit()
    )
}

/// Each haptic sweep's levels (level, mean absolute dial error in degrees) in course order,
/// by parameter: the exercises whose scores name a sweep level
/// ([`exercises::SweepParameter::level_measure`]) and a dial error.
pub fn sweep_points(
    exercises: &[ExerciseResult],
) -> Vec<(exercises::SweepParameter, Vec<(f64, f64)>)> {
    let mut out: Vec<(exercises::SweepParameter, Vec<(f64, f64)>)> = Vec::new();
    for e in exercises {
        let Some(error) = e.scores.get("dial_mean_abs_error_deg") else {
            continue;
        };
        for (k, level) in &e.scores {
            let Some(p) = exercises::SweepParameter::of_level_measure(k) else {
                continue;
            };
            match out.iter_mut().find(|(q, _)| *q == p) {
                Some((_, points)) => points.push((*level, *error)),
                None => out.push((p, vec![(*level, *error)])),
            }
        }
    }
    out
}

/// The session's haptic sweep figures, a few per swept parameter for the hub (the levels
/// themselves are in the exercise results): `sweep_<parameter>_levels`, the mean of the
/// levels' mean absolute dial errors `sweep_<parameter>_mean_abs_error_deg`, and the
/// least-squares slope of that error against the level
/// `sweep_<parameter>_error_slope_deg_per_<unit>` (Appendix E: none with K, B, I; rising
/// with frequency).
pub fn sweep_of_exercises(named: &mut BTreeMap<String, f64>, exercises: &[ExerciseResult]) {
    for (p, points) in sweep_points(exercises) {
        let n = points.len() as f64;
        let base = format!("sweep_{}", p.name());
        named.insert(format!("{base}_levels"), n);
        let mean = points.iter().map(|q| q.1).sum::<f64>() / n;
        if mean.is_finite() {
            named.insert(format!("{base}_mean_abs_error_deg"), mean);
        }
        if let Some(slope) = exercises::sweep::error_slope(&points) {
            named.insert(
                format!("{base}_error_slope_deg_per_{}", p.unit_key()),
                slope,
            );
        }
    }
}

/// The session's strength figures: each `strength_*` measure of its exercises, the highest
/// when the test ran more than once; and no dial figure when no exercise was a dial task (the
/// strength test has no car either, but no needles).
pub fn strength_of_exercises(named: &mut BTreeMap<String, f64>, exercises: &[ExerciseResult]) {
    let no_dial = !exercises
        .iter()
        .any(|e| e.scores.contains_key("dial_rms_error_deg"));
    if !exercises.is_empty() && no_dial {
        named.remove("dial_rms_error_deg");
    }
    for (k, v) in exercises.iter().flat_map(|e| &e.scores) {
        if k.starts_with("strength_") && v.is_finite() {
            let best = named.entry(k.clone()).or_insert(*v);
            *best = best.max(*v);
        }
    }
}

/// Ticks of a loop at `loop_rate_hz` averaged into one sample of the series.
fn ticks_per_sample(loop_rate_hz: f64) -> u64 {
    ((loop_rate_hz / MEASURE_RATE_HZ).round() as u64).max(1)
}

/// The movement analysis's figures by name: counts, medians over the movements, peak speed,
/// time active, ranges of motion (degrees, as a therapist reads them).
fn name_movement_measures(named: &mut BTreeMap<String, f64>, s: &SessionMeasures) {
    let mut put = |name: &str, v: f64| {
        named.insert(name.to_owned(), v);
    };
    put("movements", s.movements.len() as f64);
    put("discrete_movements", s.discrete_movements as f64);
    put("active_s", s.active_s);
    put("active_pct", 100.0 * s.active_fraction);
    put("peak_speed_deg_s", s.peak_speed_rad_s.to_degrees());
    name_per_movement(
        named,
        [
            s.sparc,
            s.ldlj,
            s.movement_peak_speed_rad_s,
            s.movement_time_s,
            s.n_peaks,
            s.speed_metric,
        ],
    );
    let mut put = |name: &str, v: f64| {
        named.insert(name.to_owned(), v);
    };
    put("movements_per_min", s.movements_per_min);
    put("reversals_per_min", s.reversals_per_min);
    put("wheel_rom_deg", s.wheel_range.range.to_degrees());
    for j in &s.joints {
        put(&format!("{}_rom_deg", j.name), j.range.to_degrees());
        put(&format!("{}_min_deg", j.name), j.min.to_degrees());
        put(&format!("{}_max_deg", j.name), j.max.to_degrees());
    }
}

/// The measures of each movement by name, median and mean (`sparc_median`, `sparc_mean`, …),
/// from their summaries in [`PER_MOVEMENT`]'s order; a measure no movement has is left out.
fn name_per_movement(named: &mut BTreeMap<String, f64>, summaries: [metrics::Summary; 6]) {
    for ((name, scale), summary) in PER_MOVEMENT.into_iter().zip(summaries) {
        if let (Some(median), Some(mean)) = (summary.median, summary.mean) {
            named.insert(format!("{name}_median"), median * scale);
            named.insert(format!("{name}_mean"), mean * scale);
        }
    }
}

/// The measures taken of each movement, with the scale from the movement's unit (rad/s to
/// °/s for the peak speed).
const PER_MOVEMENT: [(&str, f64); 6] = [
    ("sparc", 1.0),
    ("ldlj", 1.0),
    ("movement_peak_speed_deg_s", 1.0_f64.to_degrees()),
    ("movement_time_s", 1.0),
    ("speed_peaks", 1.0),
    ("speed_metric", 1.0),
];

/// An exercise whose target steps (the stepping dial, the assessment's steps part): its
/// movements are the responses to the steps, each from its onset to its rest
/// ([`metrics::StepResponse::movement`]), not the free segmentation's, which on a wheel
/// that never rests between steps finds one long movement or none from rest to rest. The
/// per-movement measures of [`name_movement_measures`] are replaced, and left out when no
/// response came to rest before the next step; the dose (`movements`, `discrete_movements`)
/// stays the segmentation's.
fn name_step_movements(named: &mut BTreeMap<String, f64>, responses: &[Reaction]) {
    for (name, _) in PER_MOVEMENT {
        named.remove(&format!("{name}_median"));
        named.remove(&format!("{name}_mean"));
    }
    let moves: Vec<&metrics::Movement> = responses
        .iter()
        .filter_map(|r| r.movement.as_ref())
        .collect();
    let of = |f: fn(&metrics::Movement) -> Option<f64>| {
        metrics::Summary::of(moves.iter().filter_map(|m| f(m)))
    };
    name_per_movement(
        named,
        [
            of(|m| m.sparc),
            of(|m| m.ldlj),
            of(|m| Some(m.peak_speed)),
            of(|m| Some(m.duration_s)),
            of(|m| Some(m.n_peaks as f64)),
            of(|m| Some(m.speed_metric)),
        ],
    );
}

/// The wheel's responses to the target's steps by name (none without a step): how many, the
/// median reaction time to unpredictable steps, the share of predictable cues anticipated
/// (`anticipation_pct`, of those met by a movement), the mean initial direction error (0° the
/// right way, 180° the wrong way: 180° × the share of wrong-way starts) and the median path
/// length ratio ([`metrics::robot`]). Medians alone, to keep the Bye's measures within their
/// 64 entries.
fn name_step_responses(named: &mut BTreeMap<String, f64>, responses: &[Reaction]) {
    if responses.is_empty() {
        return;
    }
    named.insert("step_responses".to_owned(), responses.len() as f64);
    let anticipated: Vec<bool> = responses.iter().filter_map(|r| r.anticipated).collect();
    if !anticipated.is_empty() {
        let early = anticipated.iter().filter(|&&a| a).count();
        named.insert(
            "anticipation_pct".to_owned(),
            100.0 * early as f64 / anticipated.len() as f64,
        );
    }
    for (name, values) in [
        (
            "reaction_time_s",
            responses
                .iter()
                .filter_map(|r| r.reaction_time_s)
                .collect::<Vec<_>>(),
        ),
        (
            "initial_direction_error_deg",
            responses
                .iter()
                .filter_map(|r| r.initial_direction_error_deg)
                .collect(),
        ),
        (
            "path_length_ratio",
            responses
                .iter()
                .filter_map(|r| r.path_length_ratio)
                .collect(),
        ),
    ] {
        let summary = metrics::Summary::of(values);
        let (key, value) = if name == "initial_direction_error_deg" {
            ("mean", summary.mean)
        } else {
            ("median", summary.median)
        };
        if let Some(v) = value {
            named.insert(format!("{name}_{key}"), v);
        }
    }
    name_by_side(named, responses);
}

/// The median reaction time and the mean initial direction error to targets on the left
/// and on the right, apart (`reaction_time_left_s_median`, …): a patient who neglects a side
/// is slower and errs more towards it. A side without targets is left out.
fn name_by_side(named: &mut BTreeMap<String, f64>, responses: &[Reaction]) {
    for (side, left) in [("left", true), ("right", false)] {
        let of_side = || responses.iter().filter(move |r| r.left == left);
        let times = metrics::Summary::of(of_side().filter_map(|r| r.reaction_time_s));
        if let Some(v) = times.median {
            named.insert(format!("reaction_time_{side}_s_median"), v);
        }
        let errors = metrics::Summary::of(of_side().filter_map(|r| r.initial_direction_error_deg));
        if let Some(v) = errors.mean {
            named.insert(format!("initial_direction_error_{side}_deg_mean"), v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use record::{ArmSample, AssistSample, WheelSample};

    /// Two minimum-jerk turns of 0.6 rad at 1 kHz, there and back, with rest around them.
    fn two_turns(rate_hz: f64) -> Vec<TickRecord> {
        let n = (5.0 * rate_hz) as u64;
        (0..n)
            .map(|k| {
                let t = k as f64 / rate_hz;
                let s = |on: f64| {
                    let tau = ((t - on) / 1.0).clamp(0.0, 1.0);
                    10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5)
                };
                let angle = 0.6 * (s(1.0) - s(3.0));
                TickRecord {
                    tick: k,
                    t_ns: (t * 1e9) as u64,
                    wheel: WheelSample {
                        angle_rad: angle,
                        velocity_rad_s: 1.0,
                        hand_est_nm: Some(0.3),
                        ..WheelSample::default()
                    },
                    assist: AssistSample {
                        active: true,
                        torque_nm: 0.1,
                        ..AssistSample::default()
                    },
                    arm: Some(ArmSample {
                        elbow_flexion_rad: 1.0 + angle,
                        shoulder_elevation_rad: 0.5,
                        ..ArmSample::default()
                    }),
                    ..TickRecord::default()
                }
            })
            .collect()
    }

    #[test]
    fn two_turns_are_two_smooth_movements_with_their_ranges() {
        let mut c = MeasureCollector::new(1000.0, 5000);
        for rec in two_turns(1000.0) {
            c.add(&rec);
        }
        assert_eq!(c.fs_hz(), 100.0);
        let m = c.finish(session_figures(5.0));
        assert_eq!(m.error, None);
        let s = m.session.as_ref().unwrap();
        assert_eq!(s.movements.len(), 2);
        assert_eq!(m.named["movements"], 2.0);
        assert_eq!(m.named["speed_peaks_median"], 1.0);
        let sparc = m.named["sparc_median"];
        assert!((-1.6..-1.3).contains(&sparc), "{sparc}");
        // 0.6 rad of wheel and of elbow; the shoulder did not move.
        assert!((m.named["wheel_rom_deg"] - 0.6_f64.to_degrees()).abs() < 0.1);
        assert!((m.named["elbow_flexion_rom_deg"] - 0.6_f64.to_degrees()).abs() < 0.1);
        assert_eq!(m.named["shoulder_elevation_rom_deg"], 0.0);
        assert!((m.named["session_s"] - 5.0).abs() < 1e-9);
        // The hand did 0.3 N·m · 1 rad/s · 5 s, the assist 0.1 · 1 · 5: the patient 75 %; the
        // hand's first 50 ms are before its first estimate (which is of 50 ms before its tick).
        assert!((m.named["patient_work_j"] - 0.3 * 4.95).abs() < 1e-9);
        assert!((m.named["assist_work_j"] - 0.5).abs() < 1e-9);
        let pct = 100.0 * 0.3 * 4.95 / (0.3 * 4.95 + 0.5);
        assert!((m.named["patient_work_pct"] - pct).abs() < 1e-9);
        assert!(m.named.values().all(|v| v.is_finite()));
    }

    /// A dial stepping from 0 to 0.5 rad at 1 s and the wheel following it after `delay_s`
    /// with a 0.8 s minimum-jerk turn, at 1 kHz for 4 s.
    fn a_step_followed(delay_s: f64) -> Vec<TickRecord> {
        (0..4000_u64)
            .map(|k| {
                let t = k as f64 / 1000.0;
                let tau = ((t - 1.0 - delay_s) / 0.8).clamp(0.0, 1.0);
                let turn = 10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5);
                TickRecord {
                    tick: k,
                    t_ns: k * 1_000_000,
                    wheel: WheelSample {
                        angle_rad: 0.5 * turn,
                        target_rad: if t < 1.0 { 0.0 } else { 0.5 },
                        ..WheelSample::default()
                    },
                    ..TickRecord::default()
                }
            })
            .collect()
    }

    #[test]
    fn a_step_of_the_target_gives_reaction_time_direction_and_path_ratio_to_the_hub() {
        let recs = a_step_followed(0.4);
        let (m, _) = measured(MeasureCollector::new(1000.0, 4000), &recs);
        let n = &m.named;
        assert_eq!(n["step_responses"], 1.0);
        // The delay, plus the ~0.07 s of the turn before its speed reaches 10 % of its peak.
        let rt = n["reaction_time_s_median"];
        assert!((0.4..0.55).contains(&rt), "{rt}");
        assert_eq!(n["initial_direction_error_deg_mean"], 0.0);
        let p = n["path_length_ratio_median"];
        assert!((0.9..1.05).contains(&p), "{p}");
        // One movement and no reversal in 4 s of exercise: 15 movements per active minute.
        assert!((n["movements_per_min"] - 15.0).abs() < 1e-9);
        assert_eq!(n["reversals_per_min"], 0.0);
        let sm = n["speed_metric_median"];
        assert!((0.5..0.65).contains(&sm), "{sm}");
        assert!(n.keys().all(|k| k.len() <= 64));
        // A later start gives a longer reaction time: the measure follows the patient.
        let (later, _) = measured(MeasureCollector::new(1000.0, 4000), &a_step_followed(0.9));
        let rt_later = later.named["reaction_time_s_median"];
        assert!((rt_later - rt - 0.5).abs() < 0.02, "{rt} then {rt_later}");
    }

    /// The wheel following a step of the target to the left (+0.5 rad at 1 s, after 0.3 s)
    /// and back to the right (−0.5 rad at 3 s, after `right_delay_s`), at 1 kHz for 6 s.
    fn left_then_right(right_delay_s: f64) -> Vec<TickRecord> {
        let turn = |t: f64, start: f64| {
            let tau = ((t - start) / 0.8).clamp(0.0, 1.0);
            10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5)
        };
        (0..6000_u64)
            .map(|k| {
                let t = k as f64 / 1000.0;
                let target_rad = match t {
                    t if t < 1.0 => 0.0,
                    t if t < 3.0 => 0.5,
                    _ => -0.5,
                };
                TickRecord {
                    tick: k,
                    t_ns: k * 1_000_000,
                    wheel: WheelSample {
                        angle_rad: 0.5 * turn(t, 1.3) - 1.0 * turn(t, 3.0 + right_delay_s),
                        target_rad,
                        ..WheelSample::default()
                    },
                    ..TickRecord::default()
                }
            })
            .collect()
    }

    #[test]
    fn reaction_times_are_measured_apart_for_targets_on_the_left_and_on_the_right() {
        let (m, _) = measured(MeasureCollector::new(1000.0, 6000), &left_then_right(0.9));
        let n = &m.named;
        let (left, right) = (
            n["reaction_time_left_s_median"],
            n["reaction_time_right_s_median"],
        );
        // The right-hand target waited for 0.6 s longer.
        assert!(
            (right - left - 0.6).abs() < 0.05,
            "left {left} right {right}"
        );
        assert_eq!(n["initial_direction_error_left_deg_mean"], 0.0);
        assert_eq!(n["initial_direction_error_right_deg_mean"], 0.0);
    }

    #[test]
    fn only_the_target_changes_an_exercise_calls_steps_are_responded_to() {
        let recs = a_step_followed(0.4);
        let told = |steps: TargetSteps| {
            measured(
                MeasureCollector::new(1000.0, 4000).with_target_steps(vec![steps]),
                &recs,
            )
            .0
            .named
        };
        assert_eq!(told(TargetSteps::Jumps)["step_responses"], 1.0);
        // The same jump in an exercise whose jumps are no steps (the strength test's).
        let none = told(TargetSteps::None);
        assert!(!none.contains_key("step_responses"), "{none:?}");
        assert!(none.contains_key("movements"));
        // A lane change's jumps are none either: its shifts are met on the road.
        let shifts = TargetSteps::LaneShifts(vec![exercises::LaneShift {
            s_m: 10.0,
            direction: 1.0,
        }]);
        assert!(!told(shifts.clone()).contains_key("step_responses"));
        // The car reaches the shift at 1 s: one response, the wheel turning the way asked.
        let driven: Vec<TickRecord> = recs
            .iter()
            .map(|r| TickRecord {
                vehicle: Some(record::VehicleSample {
                    s_m: r.t_ns as f64 * 1e-8,
                    ..Default::default()
                }),
                ..*r
            })
            .collect();
        let c = MeasureCollector::new(1000.0, 4000).with_target_steps(vec![shifts]);
        let n = measured(c, &driven).0.named;
        assert_eq!(n["step_responses"], 1.0, "{n:?}");
        // Seen coming, a shift is met with no reaction time (issue 42); started 0.4 s after
        // it, the turn is no anticipation.
        assert!(!n.contains_key("reaction_time_s_median"), "{n:?}");
        assert!(!n.contains_key("reaction_time_right_s_median"), "{n:?}");
        assert_eq!(n["anticipation_pct"], 0.0);
        assert_eq!(n["initial_direction_error_deg_mean"], 0.0);
    }

    #[test]
    fn paused_ticks_are_not_measured_and_movement_times_stay_in_session_time() {
        let mut c = MeasureCollector::new(1000.0, 7000);
        // 2 s paused (the arm procedure) with the wheel swept through 1.5 rad, then the turns.
        let sweep = (0..2000u64).map(|k| TickRecord {
            tick: k,
            t_ns: k * 1_000_000,
            wheel: WheelSample {
                angle_rad: 1.5 * (k as f64 / 2000.0 * std::f64::consts::PI).sin(),
                ..WheelSample::default()
            },
            score: record::ScoreSample {
                paused: true,
                ..Default::default()
            },
            ..TickRecord::default()
        });
        let turns = two_turns(1000.0).into_iter().map(|mut r| {
            r.tick += 2000;
            r.t_ns += 2_000_000_000;
            r
        });
        for rec in sweep.chain(turns) {
            c.add(&rec);
        }
        let m = c.finish(session_figures(7.0));
        assert_eq!(m.named["movements"], 2.0, "the sweep is no movement");
        assert!((m.named["wheel_rom_deg"] - 0.6_f64.to_degrees()).abs() < 0.1);
        // The speed the report draws is the exercise's only, in session time.
        let speed = c.speed_series().unwrap();
        assert_eq!((speed.len(), speed[0].len()), (1, 500));
        assert!((speed[0][0].0 - 2.0).abs() < 1e-9, "{:?}", speed[0][0]);
        let sample = c.sample(&m);
        // The first turn starts near 1 s of exercise, 3 s of session time.
        let start = sample.movements[0].start_s;
        assert!((2.9..3.2).contains(&start), "{start}");
    }

    #[test]
    fn the_live_measures_follow_the_session() {
        let mut c = MeasureCollector::new(1000.0, 5000);
        let recs = two_turns(1000.0);
        for rec in &recs[..2500] {
            c.add(rec);
        }
        let live = c.live();
        assert_eq!(live["movements"], 1.0, "{live:?}");
        assert!(live["active_s"] > 0.5, "{live:?}");
        assert!((live["wheel_rom_deg"] - 0.6_f64.to_degrees()).abs() < 0.1);
    }

    #[test]
    fn nan_wheel_readings_and_a_lost_arm_do_not_spoil_the_measures() {
        let mut c = MeasureCollector::new(1000.0, 5000);
        for (k, mut rec) in two_turns(1000.0).into_iter().enumerate() {
            if k % 7 == 0 || (1200..1300).contains(&k) {
                rec.wheel.angle_rad = f64::NAN;
                rec.wheel.velocity_rad_s = f64::NAN;
            }
            if k > 4000 {
                rec.arm = rec.arm.map(|a| ArmSample {
                    setup: ArmSetup::SensorLost,
                    elbow_flexion_rad: f64::NAN,
                    ..a
                });
            }
            c.add(&rec);
        }
        let m = c.finish(session_figures(5.0));
        assert_eq!(m.error, None);
        assert_eq!(m.named["movements"], 2.0);
        assert!(m.named.values().all(|v| v.is_finite()));
    }

    /// Two minutes of a seeded session at 1 kHz: the wheel turned back and forth at a pace
    /// and size that change, stretches paused, NaN readings, the arm tracked, lost, found.
    fn seeded_session(seed: u64) -> Vec<TickRecord> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let (mut angle, mut phase, mut paused, mut tracking) = (0.0_f64, 0.0_f64, false, true);
        let (mut amplitude, mut hz) = (0.5, 0.3);
        (0..120_000u64)
            .map(|k| {
                if rng.random_bool(1e-3) {
                    (amplitude, hz) = (rng.random_range(0.1..1.0), rng.random_range(0.1..0.8));
                }
                paused ^= rng.random_bool(if paused { 5e-4 } else { 1e-4 });
                tracking ^= rng.random_bool(2e-4);
                phase += std::f64::consts::TAU * hz * 1e-3;
                angle += amplitude * phase.cos() * std::f64::consts::TAU * hz * 1e-3;
                let reading = if rng.random_bool(0.01) {
                    f64::NAN
                } else {
                    angle + rng.random_range(-1e-4..1e-4)
                };
                TickRecord {
                    tick: k,
                    t_ns: k * 1_000_000,
                    wheel: WheelSample {
                        angle_rad: reading,
                        velocity_rad_s: amplitude * phase.cos(),
                        hand_est_nm: Some(rng.random_range(-0.5..0.5)),
                        ..WheelSample::default()
                    },
                    score: record::ScoreSample {
                        paused,
                        ..Default::default()
                    },
                    arm: Some(ArmSample {
                        setup: if tracking {
                            ArmSetup::Tracking
                        } else {
                            ArmSetup::SensorLost
                        },
                        elbow_flexion_rad: 1.0 + angle,
                        shoulder_elevation_rad: 0.5 + 0.1 * phase.sin(),
                        ..ArmSample::default()
                    }),
                    ..TickRecord::default()
                }
            })
            .collect()
    }

    /// The recorder's figures of a session of `session_s` as the measures are handed them
    /// (`session::outcome` tallies them; its tests check what they are), with a NaN the
    /// measures leave out.
    fn session_figures(session_s: f64) -> BTreeMap<String, f64> {
        BTreeMap::from([
            ("session_s".to_owned(), session_s),
            ("assist_level_mean".to_owned(), f64::NAN),
        ])
    }

    /// `c` fed `recs`.
    fn fed(mut c: MeasureCollector, recs: &[TickRecord]) -> MeasureCollector {
        for rec in recs {
            c.add(rec);
        }
        c
    }

    /// `c`'s measures of `recs`, as the `/metrics` channel records them too.
    fn measured(c: MeasureCollector, recs: &[TickRecord]) -> (Measures, MetricsSample) {
        let mut c = fed(c, recs);
        let m = c.finish(session_figures(120.0));
        let sample = c.sample(&m);
        (m, sample)
    }

    /// Exactly equal, bit for bit (the shortest round-trip digits of every `f64`, NaN too).
    fn assert_exactly_equal<T: std::fmt::Debug>(a: &T, b: &T) {
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
    }

    #[test]
    fn a_spilled_session_measures_exactly_as_one_kept_in_memory() {
        let dir = tempfile::tempdir().unwrap();
        let recs = seeded_session(17);
        let memory = measured(MeasureCollector::new(1000.0, 120_000), &recs);
        let c = MeasureCollector::spilling_in(dir.path(), 1000.0);
        assert!(c.series.is_spilled());
        let spilled = measured(c, &recs);
        assert_eq!(memory.0.error, None);
        let s = memory.0.session.as_ref().unwrap();
        assert!(s.movements.len() > 10, "{}", s.movements.len());
        assert!(memory.0.named.contains_key("shoulder_elevation_rom_deg"));
        assert_exactly_equal(&spilled, &memory);
        // The report's speed chart too.
        let mut c = MeasureCollector::new(1000.0, 120_000);
        let mut d = MeasureCollector::spilling_in(dir.path(), 1000.0);
        for rec in &recs {
            c.add(rec);
            d.add(rec);
        }
        let speed = c.speed_series().unwrap();
        assert!(
            speed.len() > 2,
            "several runs between pauses: {}",
            speed.len()
        );
        assert_exactly_equal(&d.speed_series().unwrap(), &speed);
    }

    #[test]
    fn a_spill_that_cannot_be_written_leaves_the_measures_whole() {
        let recs = seeded_session(5);
        let memory = measured(MeasureCollector::new(1000.0, 120_000), &recs);
        // No directory to make the file in: in memory from the start.
        let dir = tempfile::tempdir().unwrap();
        let c = MeasureCollector::spilling_in(&dir.path().join("removed"), 1000.0);
        assert!(!c.series.is_spilled());
        assert_exactly_equal(&measured(c, &recs), &memory);
        // The disk fills up mid-session: what was written is read back, the rest kept in
        // memory.
        let full = series::tests::FillingUp::new(20 * series::SPILL_BUFFER_BYTES as u64, false);
        let c = MeasureCollector::with_series(
            1000.0,
            SeriesStore::spilled_to(Box::new(full), dir.path()),
        );
        let mut c = fed(c, &recs);
        assert!(
            !c.series.is_spilled(),
            "back in memory when the disk filled up"
        );
        let m = c.finish(session_figures(120.0));
        assert_exactly_equal(&(c.sample(&m), m), &(memory.1, memory.0));
    }

    #[test]
    fn series_lost_to_a_failing_disk_say_so_and_keep_the_session_figures() {
        let recs = seeded_session(5);
        let failing = series::tests::FillingUp::new(20 * series::SPILL_BUFFER_BYTES as u64, true);
        let c = MeasureCollector::with_series(
            1000.0,
            SeriesStore::spilled_to(Box::new(failing), Path::new("/recordings")),
        );
        let (m, sample) = measured(c, &recs);
        assert!(m.session.is_none());
        let e = m.error.as_deref().unwrap();
        assert!(
            e.starts_with(
                "the measures' series are lost: writing them to their temporary file \
                 in /recordings failed"
            ),
            "{e}"
        );
        assert_eq!(sample.error, e);
        assert!(sample.movements.is_empty());
        assert!(m.named.contains_key("session_s") && m.named.contains_key("patient_work_j"));
        assert!(!m.named.contains_key("movements"));
    }

    #[test]
    fn an_exercise_too_brief_to_measure_says_so_and_keeps_its_figures() {
        let mut c = MeasureCollector::new(1000.0, 5);
        for rec in &two_turns(1000.0)[..5] {
            c.add(rec);
        }
        let m = c.finish(session_figures(0.005));
        assert!(m.session.is_none());
        assert!(
            m.error.as_deref().unwrap().contains("too briefly"),
            "{:?}",
            m.error
        );
        assert!(m.named.contains_key("session_s"));
        assert!(!m.named.contains_key("assist_level_mean"), "no NaN kept");
        assert!(!m.named.contains_key("movements"));
    }
}
