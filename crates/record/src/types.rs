//! One type per MCAP channel, as recorded and as read back.
//!
//! The haptic thread hands the recorder one [`TickRecord`] per tick (plain `Copy` data: no
//! allocation on the 1 kHz path); each of its parts is one channel. Every message is a
//! [`Stamped`] sample: the tick and session time, then the sample's own fields. The JSON
//! schemas are derived from these structs ([`super::channels`]), so the schema, the messages
//! and the reader cannot drift apart.

use calib::Arm3dCalibration;
use haptic_wheel::{Fault, WatchdogState};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// Everything one haptic tick measured, commanded and computed (serialisable whole for the
/// patient window's process; each part is recorded on its own channel).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TickRecord {
    /// Tick number since the session started.
    pub tick: u64,
    /// Session (simulation) time, ns since the start.
    pub t_ns: u64,
    /// Wheel side.
    pub wheel: WheelSample,
    /// Car and road side (absent during the dial task).
    pub vehicle: Option<VehicleSample>,
    /// Running score.
    pub score: ScoreSample,
    /// Active assistance.
    pub assist: AssistSample,
    /// Arm pose from the gyros (absent without arm sensing).
    pub arm: Option<ArmSample>,
    /// Loop timing on the wall clock.
    pub timing: TimingSample,
    /// The raw inputs the pure part consumed this tick (channels `/raw/wheel`, `/raw/imu`).
    // Not shown on screen: the patient window process is not sent it.
    #[serde(skip)]
    pub raw: super::raw::RawTick,
}

/// Wheel state and torques in one tick (channel `/wheel`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct WheelSample {
    /// Angle as read from the device (quantised), rad.
    pub angle_rad: f64,
    /// Estimated angular velocity (Kalman), rad/s.
    pub velocity_rad_s: f64,
    /// Torque of the haptic model (centring spring–damper, eq. 3.5), N·m.
    pub model_nm: f64,
    /// Road feel from the front lateral tyre force (§3.3.4), N·m.
    pub road_feel_nm: f64,
    /// Torque requested before the safety chain, N·m.
    pub requested_nm: f64,
    /// Torque commanded to the motor after the safety chain, N·m.
    pub commanded_nm: f64,
    /// The safety chain limited the request this tick.
    pub clipped: bool,
    /// Soft-start / fade-out scale of the safety supervisor, 0–1.
    pub safety_scale: f64,
    /// Safety supervisor state.
    pub watchdog: Watchdog,
    /// Passivity observer energy, J (negative: the rendered environment generated energy).
    pub passivity_energy_j: f64,
    /// Damping the passivity controller added, N·m·s/rad.
    pub passivity_damping_nm_s_per_rad: f64,
    /// True wheel angle, rad (simulation only; absent with a real wheel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub true_angle_rad: Option<f64>,
    /// Simulated patient's hand torque, N·m (simulation only; absent with a real wheel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub hand_nm: Option<f64>,
    /// The patient's hand torque estimated from the wheel's dynamics and the torque sent to
    /// the motor (`assist::effort`, eq. E.1–E.3), N·m, on every wheel: the torque of 50 ms
    /// before this tick (`assist::HAND_ESTIMATE_LAG_S`, the estimate's stated lag; pair it
    /// with the wheel's motion of that time). Absent while the rim is at its end stop, and in
    /// recordings made before it was estimated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub hand_est_nm: Option<f64>,
    /// Wheel angle the patient aims for, rad.
    pub target_rad: f64,
    /// The torque ceiling in force, N·m at the motor.
    pub ceiling_nm: f64,
    /// The motor's torque rating is known (built-in, measured or entered); false for an
    /// unknown wheel, whose strongest plausible motor is assumed and ceiling capped.
    pub motor_rating_known: bool,
    /// Torque updates the wheel's backend has written to the device so far (the achieved
    /// update rate at the motor is its growth per second; a driver's rate policy may hold it
    /// below the loop's). 0 for a backend that does not count them (a replay's) and in
    /// recordings made before it was counted: `motor_update_worst_gap_ms` is absent there.
    #[serde(default)]
    pub motor_updates: u64,
    /// The largest time between two torque updates written so far, ms (0 before the second);
    /// absent for a backend that does not count its updates and in older recordings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub motor_update_worst_gap_ms: Option<f64>,
    /// Force commands the wheel refused so far this session (a failed write of the ceiling
    /// or the torque, the wheel still answering reads); 0 in recordings older than it. A run
    /// of them longer than the station allows ends the session on a safety stop.
    #[serde(default)]
    pub write_failures: u64,
}

