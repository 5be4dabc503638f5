//! The patient's arm from two IMUs and the wheel: the guided mounting procedure when the
//! sensors' placement is unknown (always with real IMUs), then the pose estimator. The same
//! [`ArmTracker`] runs behind simulated IMUs ([`sim`]) and controller IMUs over HID ([`hid`]).
//! Allocation-free per tick.
//!
//! Also the arm's lengths calibrated from a session's data ([`calibration`]: the recorder
//! thread's collector, the online estimate and the physiological check), the trunk from a
//! sternum IMU ([`trunk`]) and the gentle cue to sit up ([`trunk_cue`]), and the `[arm]`
//! section of the station's configuration ([`config`]). Below the session (`session` drives
//! it from its haptic and recorder threads); devices only through `gyro_imu`'s `hid` feature.

pub mod calibration;
pub mod config;
pub mod hid;
pub mod sim;
pub mod trunk;
pub mod trunk_cue;

use clock::Clock;
use gyro_imu::ImuError;
use gyro_imu::arm::ArmGeometry;
use gyro_imu::device::{GyroRange, ImuSample};
use gyro_imu::fusion::FusionConfig;
use gyro_imu::pose::{ArmPoseEstimator, Mounting};
use gyro_imu::procedure::{GuidedMounting, GuidedOutcome, ProcedureConfig, Prompt};
use nalgebra::UnitQuaternion;
use record::raw::imu_on_grid;
use record::{ArmSample, ArmSetup};
use std::time::Duration;

pub use config::{ArmConfig, DEFAULT_TRUNK_THRESHOLD_DEG, MountingMode};

/// Where the arm sensing is: the label recorded on `/arm` and what the screen asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SetupStep {
    /// The mounting is known: joint angles are being estimated.
    Tracking,
    /// Hold the wheel still, centred.
    HoldStill {
        /// Time left in this step, s.
        remaining_s: f64,
    },
    /// Turn the wheel left and right.
    TurnWheel {
        /// Time left in this step, s.
        remaining_s: f64,
    },
    /// The mounting is being computed (a moment, off the haptic thread).
    Solving,
    /// The procedure failed: no joint angles this session (the exercise runs on).
    Failed,
    /// An IMU stopped answering: the pose is frozen for the rest of the session.
    SensorLost,
}

impl SetupStep {
    /// The step as recorded.
    pub fn label(self) -> ArmSetup {
        match self {
            SetupStep::Tracking => ArmSetup::Tracking,
            SetupStep::HoldStill { .. } => ArmSetup::HoldStill,
            SetupStep::TurnWheel { .. } => ArmSetup::TurnWheel,
            SetupStep::Solving => ArmSetup::Solving,
            SetupStep::Failed => ArmSetup::Failed,
            SetupStep::SensorLost => ArmSetup::SensorLost,
        }
    }

    /// Time left in the current step, s (0 when not in a step).
    pub fn remaining_s(self) -> f64 {
        match self {
            SetupStep::HoldStill { remaining_s } | SetupStep::TurnWheel { remaining_s } => {
                remaining_s
            }
            _ => 0.0,
        }
    }

    /// The patient is being asked to do something (the exercise waits).
    pub fn in_progress(self) -> bool {
        matches!(
            self,
            SetupStep::HoldStill { .. } | SetupStep::TurnWheel { .. } | SetupStep::Solving
        )
    }
}

/// One tick of the wheel as the host sees it, for the arm.
#[derive(Clone, Copy, Debug)]
pub struct WheelNow {
    /// Session time, ns.
    pub t_ns: u64,
    /// Angle read from the wheel, rad.
    pub angle_rad: f64,
    /// Estimated angular rate, rad/s.
    pub rate_rad_s: f64,
    /// Time since the previous tick, s.
    pub dt_s: f64,
}

/// Longest the exercise waits for the solver thread (the solve takes ~20 ms).
const SOLVE_TIMEOUT: Duration = Duration::from_secs(10);

/// The mounting takes effect this long in session time after the procedure ended, however
/// it was solved (on the solver thread in real time, in line as fast as possible), so that a
/// real-time session and its replay change step on the same tick: `telerehab replay`
/// reproduces it bit for bit. Far above the solve's 16 ms (release build), and above a debug
/// build's on a loaded machine; a solver slower than this delays the step, and only then does
/// the session depend on the wall clock. The patient sees "solving" for this second.
const SOLVE_HOLD_NS: u64 = 1_000_000_000;

