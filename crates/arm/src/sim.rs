//! The simulated patient's arm: a simulated arm holding the wheel wears two simulated IMUs
//! (consumer MEMS noise and bias), and the [`ArmTracker`] that runs on real IMUs turns their
//! samples into joint angles. Allocation-free per tick.

use super::{ArmTracker, MountingMode, SetupStep, WheelNow};
use gyro_imu::ImuError;
use gyro_imu::pose::Mounting;
use gyro_imu::sim::arm::{PatientArmConfig, SimArm};
use gyro_imu::so3;
use nalgebra::{UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use record::ArmSample;

/// Full scale of the simulated consumer gyro, rad/s (±2000 °/s, `GyroSpec::consumer_mems`):
/// a rate at or beyond it is clipped by the sensor. Real controllers clip at their own full
/// scale (`gyro_imu::device::GyroRange`: a DualShock 4 at 1999.94 °/s, a Joy-Con at 2294 °/s).
pub const IMU_FULL_SCALE_RAD_S: f64 = 2000.0 * std::f64::consts::PI / 180.0;

/// A fault injected into the simulated IMUs (the session's `imu-*` faults, `session::faults`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImuFault {
    /// An IMU is unplugged: the tracker is told the sensor is lost, and told it is back when
    /// the fault's window ends.
    Unplug,
    /// Both IMUs send NaN rates.
    Nan,
    /// Both IMUs' rates freeze at their last value while their samples stay fresh.
    Frozen,
    /// Both IMUs' rates read their full scale, ±[`IMU_FULL_SCALE_RAD_S`].
    Saturated,
}

/// Simulated arm + IMUs + tracker.
pub struct SimArmSensing {
    arm: SimArm,
    tracker: ArmTracker,
    last: ArmSample,
    /// Ticks on which the simulated arm could not reach the wheel.
    pub unreachable: u64,
    /// Injected arm-sensor faults and their session-time windows, ns.
    faults: Vec<(ImuFault, u64, u64)>,
    /// An injected unplug has been told to the tracker (and its replug not yet).
    unplugged: bool,
    /// The rates an injected freeze holds (upper, fore), rad/s.
    held: Option<(Vector3<f64>, Vector3<f64>)>,
    /// The trunk and its sternum IMU, when one is worn.
    trunk: Option<super::trunk::SimTrunkSensing>,
}

/// A rotation drawn uniformly enough for a sensor strapped on any way.
fn random_rotation(rng: &mut impl Rng) -> UnitQuaternion<f64> {
    let v = Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    so3::exp_quat(&(v * std::f64::consts::PI))
}