/// Where the arm sensing is, as recorded (a kebab-case string in the JSON).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
#[schemars(inline)]
pub enum ArmSetup {
    /// Joint angles are being estimated.
    #[default]
    Tracking,
    /// Guided procedure: hold the wheel still, centred.
    HoldStill,
    /// Guided procedure: turn the wheel left and right.
    TurnWheel,
    /// The mounting is being computed.
    Solving,
    /// The procedure failed: no joint angles this session.
    Failed,
    /// An IMU stopped answering: the pose is frozen.
    SensorLost,
}

impl ArmSetup {
    /// The label as recorded (and shown on the screen's device line).
    pub fn as_str(self) -> &'static str {
        match self {
            ArmSetup::Tracking => "tracking",
            ArmSetup::HoldStill => "hold-still",
            ArmSetup::TurnWheel => "turn-wheel",
            ArmSetup::Solving => "solving",
            ArmSetup::Failed => "failed",
            ArmSetup::SensorLost => "sensor-lost",
        }
    }
}

impl fmt::Display for ArmSetup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The safety supervisor's state as recorded: `haptic_wheel::WatchdogState` with the fault
/// named in the same string (fault-missed-deadline, not a nested object).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
#[schemars(inline)]
pub enum Watchdog {
    /// Ramping the torque scale up (start of session or recovery after a fault).
    #[default]
    SoftStart,
    /// Full torque allowed.
    Running,
    /// Fading out: the gap since the previous tick was too long.
    FaultMissedDeadline,
    /// Fading out: the wheel reading was stale, from the future or missing.
    FaultStaleReading,
    /// Fading out: a fault this recording format has no name for.
    Fault,
    /// The patient paused the exercise: fading out, then zero torque until resumed.
    Paused,
    /// A stop was requested: fading out.
    Stopping,
    /// Stopped for good: zero torque.
    Stopped,
}

impl Watchdog {
    /// The supervisor saw a fault (the torque is fading out because of it).
    pub fn is_fault(self) -> bool {
        matches!(
            self,
            Watchdog::FaultMissedDeadline | Watchdog::FaultStaleReading | Watchdog::Fault
        )
    }

    /// The label as recorded (and shown on the screen's device line).
    pub fn as_str(self) -> &'static str {
        match self {
            Watchdog::SoftStart => "soft-start",
            Watchdog::Running => "running",
            Watchdog::FaultMissedDeadline => "fault-missed-deadline",
            Watchdog::FaultStaleReading => "fault-stale-reading",
            Watchdog::Fault => "fault",
            Watchdog::Paused => "paused",
            Watchdog::Stopping => "stopping",
            Watchdog::Stopped => "stopped",
        }
    }
}

impl From<WatchdogState> for Watchdog {
    fn from(state: WatchdogState) -> Self {
        match state {
            WatchdogState::SoftStart => Watchdog::SoftStart,
            WatchdogState::Running => Watchdog::Running,
            WatchdogState::Fault(Fault::MissedDeadline) => Watchdog::FaultMissedDeadline,
            WatchdogState::Fault(Fault::StaleReading) => Watchdog::FaultStaleReading,
            WatchdogState::Fault(_) => Watchdog::Fault,
            WatchdogState::Paused => Watchdog::Paused,
            WatchdogState::Stopping => Watchdog::Stopping,
            WatchdogState::Stopped => Watchdog::Stopped,
        }
    }
}

impl fmt::Display for Watchdog {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Car and road state in one tick (channel `/vehicle`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct VehicleSample {
    /// Global x, m.
    pub x_m: f64,
    /// Global y, m.
    pub y_m: f64,
    /// Heading, rad.
    pub yaw_rad: f64,
    /// Forward velocity, m/s.
    pub ux_m_s: f64,
    /// Lateral velocity, m/s.
    pub uy_m_s: f64,
    /// Yaw rate, rad/s.
    pub r_rad_s: f64,
    /// Road-wheel angle δ, rad.
    pub steer_rad: f64,
    /// Front lateral tyre force, N.
    pub front_lateral_n: f64,
    /// Distance along the road, m.
    pub s_m: f64,
    /// Lateral deviation from the road centre, m (positive left).
    pub lateral_m: f64,
}

/// The running session score (channel `/score`, every 100 ms).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ScoreSample {
    /// Which exercise of the course is running (0-based).
    pub exercise_index: u32,
    /// RMS lateral deviation so far, m.
    pub rms_lateral_m: f64,
    /// Largest |lateral deviation| so far, m.
    pub max_lateral_m: f64,
    /// Share of time in the lane so far, %.
    pub pct_in_lane: f64,
    /// Cones hit so far.
    pub cone_hits: u32,
    /// RMS dial tracking error so far (thesis §3.3.3), degrees.
    pub dial_rms_error_deg: f64,
    /// Exercise time so far, s: the session clock without the pauses.
    pub active_s: f64,
    /// The patient paused the exercise (car, exercise clock and scores frozen; torque faded
    /// to zero).
    pub paused: bool,
    /// The strength test in progress, as it measures (the strength exercise only; absent in
    /// recordings made before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "StrengthNow")]
    pub strength: Option<StrengthNow>,
}

/// The strength test as it runs: what the therapist's live view shows of it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(inline)]
pub struct StrengthNow {
    /// The side pushed now: 1 left, −1 right, 0 resting between the sides or done.
    pub side: f64,
    /// The patient's push the spring balanced at the last tick the test took, in the side's
    /// direction, N·m.
    pub push_nm: f64,
    /// The left side's highest push so far (its result once over), N·m; absent before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub peak_left_nm: Option<f64>,
    /// The right side's, N·m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub peak_right_nm: Option<f64>,
}

/// Active assistance in one tick (channel `/assist`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct AssistSample {
    /// An assist controller runs during this exercise.
    pub active: bool,
    /// Assist torque, N·m.
    pub torque_nm: f64,
    /// Reference the assist tracks (after the reference governor), rad.
    pub reference_rad: f64,
    /// Reference minus measured angle, rad.
    pub error_rad: f64,
    /// How much the robot helps, 0 (none) to 1 (full authority).
    pub assistance_level: f64,
    /// A torque limit cut the assist this tick.
    pub saturated: bool,
}