/// Why a session has no (more) joint angles: kept on the haptic thread without allocating,
/// told in words after the session.
#[derive(Debug)]
pub enum ArmFailure {
    /// The guided procedure gave up, or its data did not fit the arm (says what to do).
    Procedure(ImuError),
    /// The mounting solve did not come back within 10 s.
    SolverTimedOut,
    /// An IMU stopped answering.
    SensorLost(ImuError),
}

impl std::fmt::Display for ArmFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ArmFailure::Procedure(e) => write!(f, "{e}"),
            ArmFailure::SolverTimedOut => write!(
                f,
                "the sensor set-up did not finish computing within {} s",
                SOLVE_TIMEOUT.as_secs()
            ),
            ArmFailure::SensorLost(e) => write!(f, "an IMU stopped answering ({e})"),
        }
    }
}

/// Say how the mounting came out (on the thread that solved it, never the haptic thread in
/// real time).
fn log_outcome(outcome: &Result<GuidedOutcome, ImuError>) {
    match outcome {
        Ok(out) => tracing::info!(
            swapped = out.swapped,
            gravity_misfit_deg = ?(
                out.report.gravity_misfit_rad.0.to_degrees(),
                out.report.gravity_misfit_rad.1.to_degrees()
            ),
            "IMU mounting found"
        ),
        Err(e) => tracing::warn!("arm sensing off for this session: {e}"),
    }
}

/// Solves a finished procedure on a thread of its own: the solve takes tens of milliseconds,
/// far more than a haptic tick, and freeing the procedure's buffers is no job for the haptic
/// thread either. The procedure goes there in its box and only the outcome comes back, both
/// through wait-free rings (no allocation, no lock on the haptic thread).
struct Solver {
    to: rtrb::Producer<Box<GuidedMounting>>,
    from: rtrb::Consumer<Result<GuidedOutcome, ImuError>>,
}

impl Solver {
    fn spawn() -> std::io::Result<Self> {
        let (to, mut requests) = rtrb::RingBuffer::<Box<GuidedMounting>>::new(1);
        let (mut results, from) = rtrb::RingBuffer::new(1);
        std::thread::Builder::new()
            .name("arm-solver".into())
            .spawn(move || {
                loop {
                    match requests.pop() {
                        Ok(procedure) => {
                            let outcome = procedure.solve();
                            log_outcome(&outcome);
                            let _ = results.push(outcome);
                            return;
                        }
                        // The session ended before the procedure did.
                        Err(_) if requests.is_abandoned() => return,
                        Err(_) => std::thread::sleep(Duration::from_millis(5)),
                    }
                }
            })?;
        Ok(Self { to, from })
    }
}

/// What the tracker was handed in one tick besides the wheel: its raw inputs, recorded on
/// `/raw/wheel` and `/raw/imu` so that a replay hands it the same.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ArmSeam {
    /// The samples of both IMUs it was stepped with (on the recording's grid); `None` when
    /// it was not stepped.
    pub stepped: Option<(ImuSample, ImuSample)>,
    /// An IMU stopped answering.
    pub lost: bool,
    /// The lost IMU answered again.
    pub regained: bool,
    /// The mounting solver's answer was in hand while the set-up waited for it.
    pub solver_answered: bool,
    /// The mounting solver timed out.
    pub solver_timed_out: bool,
}

/// The solver's answer and time-out as a recording says they came (a replay), instead of
/// from the solver thread and the clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecordedSolver {
    /// The answer was in hand this tick.
    pub answered: bool,
    /// The solver timed out this tick.
    pub timed_out: bool,
}

/// What tracking needs once the mounting is known.
struct Tracking {
    estimator: ArmPoseEstimator,
    mounting: Mounting,
    /// The second IMU is on the upper arm (found by the procedure).
    swapped: bool,
    /// Frozen or saturated samples of each IMU (device order), kept from the estimator.
    checks: [SampleCheck; 2],
}

/// Fresh samples with the very same three rates before an IMU counts as frozen: a MEMS gyro's
/// noise (several LSB at rest) makes even two equal readings of three axes rare, and 20 in a
/// row (20 ms at 1 kHz, 80 ms at 250 Hz) do not happen on a live sensor.
const FROZEN_AFTER: u32 = 20;

