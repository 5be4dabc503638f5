//! The patient's arm from two IMUs and the wheel: the guided mounting procedure when the
//! sensors' placement is unknown (always with real IMUs), then the pose estimator. The same
//! [`ArmTracker`] runs behind simulated IMUs ([`sim`]) and controller IMUs over HID ([`hid`]).
//! Allocation-free per tick.

pub mod hid;
pub mod sim;

use crate::session::record::ArmSample;
use gyro_imu::ImuError;
use gyro_imu::arm::ArmGeometry;
use gyro_imu::device::ImuSample;
use gyro_imu::fusion::FusionConfig;
use gyro_imu::pose::{ArmPoseEstimator, Mounting};
use gyro_imu::procedure::{GuidedMounting, ProcedureConfig, Prompt};
use serde::{Deserialize, Serialize};

/// How the IMUs' placement on the arm is known.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MountingMode {
    /// Simulated IMUs strapped on with their axes along the segments' (simulation only).
    #[default]
    Square,
    /// Simulated IMUs strapped on at seeded random rotations, found by the guided procedure
    /// at the start of the session, as with real IMUs.
    Guided,
}

/// The `[arm]` section: arm sensing settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ArmConfig {
    /// IMU placement in simulated sessions (real IMUs always run the guided procedure).
    pub sim_mounting: MountingMode,
    /// The real patient's arm and seat geometry (the simulated patient's is `sim_arm`).
    pub geometry: ArmGeometry,
    /// Elbow swivel (rad, positive = elbow out) the real patient holds during the guided
    /// procedure.
    pub swivel_rad: f64,
}

impl Default for ArmConfig {
    fn default() -> Self {
        Self {
            sim_mounting: MountingMode::default(),
            geometry: ArmGeometry::default(),
            swivel_rad: 0.35,
        }
    }
}

impl ArmConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        self.geometry.validate()?;
        if !(self.swivel_rad.is_finite() && self.swivel_rad.abs() <= 1.5) {
            return Err(ImuError::InvalidConfig {
                field: "swivel_rad",
                value: self.swivel_rad,
                allowed: "[-1.5, 1.5] rad",
            });
        }
        gyro_imu::arm::solve(&self.geometry, 0.0, self.swivel_rad, 0.0).map(|_| ())
    }
}

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
}