/// The arm pose estimated from the two IMUs, beside the simulated truth (channel `/arm`).
/// Angles follow `gyro_imu::arm::JointAngles`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ArmSample {
    /// Estimated humerus elevation from hanging, rad.
    pub shoulder_elevation_rad: f64,
    /// Estimated plane of elevation (0 lateral, π/2 forward), rad.
    pub shoulder_plane_rad: f64,
    /// Estimated humeral axial rotation (internal positive), rad.
    pub shoulder_rotation_rad: f64,
    /// Estimated elbow flexion (0 straight), rad.
    pub elbow_flexion_rad: f64,
    /// Estimated forearm pronation, rad.
    pub forearm_pronation_rad: f64,
    /// True humerus elevation (simulation only), rad.
    pub true_shoulder_elevation_rad: f64,
    /// True elbow flexion (simulation only), rad.
    pub true_elbow_flexion_rad: f64,
    /// RMS mismatch of the measured and fitted segment "up" directions, rad.
    pub fit_residual_rad: f64,
    /// Arm sensing step (angles are zero until tracking starts).
    pub setup: ArmSetup,
    /// Time left in the set-up step, s.
    pub setup_remaining_s: f64,
    /// Upper-arm sensor-to-earth orientation (w, x, y, z; earth z up, heading that of the
    /// wheel frame when tracking began).
    pub upper_orientation_wxyz: [f64; 4],
    /// Forearm sensor-to-earth orientation (w, x, y, z).
    pub fore_orientation_wxyz: [f64; 4],
    /// Range of motion so far of shoulder elevation, plane, rotation, elbow flexion and
    /// forearm pronation, rad.
    pub range_of_motion_rad: [f64; 5],
    /// Upper arm's long axis (shoulder → elbow) in the wheel frame, from the upper-arm IMU's
    /// orientation and mounting alone (not from the chain fit): the arm calibration's input.
    pub upper_axis: [f64; 3],
    /// Forearm's long axis (elbow → grip) in the wheel frame, from the forearm IMU alone.
    pub fore_axis: [f64; 3],
    /// Grip point on the wheel rim at the wheel angle read, m (wheel frame).
    pub grip_m: [f64; 3],
    /// Upper-arm gyro, sensor x, rad/s.
    pub upper_gyro_x_rad_s: f64,
    /// Upper-arm gyro, sensor y, rad/s.
    pub upper_gyro_y_rad_s: f64,
    /// Upper-arm gyro, sensor z, rad/s.
    pub upper_gyro_z_rad_s: f64,
    /// Forearm gyro, sensor x, rad/s.
    pub fore_gyro_x_rad_s: f64,
    /// Forearm gyro, sensor y, rad/s.
    pub fore_gyro_y_rad_s: f64,
    /// Forearm gyro, sensor z, rad/s.
    pub fore_gyro_z_rad_s: f64,
    /// A sternum IMU is worn and its start posture taken: the trunk angles below are
    /// estimated (`gyro_imu::trunk`; zero otherwise).
    #[serde(default)]
    pub trunk_tracked: bool,
    /// Estimated trunk flexion from the start posture (forward positive), rad.
    #[serde(default)]
    pub trunk_flexion_rad: f64,
    /// Estimated trunk lateral lean from the start posture (to the right positive), rad.
    #[serde(default)]
    pub trunk_lean_rad: f64,
    /// Estimated trunk rotation from the start posture (to the left positive), rad.
    #[serde(default)]
    pub trunk_rotation_rad: f64,
    /// True trunk flexion from the same start posture (simulation only), rad.
    #[serde(default)]
    pub true_trunk_flexion_rad: f64,
    /// True trunk lateral lean (simulation only), rad.
    #[serde(default)]
    pub true_trunk_lean_rad: f64,
    /// True trunk rotation (simulation only), rad.
    #[serde(default)]
    pub true_trunk_rotation_rad: f64,
    /// Gentle cues to sit up given so far in the session (the regimen's `[trunk] cue_deg`):
    /// each step up is one cue, at that tick (absent in older files: none).
    #[serde(default)]
    pub trunk_cues: u64,
    /// The cue's sentence is on the patient's screen (for a few seconds after each cue).
    #[serde(default)]
    pub trunk_cue_shown: bool,
}