/// Tells a frozen or saturated IMU from a live one, sample by sample.
#[derive(Clone, Copy, Debug)]
struct SampleCheck {
    last_t_ns: u64,
    last_rate: [f64; 3],
    /// Fresh samples in a row with the same rates as the one before.
    repeats: u32,
    /// The rates this sensor reads before it clips (its device's own full scale).
    range: GyroRange,
}

impl Default for SampleCheck {
    fn default() -> Self {
        Self {
            last_t_ns: 0,
            last_rate: [0.0; 3],
            repeats: 0,
            range: GyroRange::symmetric(sim::IMU_FULL_SCALE_RAD_S),
        }
    }
}

impl SampleCheck {
    /// `s` as the estimator may use it: with NaN rates (which its filters ignore) when the
    /// sensor is saturated (a rate at its device's full scale, which clips) or frozen.
    fn usable(&mut self, s: &ImuSample) -> ImuSample {
        let rate = rates(s);
        if s.t_ns != self.last_t_ns {
            self.repeats = if rate == self.last_rate {
                self.repeats.saturating_add(1)
            } else {
                0
            };
            self.last_t_ns = s.t_ns;
            self.last_rate = rate;
        }
        let saturated = self.range.clips(&s.rate_rad_s);
        if saturated || self.repeats >= FROZEN_AFTER {
            ImuSample {
                rate_rad_s: nalgebra::Vector3::repeat(f64::NAN),
                ..*s
            }
        } else {
            *s
        }
    }
}

/// Mounting procedure, then pose estimation (see the module docs).
pub struct ArmTracker {
    geometry: ArmGeometry,
    /// Elbow swivel assumed for the procedure's still step, rad.
    swivel_rad: f64,
    /// The guided procedure until it is handed to the solver (kept, not freed, if it fails on
    /// its own: the haptic thread frees nothing).
    procedure: Option<Box<GuidedMounting>>,
    solver: Option<Solver>,
    tracking: Option<Tracking>,
    step: SetupStep,
    failure: Option<ArmFailure>,
    /// The clock of the solver's time-out.
    clock: Clock,
    /// When the procedure went to the solver, ns on `clock`.
    solving_since_ns: Option<u64>,
    /// When the procedure ended, session time, ns ([`SOLVE_HOLD_NS`] runs from it).
    solve_started_t_ns: u64,
    /// The solver's answer, held until [`SOLVE_HOLD_NS`] has passed.
    solved: Option<Result<GuidedOutcome, ImuError>>,
    last: ArmSample,
    /// Ticks on which the estimator refused the wheel angle (arm out of reach).
    pub rejected: u64,
    /// This tick's raw inputs so far.
    seam: ArmSeam,
    /// In a replay: the solver's events as recorded for this tick.
    recorded_solver: Option<RecordedSolver>,
    /// The rates each IMU (device order) reads before it clips.
    gyro_ranges: [GyroRange; 2],
}

impl ArmTracker {
    /// Tracking from the start, with a known `mounting`, for a patient who holds elbow swivel
    /// `swivel_rad` at the start.
    pub fn known(
        geometry: ArmGeometry,
        mounting: Mounting,
        swivel_rad: f64,
    ) -> Result<Self, ImuError> {
        let mut estimator = ArmPoseEstimator::new(geometry, mounting, FusionConfig::default())?;
        estimator.set_initial_swivel(swivel_rad);
        Ok(Self {
            tracking: Some(Tracking {
                estimator,
                mounting,
                swapped: false,
                checks: Default::default(),
            }),
            step: SetupStep::Tracking,
            // Nothing to time out: the mounting is known.
            ..Self::empty(geometry, swivel_rad, Clock::real())
        })
    }

    /// The guided procedure first, for a patient holding the wheel with elbow swivel
    /// `swivel_rad`. In real time the mounting is solved on a thread of its own; otherwise
    /// (`real_time` false: a simulation as fast as possible) in line, which keeps the run
    /// independent of wall-clock time. The solver's time-out runs on `clock`.
    pub fn guided(
        geometry: ArmGeometry,
        swivel_rad: f64,
        real_time: bool,
        clock: Clock,
    ) -> Result<Self, ImuError> {
        let cfg = ProcedureConfig::default();
        let solver = if real_time {
            Solver::spawn()
                .inspect_err(|e| {
                    tracing::warn!("no solver thread ({e}): the mounting is solved in line")
                })
                .ok()
        } else {
            None
        };
        Ok(Self {
            procedure: Some(Box::new(GuidedMounting::new(geometry, swivel_rad, cfg)?)),
            solver,
            step: SetupStep::HoldStill {
                remaining_s: cfg.still_s,
            },
            ..Self::empty(geometry, swivel_rad, clock)
        })
    }