impl SimArmSensing {
    /// The arm of `cfg` with seeded sensor noise. With [`MountingMode::Square`] the IMUs sit
    /// along the segments and tracking starts at once; with [`MountingMode::Guided`] they sit at
    /// seeded random rotations and the session starts with the guided procedure, which the
    /// simulated patient follows.
    /// `real_time`: the session runs on the wall clock (see [`ArmTracker::guided`]); `clock`
    /// times the guided procedure's solver out; `faults`: the injected IMU faults and their
    /// session-time windows `[start, end)`, ns.
    pub fn new(
        cfg: PatientArmConfig,
        mode: MountingMode,
        seed: u64,
        real_time: bool,
        clock: clock::Clock,
        faults: Vec<(ImuFault, u64, u64)>,
    ) -> Result<Self, ImuError> {
        let (mu, mf) = match mode {
            MountingMode::Square => (UnitQuaternion::identity(), UnitQuaternion::identity()),
            MountingMode::Guided => {
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x6d6f_756e_7469_6e67);
                (random_rotation(&mut rng), random_rotation(&mut rng))
            }
        };
        let arm = SimArm::consumer_mems(cfg, mu, mf, seed)?;
        let tracker = match mode {
            MountingMode::Square => ArmTracker::known(
                cfg.geometry,
                Mounting {
                    upper: mu,
                    fore: mf,
                },
                cfg.swivel_mean_rad,
            )?,
            MountingMode::Guided => {
                // The simulated patient's procedure times out on the session's clock, as a
                // real one does (the solver only runs in real time).
                ArmTracker::guided(cfg.geometry, cfg.swivel_mean_rad, real_time, clock)?
            }
        };
        Ok(Self {
            arm,
            tracker,
            last: ArmSample::default(),
            unreachable: 0,
            faults,
            unplugged: false,
            held: None,
            trunk: None,
        })
    }

    /// Also wear a sternum IMU on the trunk of a patient whose arm lost `weakness` of its
    /// strength (the sensor's noise seeded from `seed`).
    pub fn with_sternum(mut self, weakness: f64, seed: u64) -> Result<Self, ImuError> {
        self.trunk = Some(super::trunk::SimTrunkSensing::new(weakness, seed)?);
        Ok(self)
    }

    /// An exercise starts: the trunk's next posture is its start posture.
    pub fn restart_trunk(&mut self) {
        if let Some(t) = &mut self.trunk {
            t.restart();
        }
    }

    /// Where the arm sensing is (the simulated patient follows its prompts).
    pub fn setup_step(&self) -> SetupStep {
        self.tracker.step_now()
    }

    /// Move the arm with the true wheel (angle, rate) and estimate its pose from the IMU
    /// samples and the wheel as the host reads it. If the arm cannot reach the wheel the
    /// previous sample is kept and counted.
    pub fn step(
        &mut self,
        true_wheel_rad: f64,
        true_wheel_rate_rad_s: f64,
        read: WheelNow,
    ) -> ArmSample {
        let truth = match self
            .arm
            .step(read.t_ns, true_wheel_rad, true_wheel_rate_rad_s, read.dt_s)
        {
            Ok(t) => t,
            Err(_) => {
                self.unreachable += 1;
                return self.last;
            }
        };
        let Some((mut upper, mut fore)) = self.arm.latest() else {
            self.unreachable += 1;
            return self.last;
        };
        // Injected faults act on what the IMUs deliver, as a real sensor's would.
        let acting = |kind| {
            self.faults
                .iter()
                .any(|&(k, start, end)| k == kind && (start..end).contains(&read.t_ns))
        };
        // Told once per unplug (the haptic thread must not allocate each tick), and the
        // replug once when its window ends.
        let unplugged = acting(ImuFault::Unplug);
        if unplugged && !self.unplugged {
            self.unplugged = true;
            self.tracker
                .lose_sensor(ImuError::Gone("an arm IMU was unplugged (injected fault)"));
        } else if !unplugged && self.unplugged {
            self.unplugged = false;
            self.tracker.regain_sensor();
        }
        if acting(ImuFault::Nan) {
            upper.rate_rad_s.fill(f64::NAN);
            fore.rate_rad_s.fill(f64::NAN);
        }
        if acting(ImuFault::Frozen) {
            let (u, f) = *self.held.get_or_insert((upper.rate_rad_s, fore.rate_rad_s));
            (upper.rate_rad_s, fore.rate_rad_s) = (u, f);
        } else {
            self.held = None;
        }
        if acting(ImuFault::Saturated) {
            let full = |r: &mut Vector3<f64>| r.apply(|x| *x = IMU_FULL_SCALE_RAD_S.copysign(*x));
            full(&mut upper.rate_rad_s);
            full(&mut fore.rate_rad_s);
        }
        let mut sample = self.tracker.update(read, &upper, &fore);
        // The simulated truth on the recording's grid: a replay of the raw inputs takes it from
        // the recording, and the session's measures must see the same values.
        let grid = |x| record::raw::on_grid(x, record::raw::ANGLE_QUANTUM_RAD);
        sample.true_shoulder_elevation_rad = grid(truth.angles.shoulder_elevation_rad);
        sample.true_elbow_flexion_rad = grid(truth.angles.elbow_flexion_rad);
        if let Some(trunk) = &mut self.trunk {
            trunk.step(
                read.t_ns,
                true_wheel_rad,
                true_wheel_rate_rad_s,
                read.dt_s,
                &mut sample,
            );
        }
        self.last = sample;
        sample
    }

    /// This tick's raw inputs of the tracker, taken.
    pub fn take_seam(&mut self) -> super::ArmSeam {
        self.tracker.take_seam()
    }

    /// Why there are no (more) joint angles, if so.
    pub fn failure(&self) -> Option<&super::ArmFailure> {
        self.tracker.failure()
    }

    /// Range of motion of each estimated joint angle this session, rad.
    pub fn range_of_motion_rad(&self) -> [f64; 5] {
        self.tracker.range_of_motion_rad()
    }
}