/// Wall-clock timing of one tick (channel `/timing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TimingSample {
    /// How late the tick started after its absolute deadline, ns (0 at `--speed max`).
    pub lateness_ns: u64,
    /// Wall time since the previous tick started, ns.
    pub period_ns: u64,
    /// Time spent computing this tick, ns.
    pub work_ns: u64,
    /// Records the recorder could not take so far (ring full), count.
    pub dropped_records: u64,
}

/// The arm calibration as recorded (channel `/arm_calibration`, once at the end).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ArmCalibrationSample {
    /// Shoulder joint centre in the wheel frame, m.
    pub shoulder_m: [f64; 3],
    /// Upper-arm length (shoulder to elbow), m.
    pub upper_arm_m: f64,
    /// Forearm length (elbow to grip), m.
    pub forearm_m: f64,
    /// 1σ standard error of the upper-arm length, m.
    pub upper_arm_se_m: f64,
    /// 1σ standard error of the forearm length, m.
    pub forearm_se_m: f64,
    /// RMS loop-closure residual, m.
    pub rms_residual_m: f64,
    /// Condition number of the fit (below 200 is well identified).
    pub condition_number: f64,
    /// Samples used.
    pub samples: f64,
    /// Warnings, each with what to do about it.
    pub warnings: Vec<String>,
    /// The online estimate (`calib::arm3d::OnlineArm3d`, run during the session) when it
    /// converged, if it did; absent in recordings made before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "OnlineArmCalibrationSample")]
    pub online: Option<OnlineArmCalibrationSample>,
}

/// The arm calibration estimated during the session, when its convergence rule first held
/// (the live view's pose switched to these lengths then).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(inline)]
pub struct OnlineArmCalibrationSample {
    /// Session time it converged at, s.
    pub converged_at_s: f64,
    /// Shoulder joint centre in the wheel frame, m.
    pub shoulder_m: [f64; 3],
    /// Upper-arm length (shoulder to elbow), m.
    pub upper_arm_m: f64,
    /// Forearm length (elbow to grip), m.
    pub forearm_m: f64,
    /// 1σ standard error of the upper-arm length, m.
    pub upper_arm_se_m: f64,
    /// 1σ standard error of the forearm length, m.
    pub forearm_se_m: f64,
    /// RMS loop-closure residual of its samples, m.
    pub rms_residual_m: f64,
    /// Samples it fitted.
    pub samples: f64,
    /// The recursive estimator's (`OnlineArm3d`, no heading-drift term) upper-arm length at
    /// the same moment, m (NaN while it had none): for the comparison only.
    pub recursive_upper_arm_m: f64,
    /// The recursive estimator's forearm length then, m.
    pub recursive_forearm_m: f64,
    /// The recursive estimator's RMS loop-closure residual then, m.
    pub recursive_rms_residual_m: f64,
}

impl From<&Arm3dCalibration> for ArmCalibrationSample {
    fn from(c: &Arm3dCalibration) -> Self {
        Self {
            shoulder_m: c.params.shoulder_m,
            upper_arm_m: c.params.upper_arm_m,
            forearm_m: c.params.forearm_m,
            upper_arm_se_m: c.std_errors.upper_arm_m,
            forearm_se_m: c.std_errors.forearm_m,
            rms_residual_m: c.rms_residual_m,
            condition_number: c.condition_number,
            samples: c.samples,
            warnings: c.warnings.clone(),
            online: None,
        }
    }
}