    fn empty(geometry: ArmGeometry, swivel_rad: f64, clock: Clock) -> Self {
        Self {
            geometry,
            swivel_rad,
            procedure: None,
            solver: None,
            tracking: None,
            step: SetupStep::Failed,
            failure: None,
            clock,
            solving_since_ns: None,
            solve_started_t_ns: 0,
            solved: None,
            last: ArmSample::default(),
            rejected: 0,
            seam: ArmSeam::default(),
            recorded_solver: None,
            gyro_ranges: [GyroRange::symmetric(sim::IMU_FULL_SCALE_RAD_S); 2],
        }
    }

    /// The full scale of each IMU's gyro (`a`, `b` in device order), each device's own (a
    /// DualShock 4 clips at 1999.94 °/s, a Joy-Con at 2294 °/s): a rate at it is clipped and
    /// not used. Without this call, ±[`sim::IMU_FULL_SCALE_RAD_S`] (the
    /// simulated sensors').
    pub fn set_gyro_ranges(&mut self, ranges: [GyroRange; 2]) {
        self.gyro_ranges = ranges;
        if let Some(t) = &mut self.tracking {
            t.checks[0].range = ranges[0];
            t.checks[1].range = ranges[1];
        }
    }

    /// Fresh sample checks with each IMU's full scale.
    fn fresh_checks(&self) -> [SampleCheck; 2] {
        self.gyro_ranges.map(|range| SampleCheck {
            range,
            ..SampleCheck::default()
        })
    }

    /// This tick's raw inputs, taken (the next tick starts afresh).
    pub fn take_seam(&mut self) -> ArmSeam {
        std::mem::take(&mut self.seam)
    }

    /// In a replay: the solver's answer and time-out this tick as recorded. From the first
    /// call on, a procedure is solved in line when it ends and its answer is used from the
    /// recorded tick on; the solver thread and the clock are no longer asked.
    pub fn replay_solver(&mut self, events: RecordedSolver) {
        self.recorded_solver = Some(events);
    }

    /// Where the sensing is now.
    pub fn step_now(&self) -> SetupStep {
        self.step
    }

    /// Why there are no (more) joint angles, if so.
    pub fn failure(&self) -> Option<&ArmFailure> {
        self.failure.as_ref()
    }

    /// An IMU stopped answering (`error`): the pose stays frozen from now on.
    pub fn lose_sensor(&mut self, error: ImuError) {
        self.seam.lost = true;
        if self.failure.is_none() {
            self.failure = Some(ArmFailure::SensorLost(error));
        }
        self.step = SetupStep::SensorLost;
        self.last.setup = self.step.label();
    }

    /// The lost IMU answers again: tracking resumes with the mounting found before (the straps
    /// did not move: a cable or a radio link came back), the sensors' orientations re-acquired
    /// from the arm chain at the wheel's angle on the next update. A sensor lost before its
    /// mounting was known leaves the sensing failed (the guided procedure is not re-run in the
    /// middle of an exercise).
    pub fn regain_sensor(&mut self) {
        self.seam.regained = true;
        if self.step != SetupStep::SensorLost {
            return;
        }
        let checks = self.fresh_checks();
        self.step = match &mut self.tracking {
            Some(t) => {
                t.estimator.reacquire();
                t.checks = checks;
                self.failure = None;
                SetupStep::Tracking
            }
            None => SetupStep::Failed,
        };
        self.last.setup = self.step.label();
    }

