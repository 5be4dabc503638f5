//! The trunk from a third IMU on the sternum (optional, `[arm] sternum`): the simulated
//! patient's trunk ([`gyro_imu::sim::trunk`]) wears a simulated sternum IMU like the arm's, and
//! [`TrunkEstimator`] turns its samples into the trunk's flexion, lean and rotation from the
//! start posture (taken again at each exercise's start). Allocation-free per tick.

use gyro_imu::ImuError;
use gyro_imu::sim::trunk::{SimTrunk, TrunkCompensationConfig};
use gyro_imu::trunk::{TrunkAngles, TrunkEstimator, trunk_angles};
use nalgebra::UnitQuaternion;
use record::ArmSample;
use record::raw::{ANGLE_QUANTUM_RAD, on_grid};

/// The simulated trunk, its sternum IMU and the estimator.
pub struct SimTrunkSensing {
    trunk: SimTrunk,
    estimator: TrunkEstimator,
    /// The true trunk orientation at the estimator's start posture (trunk-to-world).
    truth_start: Option<UnitQuaternion<f64>>,
}

/// `a` in rad on the recording's grid: what a replay reads back is what was measured.
fn on_grid_rad(a: &TrunkAngles) -> [f64; 3] {
    a.to_array()
        .map(|deg| on_grid(deg.to_radians(), ANGLE_QUANTUM_RAD))
}

impl SimTrunkSensing {
    /// The trunk of a simulated patient whose arm lost `weakness` of its strength, with the
    /// sternum IMU strapped square on the sternum (x forward, y left, z up); noise seeded.
    pub fn new(weakness: f64, seed: u64) -> Result<Self, ImuError> {
        let mount = UnitQuaternion::identity();
        Ok(Self {
            trunk: SimTrunk::consumer_mems(
                TrunkCompensationConfig::default(),
                weakness,
                mount,
                seed,
            )?,
            estimator: TrunkEstimator::new(mount, TrunkEstimator::fusion_config())?,
            truth_start: None,
        })
    }

    /// Move the trunk with the true wheel and estimate its angles into `sample` (left
    /// untracked while the fusion settles or the input is not finite).
    pub fn step(
        &mut self,
        t_ns: u64,
        true_wheel_rad: f64,
        true_wheel_rate_rad_s: f64,
        dt_s: f64,
        sample: &mut ArmSample,
    ) {
        let Ok(truth) = self
            .trunk
            .step(t_ns, true_wheel_rad, true_wheel_rate_rad_s, dt_s)
        else {
            return;
        };
        let Some(imu) = self.trunk.latest() else {
            return;
        };
        let Some(est) = self.estimator.update(&imu, dt_s) else {
            return;
        };
        // The sensor sits square on the sternum: the sensor's orientation is the trunk's.
        if self.estimator.took_start() || self.truth_start.is_none() {
            self.truth_start = Some(truth.sensor);
        }
        let start = self.truth_start.unwrap_or(truth.sensor);
        let true_angles = trunk_angles(&start, &truth.sensor);
        sample.trunk_tracked = true;
        [
            sample.trunk_flexion_rad,
            sample.trunk_lean_rad,
            sample.trunk_rotation_rad,
        ] = on_grid_rad(&est);
        [
            sample.true_trunk_flexion_rad,
            sample.true_trunk_lean_rad,
            sample.true_trunk_rotation_rad,
        ] = on_grid_rad(&true_angles);
    }

    /// Take the next posture as the start posture (an exercise starts).
    pub fn restart(&mut self) {
        self.estimator.restart();
        self.truth_start = None;
    }
}