/// The session's movement measures as recorded (channel `/metrics`, once at the end).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MetricsSample {
    /// Every measure by name, the unit in the name (`sparc_median`, `wheel_rom_deg`,
    /// `active_s`, `patient_work_pct`, …); finite values only. The same set the hub stores.
    pub measures: BTreeMap<String, f64>,
    /// Rate of the series the movements were found in, Hz.
    pub fs_hz: f64,
    /// The wheel's movements, in time order (empty without the movement analysis).
    pub movements: Vec<MovementSample>,
    /// Why the movement analysis is missing; absent when it was made.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub error: String,
    /// Each exercise's own results, in course order (absent from recordings made before
    /// they were recorded).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub exercises: Vec<ExerciseResult>,
    /// How the session ended, in the words its `Bye` carries (`complete`, `ended early by the
    /// patient (…)`, `wheel unplugged`, `safety stop: …`); absent from recordings made before
    /// it was recorded.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub end_reason: String,
}

/// One exercise's own results in a session (within [`MetricsSample`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(inline)]
pub struct ExerciseResult {
    /// Its place in the session's course, from 0.
    pub index: u32,
    /// Its kind, the regimen's short name (`sine-road`, `dial-sine`).
    pub kind: String,
    /// Its name as the patient sees it (`Sine road`).
    pub name: String,
    /// Its prescribed duration, s.
    pub prescribed_s: f64,
    /// The time it ran, s (the patient's pauses left out).
    pub active_s: f64,
    /// Its scores and movement measures over its own span, name (unit in the name) → finite
    /// value: `rms_lateral_m`, `pct_in_lane`, `heading_rms_error_deg`, `cone_hits`,
    /// `completion_time_s`, `tracking_rms_error_deg`, `dial_mean_abs_error_deg` (the thesis's
    /// Appendix E measure), `dial_rms_error_deg`, `movements`, `sparc_median`, ….
    pub scores: BTreeMap<String, f64>,
}

/// One movement of the wheel (within [`MetricsSample`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(inline)]
pub struct MovementSample {
    /// Its start from the session's start, s.
    pub start_s: f64,
    /// Its duration, s.
    pub duration_s: f64,
    /// Its peak speed, rad/s.
    pub peak_speed_rad_s: f64,
    /// Its speed peaks (1 for one smooth submovement).
    pub n_peaks: u32,
    /// Its spectral arc length (dimensionless, ≤ 0); absent when undefined.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub sparc: Option<f64>,
    /// Its log dimensionless jerk (dimensionless); absent when undefined.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "f64")]
    pub ldlj: Option<f64>,
}

impl From<&metrics::Movement> for MovementSample {
    fn from(m: &metrics::Movement) -> Self {
        Self {
            start_s: m.start_s,
            duration_s: m.duration_s,
            peak_speed_rad_s: m.peak_speed,
            n_peaks: u32::try_from(m.n_peaks).unwrap_or(u32::MAX),
            sparc: m.sparc,
            ldlj: m.ldlj,
        }
    }
}

/// A message: the tick and session time, then the sample's own fields.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Stamped<T> {
    /// Haptic tick number since the session start.
    pub tick: u64,
    /// Session time, s.
    pub t_s: f64,
    /// The sample.
    #[serde(flatten)]
    pub data: T,
}

impl TickRecord {
    /// The tick as reading its recording gives it back: every float of the per-tick channels
    /// rounded to its quantum ([`super::blocks`]); the score is recorded in full.
    pub fn as_recorded(&self) -> Self {
        use super::blocks::as_recorded;
        Self {
            wheel: as_recorded(&self.wheel),
            vehicle: self.vehicle.as_ref().map(as_recorded),
            assist: as_recorded(&self.assist),
            arm: self.arm.as_ref().map(as_recorded),
            timing: self.timing,
            raw: super::raw::RawTick {
                wheel: as_recorded(&self.raw.wheel),
                imu: self.raw.imu.map(|s| s.as_ref().map(as_recorded)),
            },
            ..*self
        }
    }
}

impl<T> Stamped<T> {
    /// `data` stamped with the tick and session time (ns) of `rec`.
    pub fn at(rec: &TickRecord, data: T) -> Self {
        Self {
            tick: rec.tick,
            t_s: rec.t_ns as f64 * 1e-9,
            data,
        }
    }

    /// Session time, ns (exact: the recorded seconds round back to the tick's nanoseconds).
    pub fn t_ns(&self) -> u64 {
        (self.t_s * 1e9).round() as u64
    }
}

/// The recording format this build writes, in every recording's metadata (`format_version`).
///
/// 1. All-JSON: every channel JSON, one message a tick.
/// 2. Compact: the high-rate channels as protobuf blocks of delta-coded quantised columns
///    ([`crate::blocks`]), the arm as a Foxglove 3-D scene.
/// 3. Raw inputs: `/raw/wheel` and `/raw/imu` and the body's facts in the metadata, so a real
///    device's session replays.
/// 4. The format version in the metadata; configuration and regimen read leniently.
/// 5. The trunk's angles from a sternum IMU on `/arm` (absent in older files: not tracked).
/// 6. The gentle trunk cues on `/arm` (`trunk_cues`, `trunk_cue_shown`; absent in older
///    files: none given).
///
/// Formats 1–3 carry no version (read as [`UNVERSIONED_FORMAT`]); every format this product has
/// written stays readable (the golden recordings under `tests/golden/` are opened by every
/// reader in CI). A change to what a channel holds or how it is encoded takes the next number.
pub const FORMAT_VERSION: u32 = 6;