    /// One tick with the latest sample of each IMU (`a` and `b` in the order the devices were
    /// opened; the procedure finds which is on the upper arm).
    pub fn update(&mut self, wheel: WheelNow, a: &ImuSample, b: &ImuSample) -> ArmSample {
        // The device edge: on the recording's grid, so that `/raw/imu` holds exactly what is
        // consumed here.
        let (a, b) = (&imu_on_grid(a), &imu_on_grid(b));
        self.seam.stepped = Some((*a, *b));
        match self.step {
            SetupStep::HoldStill { .. } | SetupStep::TurnWheel { .. } => {
                self.step = self.follow_procedure(wheel, a, b);
            }
            SetupStep::Solving => self.step = self.wait_for_solver(wheel.t_ns),
            SetupStep::Tracking => self.track(wheel, a, b),
            SetupStep::Failed | SetupStep::SensorLost => {}
        }
        let swapped = self.tracking.as_ref().is_some_and(|t| t.swapped);
        let (upper, fore) = if swapped { (b, a) } else { (a, b) };
        let [ux, uy, uz] = rates(upper);
        let [fx, fy, fz] = rates(fore);
        self.last.upper_gyro_x_rad_s = ux;
        self.last.upper_gyro_y_rad_s = uy;
        self.last.upper_gyro_z_rad_s = uz;
        self.last.fore_gyro_x_rad_s = fx;
        self.last.fore_gyro_y_rad_s = fy;
        self.last.fore_gyro_z_rad_s = fz;
        self.last.setup = self.step.label();
        self.last.setup_remaining_s = self.step.remaining_s();
        self.last
    }

    /// One tick of the guided procedure.
    fn follow_procedure(&mut self, wheel: WheelNow, a: &ImuSample, b: &ImuSample) -> SetupStep {
        let Some(procedure) = &mut self.procedure else {
            return SetupStep::Failed;
        };
        match procedure.step(wheel.t_ns, wheel.angle_rad, wheel.rate_rad_s, a, b) {
            Prompt::HoldStill { remaining_s } => SetupStep::HoldStill { remaining_s },
            Prompt::TurnWheel { remaining_s, .. } => SetupStep::TurnWheel { remaining_s },
            Prompt::ReadyToSolve => self.solve(wheel.t_ns),
            // The procedure gave up by itself (it keeps its box until the session ends).
            Prompt::Done => match procedure.take_outcome() {
                Some(outcome) => self.finish(outcome),
                None => SetupStep::Failed,
            },
        }
    }

    /// Hand the finished procedure (at session time `t_ns`) to the solver thread, or solve it
    /// here without one; either way the answer waits for [`SOLVE_HOLD_NS`].
    fn solve(&mut self, t_ns: u64) -> SetupStep {
        let Some(procedure) = self.procedure.take() else {
            return SetupStep::Failed;
        };
        self.solving_since_ns = Some(self.clock.now_ns());
        self.solve_started_t_ns = t_ns;
        let procedure = match &mut self.solver {
            Some(solver) if self.recorded_solver.is_none() => match solver.to.push(procedure) {
                Ok(()) => return SetupStep::Solving,
                Err(rtrb::PushError::Full(p)) => p,
            },
            _ => procedure,
        };
        let outcome = procedure.solve();
        log_outcome(&outcome);
        self.solved = Some(outcome);
        SetupStep::Solving
    }

    /// The solver's answer once [`SOLVE_HOLD_NS`] of session time has passed (`t_ns` now), or
    /// give up after [`SOLVE_TIMEOUT`] so that the exercise never waits forever (a dead solver
    /// thread).
    fn wait_for_solver(&mut self, t_ns: u64) -> SetupStep {
        if self.solved.is_none() && self.recorded_solver.is_none() {
            self.solved = self.solver.as_mut().and_then(|s| s.from.pop().ok());
        }
        // In a replay the answer (solved in line) counts from the tick it came in the session.
        let answered = match self.recorded_solver {
            Some(r) => r.answered && self.solved.is_some(),
            None => self.solved.is_some(),
        };
        self.seam.solver_answered = answered;
        if answered {
            if t_ns.saturating_sub(self.solve_started_t_ns) < SOLVE_HOLD_NS {
                return SetupStep::Solving;
            }
            if let Some(outcome) = self.solved.take() {
                return self.finish(outcome);
            }
        }
        let timed_out = match self.recorded_solver {
            Some(r) => r.timed_out,
            None => {
                let now_ns = self.clock.now_ns();
                self.solving_since_ns
                    .is_some_and(|t| Duration::from_nanos(now_ns.saturating_sub(t)) > SOLVE_TIMEOUT)
            }
        };
        if timed_out {
            self.seam.solver_timed_out = true;
            self.failure = Some(ArmFailure::SolverTimedOut);
            return SetupStep::Failed;
        }
        SetupStep::Solving
    }

