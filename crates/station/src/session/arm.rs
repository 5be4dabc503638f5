//! The patient's arm in a simulated session: a simulated arm holding the wheel wears two
//! simulated IMUs (consumer MEMS noise and bias), and the same pose estimator that runs on
//! real IMUs turns their samples into joint angles. Allocation-free per tick.

use crate::session::record::ArmSample;
use gyro_imu::ImuError;
use gyro_imu::device::ImuSample;
use gyro_imu::fusion::FusionConfig;
use gyro_imu::pose::{ArmPoseEstimator, Mounting};
use gyro_imu::sensor::{AccSpec, GyroSpec};
use gyro_imu::sim::arm::{PatientArmConfig, SimArm};
use nalgebra::UnitQuaternion;

/// Simulated arm + IMUs + pose estimator.
pub struct SimArmSensing {
    arm: SimArm,
    estimator: ArmPoseEstimator,
    last: ArmSample,
    /// Ticks on which the estimator refused the wheel angle (arm out of reach).
    pub rejected: u64,
}

impl SimArmSensing {
    /// The arm of `cfg` with seeded sensor noise. The simulated IMUs are strapped on with a
    /// known mounting (identity); with real IMUs the mounting comes from the guided
    /// procedure in `gyro_imu::mounting`.
    pub fn new(cfg: PatientArmConfig, seed: u64) -> Result<Self, ImuError> {
        let id = UnitQuaternion::identity();
        let arm = SimArm::new(
            cfg,
            GyroSpec::consumer_mems(),
            Some(AccSpec::consumer_mems()),
            id,
            id,
            seed,
        )?;
        let estimator = ArmPoseEstimator::new(
            cfg.geometry,
            Mounting {
                upper: id,
                fore: id,
            },
            FusionConfig::default(),
        )?;
        Ok(Self {
            arm,
            estimator,
            last: ArmSample::default(),
            rejected: 0,
        })
    }

    /// Move the arm with the true wheel (angle, rate) and estimate its pose from the IMU
    /// samples and the wheel angle the host reads. On a refused sample the previous pose is
    /// kept and counted.
    pub fn step(
        &mut self,
        t_ns: u64,
        true_wheel_rad: f64,
        true_wheel_rate_rad_s: f64,
        read_wheel_rad: f64,
        dt_s: f64,
    ) -> ArmSample {
        let truth = match self
            .arm
            .step(t_ns, true_wheel_rad, true_wheel_rate_rad_s, dt_s)
        {
            Ok(t) => t,
            Err(_) => {
                self.rejected += 1;
                return self.last;
            }
        };
        let Some((upper, fore)) = self.arm.latest() else {
            self.rejected += 1;
            return self.last;
        };
        match self.estimator.update(read_wheel_rad, &upper, &fore, dt_s) {
            Ok(pose) => {
                let a = pose.angles;
                let [ux, uy, uz] = rates(&upper);
                let [fx, fy, fz] = rates(&fore);
                self.last = ArmSample {
                    shoulder_elevation_rad: a.shoulder_elevation_rad,
                    shoulder_plane_rad: a.shoulder_plane_rad,
                    shoulder_rotation_rad: a.shoulder_rotation_rad,
                    elbow_flexion_rad: a.elbow_flexion_rad,
                    forearm_pronation_rad: a.forearm_pronation_rad,
                    true_shoulder_elevation_rad: truth.angles.shoulder_elevation_rad,
                    true_elbow_flexion_rad: truth.angles.elbow_flexion_rad,
                    fit_residual_rad: pose.fit_residual_rad,
                    upper_gyro_x_rad_s: ux,
                    upper_gyro_y_rad_s: uy,
                    upper_gyro_z_rad_s: uz,
                    fore_gyro_x_rad_s: fx,
                    fore_gyro_y_rad_s: fy,
                    fore_gyro_z_rad_s: fz,
                };
            }
            Err(_) => self.rejected += 1,
        }
        self.last
    }

    /// Range of motion of each estimated joint angle this session, rad (field order of
    /// `gyro_imu::arm::JointAngles`).
    pub fn range_of_motion_rad(&self) -> [f64; 5] {
        self.estimator.range_of_motion().range_rad()
    }
}

fn rates(s: &ImuSample) -> [f64; 3] {
    [s.rate_rad_s.x, s.rate_rad_s.y, s.rate_rad_s.z]
}