/// The `format_version` of a recording written before versions were recorded (formats 1–3).
pub const UNVERSIONED_FORMAT: u32 = 0;

/// The session's metadata record (`"session"`): what a replay needs besides the messages.
#[derive(Clone, Debug, PartialEq)]
pub struct SessionMetadata {
    /// The recording format ([`FORMAT_VERSION`] when written by this build,
    /// [`UNVERSIONED_FORMAT`] when read from a recording of formats 1–3).
    pub format_version: u32,
    /// The configured exercise name.
    pub exercise: String,
    /// Random seed of the simulation.
    pub seed: u64,
    /// Pseudonymous patient identifier.
    pub patient_id: String,
    /// Haptic loop rate, Hz.
    pub loop_rate_hz: f64,
    /// The whole station configuration, TOML.
    pub config_toml: String,
    /// The prescribed regimen, TOML (absent when the session repeated one exercise).
    pub regimen_toml: Option<String>,
    /// Who held the wheel, and the device facts a replay of the raw inputs needs (absent in
    /// recordings made before the raw inputs were recorded).
    pub body: Option<super::raw::BodyFacts>,
    /// The difficulty the session ran at, when its regimen adapts it (`[difficulty]`), with
    /// its change and the reason (absent otherwise and in older recordings).
    pub difficulty: Option<DifficultyNote>,
    /// Whom the session was for as the clinic knows them, when the station is paired (absent
    /// when unpaired and in older recordings; a damaged one is read as absent).
    pub clinic: Option<ClinicNote>,
}

/// Whom a paired station's session was for, in the clinic's own words: what the report and
/// every reader name the session by (never the internal patient id).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ClinicNote {
    /// The patient's pseudonym as the clinic knows it (`P-0042`); empty when the hub that
    /// paired the station did not say it (hubs older than this field).
    #[serde(default)]
    pub patient_pseudonym: String,
    /// The clinic: the name on its hub's certificate (and address), as the pairing gave it.
    #[serde(default)]
    pub clinic: String,
    /// The therapist who prescribed the session's regimen (name or e-mail), when the station
    /// was told; empty otherwise.
    #[serde(default)]
    pub therapist: String,
}

/// The difficulty a session ran at (`regimen::Regimen::at_difficulty`) and why it changed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DifficultyNote {
    /// The difficulty, in [0, 1].
    pub difficulty: f64,
    /// The change from the session before.
    pub change: f64,
    /// Why, in words (`success 82 % above the 70 % target: +0.05`).
    pub reason: String,
}

impl Default for SessionMetadata {
    fn default() -> Self {
        Self {
            format_version: FORMAT_VERSION,
            exercise: String::new(),
            seed: 0,
            patient_id: String::new(),
            loop_rate_hz: 0.0,
            config_toml: String::new(),
            regimen_toml: None,
            body: None,
            difficulty: None,
            clinic: None,
        }
    }
}

/// Why a metadata record does not describe a session.
#[derive(Debug, thiserror::Error)]
#[error("session metadata `{key}`: {reason}")]
pub struct MetadataError {
    /// The key at fault.
    pub key: &'static str,
    /// What is wrong with it.
    pub reason: String,
}

impl SessionMetadata {
    /// The name of the MCAP metadata record.
    pub const NAME: &'static str = "session";

    /// The record's key → value map, as written.
    pub fn to_map(&self) -> BTreeMap<String, String> {
        let mut map = BTreeMap::new();
        map.insert("format_version".into(), self.format_version.to_string());
        map.insert("exercise".into(), self.exercise.clone());
        map.insert("seed".into(), self.seed.to_string());
        map.insert("patient_id".into(), self.patient_id.clone());
        map.insert("loop_rate_hz".into(), self.loop_rate_hz.to_string());
        map.insert("config_toml".into(), self.config_toml.clone());
        if let Some(r) = &self.regimen_toml {
            map.insert("regimen_toml".into(), r.clone());
        }
        if let Some(b) = &self.body {
            map.insert(
                "body".into(),
                serde_json::to_string(b).expect("body facts serialise"),
            );
        }
        if let Some(d) = &self.difficulty {
            map.insert(
                "difficulty".into(),
                serde_json::to_string(d).expect("a difficulty serialises"),
            );
        }
        if let Some(c) = &self.clinic {
            map.insert(
                "clinic".into(),
                serde_json::to_string(c).expect("a clinic note serialises"),
            );
        }
        map
    }