    /// The procedure ended: track with its mounting, starting from the swivel the patient
    /// held in the still step, or remember why not.
    fn finish(&mut self, outcome: Result<GuidedOutcome, ImuError>) -> SetupStep {
        let checks = self.fresh_checks();
        let started = outcome.and_then(|out| {
            let mut estimator =
                ArmPoseEstimator::new(self.geometry, out.mounting, FusionConfig::default())?;
            estimator.set_initial_swivel(self.swivel_rad + out.report.still_swivel_offset_rad);
            Ok(Tracking {
                estimator,
                mounting: out.mounting,
                swapped: out.swapped,
                checks,
            })
        });
        match started {
            Ok(tracking) => {
                self.tracking = Some(tracking);
                SetupStep::Tracking
            }
            Err(e) => {
                self.failure = Some(ArmFailure::Procedure(e));
                SetupStep::Failed
            }
        }
    }

    /// One tick of pose estimation.
    fn track(&mut self, wheel: WheelNow, a: &ImuSample, b: &ImuSample) {
        let Some(t) = &mut self.tracking else { return };
        // Frozen or saturated rates carry no motion: the filters hold rather than integrate.
        let (a, b) = (t.checks[0].usable(a), t.checks[1].usable(b));
        let (upper, fore) = if t.swapped { (&b, &a) } else { (&a, &b) };
        let pose = match t.estimator.update(wheel.angle_rad, upper, fore, wheel.dt_s) {
            Ok(pose) => pose,
            Err(_) => {
                self.rejected += 1;
                return;
            }
        };
        let x = pose.angles;
        let (qu, qf) = t.estimator.sensor_orientations();
        let wxyz = |q: UnitQuaternion<f64>| [q.w, q.i, q.j, q.k];
        // Segment long axes (x) from the IMUs alone: sensor-to-earth · segment-to-sensor.
        let axis = |q: UnitQuaternion<f64>| {
            let v = q * nalgebra::Vector3::x();
            [v.x, v.y, v.z]
        };
        let g = self.geometry.grip(wheel.angle_rad);
        self.last = ArmSample {
            upper_axis: axis(qu * t.mounting.upper.inverse()),
            fore_axis: axis(qf * t.mounting.fore.inverse()),
            grip_m: [g.x, g.y, g.z],
            upper_orientation_wxyz: wxyz(qu),
            fore_orientation_wxyz: wxyz(qf),
            range_of_motion_rad: t.estimator.range_of_motion().range_rad(),
            shoulder_elevation_rad: x.shoulder_elevation_rad,
            shoulder_plane_rad: x.shoulder_plane_rad,
            shoulder_rotation_rad: x.shoulder_rotation_rad,
            elbow_flexion_rad: x.elbow_flexion_rad,
            forearm_pronation_rad: x.forearm_pronation_rad,
            fit_residual_rad: pose.fit_residual_rad,
            ..self.last
        };
    }

    /// Range of motion of each estimated joint angle this session, rad (field order of
    /// `gyro_imu::arm::JointAngles`); zeros before tracking starts.
    pub fn range_of_motion_rad(&self) -> [f64; 5] {
        self.tracking
            .as_ref()
            .map_or([0.0; 5], |t| t.estimator.range_of_motion().range_rad())
    }
}

