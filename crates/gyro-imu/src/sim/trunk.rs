//! The simulated patient's trunk and the IMU on the sternum.
//!
//! A patient whose arm is weak turns the wheel partly with the trunk: twisting toward the
//! turn, leaning sideways and bending forward to reach (trunk compensation; Cirstea & Levin,
//! "Compensatory strategies for reaching in stroke", *Brain* 123, 2000: the more impaired the
//! arm, the more the trunk moves). [`SimTrunk`] models it as trunk angles that follow the wheel
//! angle with gains scaled by the arm's weakness, on top of a slow postural sway; the trunk
//! pivots about the hips and carries the sternum IMU ([`crate::sensor`]'s error model).

use nalgebra::{UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::device::ImuSample;
use crate::error::{ImuError, check_range};
use crate::posture::{TrunkAngles, trunk_rotation};
use crate::sensor::{AccSpec, GyroSpec};
use crate::sim::arm::SimImu;
use crate::sim::wheel_acceleration;
use crate::so3;

/// How the simulated patient's trunk moves with the wheel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrunkCompensationConfig {
    /// Trunk rotation per radian of wheel angle of a fully weak arm (rad/rad; scaled by the
    /// weakness): the trunk twists toward the turn.
    pub rotation_per_wheel: f64,
    /// Lateral lean per radian of wheel angle of a fully weak arm (rad/rad, scaled likewise).
    pub lean_per_wheel: f64,
    /// Forward flexion per radian of wheel excursion (either way) of a fully weak arm
    /// (rad/rad, scaled likewise): the patient bends forward to reach.
    pub flexion_per_wheel: f64,
    /// Amplitude of the postural sway on each axis (rad); 0.003 rad (0.17°) is quiet sitting's
    /// order of magnitude.
    pub sway_amp_rad: f64,
    /// Typical frequency of the sway (Hz); each axis's is drawn from [0.5, 1.5] × this.
    pub sway_freq_hz: f64,
    /// Distance from the hips (the trunk's pivot) to the sternum IMU (m).
    pub sternum_height_m: f64,
    /// Forward flexion of the start posture (rad): patients rarely sit quite upright.
    pub start_flexion_rad: f64,
}

impl Default for TrunkCompensationConfig {
    fn default() -> Self {
        Self {
            rotation_per_wheel: 0.35,
            lean_per_wheel: 0.25,
            flexion_per_wheel: 0.2,
            sway_amp_rad: 0.003,
            sway_freq_hz: 0.1,
            sternum_height_m: 0.45,
            start_flexion_rad: 0.1,
        }
    }
}

impl TrunkCompensationConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        check_range(
            "rotation_per_wheel",
            self.rotation_per_wheel,
            0.0,
            1.0,
            "[0, 1]",
        )?;
        check_range("lean_per_wheel", self.lean_per_wheel, 0.0, 1.0, "[0, 1]")?;
        check_range(
            "flexion_per_wheel",
            self.flexion_per_wheel,
            0.0,
            1.0,
            "[0, 1]",
        )?;
        check_range("sway_amp_rad", self.sway_amp_rad, 0.0, 0.2, "[0, 0.2] rad")?;
        check_range("sway_freq_hz", self.sway_freq_hz, 0.0, 2.0, "[0, 2] Hz")?;
        check_range(
            "sternum_height_m",
            self.sternum_height_m,
            0.1,
            1.0,
            "[0.1, 1] m",
        )?;
        check_range(
            "start_flexion_rad",
            self.start_flexion_rad,
            -0.5,
            1.0,
            "[-0.5, 1] rad",
        )
    }
}

/// Smooth `|x|` (rad): `√(x² + ε²) − ε` with ε = 0.05 rad, so that the trunk's rate stays
/// continuous when the wheel passes the centre.
fn smooth_abs(x: f64) -> f64 {
    const EPS: f64 = 0.05;
    (x * x + EPS * EPS).sqrt() - EPS
}