impl SetupStep {
    /// The step as a stable label for recordings.
    pub fn label(self) -> &'static str {
        match self {
            SetupStep::Tracking => "tracking",
            SetupStep::HoldStill { .. } => "hold-still",
            SetupStep::TurnWheel { .. } => "turn-wheel",
            SetupStep::Solving => "solving",
            SetupStep::Failed => "failed",
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
const SOLVE_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(10);

/// Solves a finished procedure on a thread of its own: the solve takes tens of milliseconds,
/// far more than a haptic tick. The procedure travels there and back in its box through
/// wait-free rings (no allocation, no lock on the haptic thread).
struct Solver {
    to: rtrb::Producer<Box<GuidedMounting>>,
    from: rtrb::Consumer<Box<GuidedMounting>>,
}

impl Solver {
    fn spawn() -> std::io::Result<Self> {
        let (to, mut requests) = rtrb::RingBuffer::<Box<GuidedMounting>>::new(1);
        let (mut results, from) = rtrb::RingBuffer::<Box<GuidedMounting>>::new(1);
        std::thread::Builder::new()
            .name("arm-solver".into())
            .spawn(move || {
                loop {
                    match requests.pop() {
                        Ok(mut procedure) => {
                            let outcome = procedure.solve();
                            procedure.set_outcome(outcome);
                            let _ = results.push(procedure);
                            return;
                        }
                        // The session ended before the procedure did.
                        Err(_) if requests.is_abandoned() => return,
                        Err(_) => std::thread::sleep(std::time::Duration::from_millis(5)),
                    }
                }
            })?;
        Ok(Self { to, from })
    }
}

/// Mounting procedure, then pose estimation (see the module docs).
pub struct ArmTracker {
    geometry: ArmGeometry,
    /// Elbow swivel assumed for the procedure's still step, rad.
    swivel_rad: f64,
    /// Sensor-to-segment rotations, once known.
    mounting: Option<Mounting>,
    setup: Option<Box<GuidedMounting>>,
    solver: Option<Solver>,
    estimator: Option<ArmPoseEstimator>,
    /// The second IMU is on the upper arm (found by the procedure).
    swapped: bool,
    step: SetupStep,
    /// When the procedure went to the solver (wall clock).
    solving_since: Option<std::time::Instant>,
    last: ArmSample,
    /// Ticks on which the estimator refused the wheel angle (arm out of reach).
    pub rejected: u64,
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
            geometry,
            swivel_rad,
            mounting: Some(mounting),
            setup: None,
            solver: None,
            estimator: Some(estimator),
            swapped: false,
            step: SetupStep::Tracking,
            solving_since: None,
            last: ArmSample::default(),
            rejected: 0,
        })
    }

    /// The guided procedure first, for a patient holding the wheel with elbow swivel
    /// `swivel_rad`. In real time the mounting is solved on a thread of its own; otherwise
    /// (`real_time` false: a simulation as fast as possible) in line, which keeps the run
    /// independent of wall-clock time.
    pub fn guided(
        geometry: ArmGeometry,
        swivel_rad: f64,
        real_time: bool,
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
            geometry,
            swivel_rad,
            mounting: None,
            setup: Some(Box::new(GuidedMounting::new(geometry, swivel_rad, cfg)?)),
            solver,
            estimator: None,
            swapped: false,
            step: SetupStep::HoldStill {
                remaining_s: cfg.still_s,
            },
            solving_since: None,
            last: ArmSample::default(),
            rejected: 0,
        })
    }

    /// Where the sensing is now.
    pub fn step_now(&self) -> SetupStep {
        self.step
    }

    /// One tick with the latest sample of each IMU (`a` and `b` in the order the devices were
    /// opened; the procedure finds which is on the upper arm).
    pub fn update(&mut self, wheel: WheelNow, a: &ImuSample, b: &ImuSample) -> ArmSample {
        if let Some(setup) = &mut self.setup {
            let prompt = setup.step(wheel.t_ns, wheel.angle_rad, wheel.rate_rad_s, a, b);
            self.step = match prompt {
                Prompt::HoldStill { remaining_s } => SetupStep::HoldStill { remaining_s },
                Prompt::TurnWheel { remaining_s, .. } => SetupStep::TurnWheel { remaining_s },
                Prompt::ReadyToSolve => {
                    self.solving_since = Some(std::time::Instant::now());
                    self.hand_over_to_solver()
                }
                Prompt::Done => self.finish_setup(),
            };
        } else if self.step == SetupStep::Solving {
            if let Some(done) = self.solver.as_mut().and_then(|s| s.from.pop().ok()) {
                self.setup = Some(done);
                self.step = self.finish_setup();
            } else if self
                .solving_since
                .is_some_and(|t| t.elapsed() > SOLVE_TIMEOUT)
            {
                // The solver thread died or starves: the exercise must not wait forever.
                tracing::warn!(
                    "arm sensing off for this session: the mounting solve did not finish"
                );
                self.step = SetupStep::Failed;
            }
        } else if let Some(est) = &mut self.estimator {
            let (upper, fore) = if self.swapped { (b, a) } else { (a, b) };
            match est.update(wheel.angle_rad, upper, fore, wheel.dt_s) {
                Ok(pose) => {
                    let x = pose.angles;
                    let (qu, qf) = est.sensor_orientations();
                    let wxyz = |q: nalgebra::UnitQuaternion<f64>| [q.w, q.i, q.j, q.k];
                    // Segment long axes (x) from the IMUs: sensor-to-earth · segment-to-sensor.
                    let (upper_axis, fore_axis) = self.mounting.map_or(([0.0; 3], [0.0; 3]), |m| {
                        let axis = |q: nalgebra::UnitQuaternion<f64>| {
                            let v = q * nalgebra::Vector3::x();
                            [v.x, v.y, v.z]
                        };
                        (axis(qu * m.upper.inverse()), axis(qf * m.fore.inverse()))
                    });
                    let g = self.geometry.grip(wheel.angle_rad);
                    self.last = ArmSample {
                        upper_axis,
                        fore_axis,
                        grip_m: [g.x, g.y, g.z],
                        upper_orientation_wxyz: wxyz(qu),
                        fore_orientation_wxyz: wxyz(qf),
                        range_of_motion_rad: est.range_of_motion().range_rad(),
                        shoulder_elevation_rad: x.shoulder_elevation_rad,
                        shoulder_plane_rad: x.shoulder_plane_rad,
                        shoulder_rotation_rad: x.shoulder_rotation_rad,
                        elbow_flexion_rad: x.elbow_flexion_rad,
                        forearm_pronation_rad: x.forearm_pronation_rad,
                        fit_residual_rad: pose.fit_residual_rad,
                        ..self.last
                    };
                }
                Err(_) => self.rejected += 1,
            }
        }
        let (upper, fore) = if self.swapped { (b, a) } else { (a, b) };
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

    /// Send the finished procedure to the solver thread (or, without one, solve it here).
    fn hand_over_to_solver(&mut self) -> SetupStep {
        let Some(procedure) = self.setup.take() else {
            return self.step;
        };
        let refused = match &mut self.solver {
            Some(solver) => match solver.to.push(procedure) {
                Ok(()) => return SetupStep::Solving,
                Err(rtrb::PushError::Full(p)) => p,
            },
            None => procedure,
        };
        let mut procedure = refused;
        procedure.solve_now();
        self.setup = Some(procedure);
        self.finish_setup()
    }

    /// The procedure ended: start tracking with its mounting, or give up on arm sensing for
    /// this session (logged once, with the reason and what to do).
    fn finish_setup(&mut self) -> SetupStep {
        let Some(setup) = self.setup.take() else {
            return self.step;
        };
        let started = match setup.outcome() {
            Some(Ok(out)) => {
                tracing::info!(
                    swapped = out.swapped,
                    gravity_misfit_deg = ?(out.report.gravity_misfit_rad.0.to_degrees(), out.report.gravity_misfit_rad.1.to_degrees()),
                    "IMU mounting found"
                );
                self.swapped = out.swapped;
                self.mounting = Some(out.mounting);
                ArmPoseEstimator::new(self.geometry, out.mounting, FusionConfig::default()).map(
                    |mut est| {
                        // Start from the swivel the patient held in the still step.
                        est.set_initial_swivel(
                            self.swivel_rad + out.report.still_swivel_offset_rad,
                        );
                        est
                    },
                )
            }
            Some(Err(e)) => Err(ImuError::Calibration(e.to_string())),
            None => Err(ImuError::Calibration(
                "the procedure ended without a result".into(),
            )),
        };
        match started {
            Ok(est) => {
                self.estimator = Some(est);
                SetupStep::Tracking
            }
            Err(e) => {
                tracing::warn!("arm sensing off for this session: {e}");
                SetupStep::Failed
            }
        }
    }

    /// Range of motion of each estimated joint angle this session, rad (field order of
    /// `gyro_imu::arm::JointAngles`); zeros before tracking starts.
    pub fn range_of_motion_rad(&self) -> [f64; 5] {
        self.estimator
            .as_ref()
            .map_or([0.0; 5], |e| e.range_of_motion().range_rad())
    }
}

fn rates(s: &ImuSample) -> [f64; 3] {
    [s.rate_rad_s.x, s.rate_rad_s.y, s.rate_rad_s.z]
}