fn rates(s: &ImuSample) -> [f64; 3] {
    [s.rate_rad_s.x, s.rate_rad_s.y, s.rate_rad_s.z]
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn a_procedure_that_gives_up_leaves_tracking_off_with_the_reason_to_tell() {
        let mut tracker =
            ArmTracker::guided(ArmGeometry::default(), 0.35, false, Clock::real()).unwrap();
        let still = ImuSample {
            t_ns: 0,
            rate_rad_s: Vector3::zeros(),
            acc_m_s2: Some(Vector3::z() * 9.81),
        };
        // The patient holds still, then never turns the wheel: the procedure gives up at 90 s.
        let mut sample = ArmSample::default();
        for k in 0..20_000u64 {
            let wheel = WheelNow {
                t_ns: k * 5_000_000,
                angle_rad: 0.0,
                rate_rad_s: 0.0,
                dt_s: 0.005,
            };
            sample = tracker.update(wheel, &still, &still);
        }
        assert_eq!(tracker.step_now(), SetupStep::Failed);
        assert_eq!(sample.setup, ArmSetup::Failed);
        let why = tracker.failure().expect("a reason").to_string();
        assert!(why.contains("did not turn far enough"), "{why}");
    }

    #[test]
    fn a_solver_that_never_answers_times_out_after_10_s_on_the_sessions_clock() {
        let (clock, mock) = Clock::mock();
        let mut tracker =
            ArmTracker::guided(ArmGeometry::default(), 0.35, false, clock.clone()).unwrap();
        // A solver thread that takes the procedure and never answers (the far ends are kept
        // so the rings stay open).
        let (to, _requests) = rtrb::RingBuffer::new(1);
        let (_results, from) = rtrb::RingBuffer::new(1);
        tracker.solver = Some(Solver { to, from });
        mock.advance_ns(123_456);
        tracker.step = tracker.solve(0);
        assert_eq!(tracker.step_now(), SetupStep::Solving);
        let still = ImuSample {
            t_ns: 0,
            rate_rad_s: Vector3::zeros(),
            acc_m_s2: Some(Vector3::z() * 9.81),
        };
        let wheel = WheelNow {
            t_ns: 0,
            angle_rad: 0.0,
            rate_rad_s: 0.0,
            dt_s: 0.001,
        };
        mock.advance(SOLVE_TIMEOUT);
        let sample = tracker.update(wheel, &still, &still);
        assert_eq!(
            (tracker.step_now(), sample.setup),
            (SetupStep::Solving, ArmSetup::Solving),
            "exactly 10 s is not past the time-out"
        );
        assert!(tracker.failure().is_none());
        mock.advance_ns(1);
        let sample = tracker.update(wheel, &still, &still);
        assert_eq!(
            (tracker.step_now(), sample.setup),
            (SetupStep::Failed, ArmSetup::Failed)
        );
        assert!(matches!(
            tracker.failure(),
            Some(ArmFailure::SolverTimedOut)
        ));
        let why = tracker.failure().unwrap().to_string();
        assert!(why.contains("within 10 s"), "{why}");
    }

    #[test]
    fn the_saturation_check_uses_each_devices_own_full_scale() {
        let ds4 = gyro_imu::device::sony::SonyCalibration::nominal().gyro_range();
        let joycon = gyro_imu::device::switch::SwitchCalibration::nominal().gyro_range();
        let at = |deg_s: f64| ImuSample {
            t_ns: 1,
            rate_rad_s: Vector3::new(deg_s.to_radians(), 0.0, 0.0),
            acc_m_s2: None,
        };
        let used = |range: GyroRange, deg_s: f64| {
            let mut check = SampleCheck {
                range,
                ..SampleCheck::default()
            };
            check.usable(&at(deg_s)).rate_rad_s.x.is_finite()
        };
        // A DualShock 4's largest count, 1999.94 °/s, is clipped though below 2000 °/s.
        let ds4_top_deg_s = ds4.max_rad_s[0].to_degrees();
        assert!(ds4_top_deg_s < 2000.0);
        assert!(!used(ds4, ds4_top_deg_s));
        assert!(used(ds4, ds4_top_deg_s - 0.061));
        assert!(!used(ds4, -2000.0));
        // A Joy-Con measures 2100 °/s; a DualShock 4 cannot.
        assert!(used(joycon, 2100.0));
        assert!(!used(ds4, 2100.0));
        assert!(!used(joycon, joycon.max_rad_s[0].to_degrees()));
        // The tracker hands each IMU its own range, the second device's to the second check.
        let mounting = Mounting {
            upper: UnitQuaternion::identity(),
            fore: UnitQuaternion::identity(),
        };
        let mut tracker = ArmTracker::known(ArmGeometry::default(), mounting, 0.35).unwrap();
        tracker.set_gyro_ranges([ds4, joycon]);
        let checks = tracker.tracking.as_mut().unwrap().checks;
        assert_eq!(checks.map(|c| c.range), [ds4, joycon]);
        tracker.lose_sensor(ImuError::Device("gone".into()));
        tracker.regain_sensor();
        let checks = tracker.tracking.as_mut().unwrap().checks;
        assert_eq!(checks.map(|c| c.range), [ds4, joycon]);
    }

    #[test]
    fn a_lost_sensor_freezes_the_pose_and_says_so() {
        let mounting = Mounting {
            upper: UnitQuaternion::identity(),
            fore: UnitQuaternion::identity(),
        };
        let mut tracker = ArmTracker::known(ArmGeometry::default(), mounting, 0.35).unwrap();
        tracker.lose_sensor(ImuError::Device("read: device disconnected".into()));
        assert_eq!(tracker.step_now(), SetupStep::SensorLost);
        let why = tracker.failure().unwrap().to_string();
        assert!(
            why.contains("stopped answering") && why.contains("disconnected"),
            "{why}"
        );
    }
}