/// The truth of one simulated tick of the trunk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimTrunkTruth {
    /// Trunk angles from the start posture.
    pub angles: TrunkAngles,
    /// Sternum sensor orientation (sensor-to-world).
    pub sensor: UnitQuaternion<f64>,
}

/// The simulated patient's trunk wearing an IMU on the sternum.
#[derive(Debug, Clone)]
pub struct SimTrunk {
    cfg: TrunkCompensationConfig,
    weakness: f64,
    /// Trunk-to-world orientation of the start posture.
    start: UnitQuaternion<f64>,
    /// Sway per axis (rotation, flexion, lean): frequency (Hz) and phase (rad).
    sway: [(f64, f64); 3],
    imu: SimImu,
    prev_wheel_rate: Option<f64>,
}

impl SimTrunk {
    /// A trunk compensating for an arm that lost `weakness` (in [0, 1)) of its strength (the
    /// simulated patient's `human_arm.weakness`), with a sternum sensor of the given specs
    /// mounted at the sensor-to-trunk rotation `mount`; sway and noise seeded from `seed`.
    pub fn new(
        cfg: TrunkCompensationConfig,
        weakness: f64,
        gyro: GyroSpec,
        acc: Option<AccSpec>,
        mount: UnitQuaternion<f64>,
        seed: u64,
    ) -> Result<Self, ImuError> {
        cfg.validate()?;
        check_range("weakness", weakness, 0.0, 0.999, "[0, 1)")?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x7472_756e_6b00);
        let sway = [(); 3].map(|()| {
            (
                cfg.sway_freq_hz * rng.random_range(0.5..1.5),
                rng.random_range(0.0..std::f64::consts::TAU),
            )
        });
        let heading = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let start = UnitQuaternion::from_euler_angles(0.0, cfg.start_flexion_rad, heading);
        Ok(Self {
            cfg,
            weakness,
            start,
            sway,
            imu: SimImu::new("sternum", gyro, acc, mount, seed.wrapping_add(0x5851_f42d))?,
            prev_wheel_rate: None,
        })
    }

    /// A trunk wearing a consumer-MEMS IMU ([`GyroSpec::consumer_mems`],
    /// [`AccSpec::consumer_mems`]) like the arm's: the usual simulated patient.
    pub fn consumer_mems(
        cfg: TrunkCompensationConfig,
        weakness: f64,
        mount: UnitQuaternion<f64>,
        seed: u64,
    ) -> Result<Self, ImuError> {
        Self::new(
            cfg,
            weakness,
            GyroSpec::consumer_mems(),
            Some(AccSpec::consumer_mems()),
            mount,
            seed,
        )
    }

    /// The sternum IMU.
    pub fn imu(&mut self) -> &mut SimImu {
        &mut self.imu
    }

    /// The latest sternum sample, if any tick has run.
    pub fn latest(&self) -> Option<ImuSample> {
        self.imu.latest()
    }

    /// The true trunk angles at `t_s` with the wheel at `wheel_rad`.
    pub fn angles(&self, t_s: f64, wheel_rad: f64) -> TrunkAngles {
        let k = self.weakness;
        let sway = self.sway.map(|(f_hz, ph)| {
            self.cfg.sway_amp_rad * (std::f64::consts::TAU * f_hz * t_s + ph).sin()
        });
        TrunkAngles {
            rotation_deg: (k * self.cfg.rotation_per_wheel * wheel_rad + sway[0]).to_degrees(),
            flexion_deg: (k * self.cfg.flexion_per_wheel * smooth_abs(wheel_rad) + sway[1])
                .to_degrees(),
            lean_deg: (k * self.cfg.lean_per_wheel * wheel_rad + sway[2]).to_degrees(),
        }
    }

    /// Simulate one tick at `t_ns` with the wheel at `wheel_rad` turning at
    /// `wheel_rate_rad_s`, `dt_s` after the previous tick. Leaves one sample in the IMU.
    pub fn step(
        &mut self,
        t_ns: u64,
        wheel_rad: f64,
        wheel_rate_rad_s: f64,
        dt_s: f64,
    ) -> Result<SimTrunkTruth, ImuError> {
        let wheel_acc =
            wheel_acceleration(&mut self.prev_wheel_rate, wheel_rad, wheel_rate_rad_s, dt_s)?;
        let t = t_ns as f64 * 1e-9;
        let trunk = |h: f64| {
            let w = wheel_rad + wheel_rate_rad_s * h + 0.5 * wheel_acc * h * h;
            self.start * trunk_rotation(&self.angles(t + h, w))
        };
        let h = 1e-3;
        let (q0, qp, qm) = (trunk(0.0), trunk(h), trunk(-h));
        let w_trunk = so3::log_quat(&(qm.inverse() * qp)) / (2.0 * h);
        let up = Vector3::z() * self.cfg.sternum_height_m;
        let acc = (qp * up - (q0 * up) * 2.0 + qm * up) / (h * h);
        let sensor = q0 * self.imu.mount();
        self.imu.sense(t_ns, &sensor, &w_trunk, &acc, dt_s);
        Ok(SimTrunkTruth {
            angles: self.angles(t, wheel_rad),
            sensor,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peak_excursion_deg(weakness: f64) -> f64 {
        let mut trunk = SimTrunk::new(
            TrunkCompensationConfig::default(),
            weakness,
            GyroSpec::ideal(),
            None,
            UnitQuaternion::identity(),
            3,
        )
        .unwrap();
        (0..4000)
            .map(|k| {
                let t = k as f64 * 0.005;
                let (w, wd) = crate::sim::arm::sine_road(t, 0.8, 0.2, 0.25, 0.45);
                let a = trunk.step((t * 1e9) as u64, w, wd, 0.005).unwrap().angles;
                a.rotation_deg
                    .abs()
                    .max(a.lean_deg.abs())
                    .max(a.flexion_deg.abs())
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_weaker_arm_moves_the_trunk_further() {
        let (strong, mid, weak) = (
            peak_excursion_deg(0.0),
            peak_excursion_deg(0.4),
            peak_excursion_deg(0.8),
        );
        assert!(strong < 2.0, "sway only: {strong}°");
        assert!(
            mid > 3.0 * strong && weak > 1.8 * mid,
            "{strong} {mid} {weak}"
        );
    }

    #[test]
    fn the_sternum_reads_gravity_and_no_rate_when_the_wheel_and_sway_are_still() {
        let cfg = TrunkCompensationConfig {
            sway_amp_rad: 0.0,
            ..TrunkCompensationConfig::default()
        };
        let mount = so3::exp_quat(&Vector3::new(0.3, -1.2, 0.4));
        let mut trunk = SimTrunk::new(
            cfg,
            0.5,
            GyroSpec::ideal(),
            Some(AccSpec {
                resolution_m_s2: 0.0,
                bias_std_m_s2: 0.0,
                noise_density_m_s2_sqrt_hz: 0.0,
                saturation_m_s2: 100.0,
            }),
            mount,
            4,
        )
        .unwrap();
        let truth = trunk.step(0, 0.4, 0.0, 0.001).unwrap();
        let s = trunk.latest().unwrap();
        let g = truth.sensor.inverse() * Vector3::z() * crate::sim::motion::GRAVITY_M_S2;
        assert!((s.acc_m_s2.unwrap() - g).norm() < 1e-6);
        assert!(s.rate_rad_s.norm() < 1e-9);
        assert!(trunk.step(0, f64::NAN, 0.0, 0.001).is_err());
        assert!(
            SimTrunk::consumer_mems(cfg, 1.5, mount, 1)
                .unwrap_err()
                .to_string()
                .contains("weakness")
        );
    }
}