    /// What a reader should say about this recording's format: written by a newer telerehab
    /// (read as far as this build knows the format), or `None`.
    pub fn format_note(&self) -> Option<String> {
        (self.format_version > FORMAT_VERSION).then(|| {
            format!(
                "recorded by a newer telerehab (recording format {}, this build knows up to {}): \
                 what this version knows is read, the rest is skipped",
                self.format_version, FORMAT_VERSION
            )
        })
    }

    /// Read the record's map back (unknown keys are ignored).
    pub fn from_map(map: &BTreeMap<String, String>) -> Result<Self, MetadataError> {
        let get = |key: &'static str| {
            map.get(key).cloned().ok_or(MetadataError {
                key,
                reason: "missing".into(),
            })
        };
        let parse = |key: &'static str, e: &dyn fmt::Display| MetadataError {
            key,
            reason: format!("not a number ({e})"),
        };
        let format_version = match map.get("format_version") {
            None => UNVERSIONED_FORMAT,
            Some(v) => v.parse().map_err(|e| parse("format_version", &e))?,
        };
        Ok(Self {
            format_version,
            exercise: get("exercise")?,
            seed: get("seed")?.parse().map_err(|e| parse("seed", &e))?,
            patient_id: get("patient_id")?,
            loop_rate_hz: get("loop_rate_hz")?
                .parse()
                .map_err(|e| parse("loop_rate_hz", &e))?,
            config_toml: get("config_toml")?,
            regimen_toml: map.get("regimen_toml").cloned(),
            body: map
                .get("body")
                .map(|b| serde_json::from_str(b))
                .transpose()
                .map_err(|e| MetadataError {
                    key: "body",
                    reason: format!("not the body's facts ({e})"),
                })?,
            difficulty: map
                .get("difficulty")
                .map(|d| serde_json::from_str(d))
                .transpose()
                .map_err(|e| MetadataError {
                    key: "difficulty",
                    reason: format!("not a difficulty ({e})"),
                })?,
            // Words for people, not needed to replay: a damaged note is left out, never a
            // reason not to read the session.
            clinic: map.get("clinic").and_then(|c| serde_json::from_str(c).ok()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{ArmSample, ArmSetup, Watchdog, WheelSample};
    use crate::blocks::Cell;
    use crate::blocks::flatten::{Prim, flatten};
    use crate::blocks::unflatten::unflatten;
    use haptic_wheel::{Fault, WatchdogState};

    fn cells_of<T: serde::Serialize>(sample: &T) -> Vec<Cell> {
        let mut prims = Vec::new();
        flatten(sample, &mut prims, None).unwrap();
        prims
            .into_iter()
            .map(|p| match p {
                Prim::Float(x) => Cell::Float(x),
                Prim::Int(n) => Cell::Int(n),
                Prim::Bool(b) => Cell::Bool(b),
                Prim::Text(t) => Cell::Text(t.into()),
                Prim::Absent => Cell::Absent,
            })
            .collect()
    }

    #[test]
    fn samples_unflatten_to_what_was_flattened_nan_and_infinity_included() {
        let wheel = WheelSample {
            angle_rad: f64::INFINITY,
            requested_nm: 0.25,
            watchdog: Watchdog::FaultStaleReading,
            true_angle_rad: Some(0.5),
            hand_nm: None,
            ..Default::default()
        };
        let back: WheelSample = unflatten(&cells_of(&wheel)).unwrap();
        assert_eq!(back, wheel);
        let arm = ArmSample {
            upper_gyro_x_rad_s: f64::NAN,
            setup: ArmSetup::SensorLost,
            grip_m: [1.0, 2.0, 3.0],
            ..Default::default()
        };
        let back: ArmSample = unflatten(&cells_of(&arm)).unwrap();
        assert!(back.upper_gyro_x_rad_s.is_nan());
        assert_eq!(
            (back.setup, back.grip_m),
            (ArmSetup::SensorLost, [1.0, 2.0, 3.0])
        );
        let mut short = cells_of(&arm);
        short.pop();
        assert!(unflatten::<ArmSample>(&short).is_err());
    }

    /// A block decoded straight into its samples (`Layout::decode_samples`, what the
    /// streaming reader does) gives what its cells unflatten to, sample for sample, NaN,
    /// infinities, absent fields, labels and arrays included; a block read as another type's
    /// samples is refused both ways.
    #[test]
    fn blocks_decode_into_samples_as_their_cells_unflatten() {
        use crate::blocks::{BlockBuilder, DecodeScratch, Layout};
        use crate::channels::Channel;
        let layout = |c: Channel| c.spec().block_layout().unwrap().unwrap();
        let (wheel_layout, arm_layout) = (layout(Channel::Wheel), layout(Channel::Arm));
        let mut wheel = WheelSample::default();
        let mut arm = ArmSample::default();
        let (mut wheels, mut arms) = (BlockBuilder::new(), BlockBuilder::new());
        for i in 0..37u64 {
            let x = i as f64 * 0.37 - 3.0;
            wheel.angle_rad = [x.sin(), f64::NAN, f64::INFINITY][(i % 3) as usize];
            wheel.hand_nm = (i % 4 != 0).then_some(x * 1e3);
            wheel.watchdog = [Watchdog::Running, Watchdog::FaultStaleReading][(i % 2) as usize];
            wheel.clipped = i % 5 == 0;
            arm.grip_m = [x, -x, f64::NEG_INFINITY];
            arm.setup = [ArmSetup::Tracking, ArmSetup::SensorLost][(i % 2) as usize];
            arm.upper_gyro_x_rad_s = x.cos();
            wheels.push(i, i * 1_000_000, &wheel).unwrap();
            arms.push(i, i * 1_000_000, &arm).unwrap();
        }
        let wheel_block = wheels.take(&wheel_layout).unwrap();
        let arm_block = arms.take(&arm_layout).unwrap();
        fn both<T: serde::de::DeserializeOwned + std::fmt::Debug>(
            layout: &Layout,
            block: &[u8],
            scratch: &mut DecodeScratch,
        ) -> (Vec<String>, Vec<String>) {
            let mut direct = Vec::new();
            let rows = layout.decode_samples::<T>(block, scratch, |tick, t_ns, s| {
                direct.push(format!("{tick} {t_ns} {s:?}"));
            });
            let via_cells = layout.decode_cells(block).map(|samples| {
                samples
                    .iter()
                    .map(|c| {
                        let [Cell::Int(tick), Cell::Int(t_ns)] = &c[..2] else {
                            panic!("a sample without its stamps: {c:?}");
                        };
                        let s = unflatten::<T>(&c[2..])?;
                        Ok(format!("{tick} {t_ns} {s:?}"))
                    })
                    .collect::<Result<Vec<String>, crate::blocks::unflatten::Mismatch>>()
            });
            match (rows, via_cells) {
                (Ok(n), Ok(Ok(cells))) => {
                    assert_eq!(n, cells.len());
                    (direct, cells)
                }
                (Err(_), Ok(Err(_)) | Err(_)) => (Vec::new(), Vec::new()),
                (rows, _) => panic!("one way decodes, the other not: {rows:?}"),
            }
        }
        // One scratch for every block, as the reader keeps it.
        let mut scratch = DecodeScratch::default();
        for _ in 0..2 {
            let (direct, cells) = both::<WheelSample>(&wheel_layout, &wheel_block, &mut scratch);
            assert_eq!((direct.len(), &direct), (37, &cells));
            let (direct, cells) = both::<ArmSample>(&arm_layout, &arm_block, &mut scratch);
            assert_eq!((direct.len(), &direct), (37, &cells));
        }
        let (direct, _) = both::<ArmSample>(&wheel_layout, &wheel_block, &mut scratch);
        assert!(direct.is_empty());
        let (direct, _) = both::<WheelSample>(&arm_layout, &arm_block, &mut scratch);
        assert!(direct.is_empty());
    }

    #[test]
    fn arm_setup_labels_are_the_recorded_strings() {
        for s in [
            ArmSetup::Tracking,
            ArmSetup::HoldStill,
            ArmSetup::TurnWheel,
            ArmSetup::Solving,
            ArmSetup::Failed,
            ArmSetup::SensorLost,
        ] {
            assert_eq!(serde_json::to_string(&s).unwrap(), format!("\"{s}\""));
        }
    }

    #[test]
    fn watchdog_labels_are_the_strings_recorded_before_the_enum() {
        for (state, label) in [
            (WatchdogState::SoftStart, "soft-start"),
            (WatchdogState::Running, "running"),
            (
                WatchdogState::Fault(Fault::MissedDeadline),
                "fault-missed-deadline",
            ),
            (
                WatchdogState::Fault(Fault::StaleReading),
                "fault-stale-reading",
            ),
            (WatchdogState::Paused, "paused"),
            (WatchdogState::Stopping, "stopping"),
            (WatchdogState::Stopped, "stopped"),
        ] {
            let w = Watchdog::from(state);
            assert_eq!(serde_json::to_string(&w).unwrap(), format!("\"{label}\""));
            assert_eq!(w.as_str(), label);
            assert_eq!(w.is_fault(), label.starts_with("fault"));
        }
        assert_eq!(
            serde_json::to_string(&Watchdog::Fault).unwrap(),
            "\"fault\""
        );
    }
}
